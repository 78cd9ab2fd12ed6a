// sdftrace — building the distance grid: the exact narrow band (band.h)
// signed by the winding number, or left unsigned; or, for --sign flood,
// OpenVDB's own mesh-to-volume band and flood-fill sign, for comparison.
// For --full, exact distances in the rest of the padded box.
#ifndef SDFT_MESH_GRID_BUILD_H
#define SDFT_MESH_GRID_BUILD_H

#include "geometry/triangle_mesh.h"
#include "progress/progress.h"
#include "sdftrace/mesh.h"
#include "sign/winding.h"

#include <openvdb/openvdb.h>

#include <array>
#include <string>

namespace meshsdf
{

/// Largest grid side in voxels (res, or the side a voxel size implies).
constexpr int kMaxResolution = SDFT_MESH_MAX_RES;
/// Largest dense output (full, .npy) in voxels.
constexpr double kMaxDenseVoxels = SDFT_MESH_MAX_DENSE_VOXELS;

/// The vector instructions a mesh's work may use.
struct Simd {
    bool vector = true; // AVX2 where the processor has it
    bool wide = true;   // and AVX-512
};

/// The padding of `p` in voxels: its setting, or for the default band + 1.
double gridPadding(const sdft_mesh_grid_params &p);

/// The padded box: voxel (i, j, k), 0 <= i < dims[0] ..., has its centre at
/// world position origin + (i, j, k) * voxelSize. Index space of the grid is
/// the same (i, j, k).
struct BoxGeometry {
    double voxelSize = 0;
    std::array<double, 3> origin{};
    std::array<int, 3> dims{};
    double voxelCount() const { return double(dims[0]) * dims[1] * dims[2]; }
};

/// Voxel size and box from p's res or voxel_size and its padding: res N
/// puts N voxel centres along the padded box's longest side. Fails with one line
/// when a side would exceed kMaxResolution or be too small for the padding,
/// or a dense output would exceed kMaxDenseVoxels. (Whether the conversion
/// fits memory is memory_estimate.h's question.)
bool planBox(const TriangleMesh &mesh, const sdft_mesh_grid_params &p, BoxGeometry &box, std::string &error);

struct BuildStats {
    double windingSeconds = 0;    // exact band distances and winding sign (SDFT_MESH_SIGN_WINDING only)
    double indexSeconds = 0;      // the hierarchies built before the first distance
    uint64_t ambiguousVoxels = 0; // active voxels signed from a winding number in (0.25, 0.75)
};

/// Where on the progress bar building ends and writing begins, in percent.
int buildGridEnd(const sdft_mesh_grid_params &p);

/// The signed (or, with SDFT_MESH_SIGN_NONE, unsigned) distance grid in world
/// units: a GRID_LEVEL_SET with background band * voxelSize and the box's
/// transform. Its stages fill `progress` from 0 to buildGridEnd(p) %.
/// `accuracy`: the winding sign's (WindingSign).
openvdb::FloatGrid::Ptr buildGrid(const TriangleMesh &mesh, const BoxGeometry &box, const sdft_mesh_grid_params &p,
                                  Simd simd, WindingAccuracy accuracy, Progress &progress, BuildStats &stats);

} // namespace meshsdf

#endif
