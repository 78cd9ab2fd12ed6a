// mesh2sdf — building the distance grid: the exact narrow band (band.h)
// signed by the winding number, or left unsigned; or, for --sign flood,
// OpenVDB's own mesh-to-volume band and flood-fill sign, for comparison.
// For --full, exact distances in the rest of the padded box.
#ifndef MESH2SDF_GRID_H
#define MESH2SDF_GRID_H

#include "mesh.h"
#include "options.h"
#include "progress.h"

#include <openvdb/openvdb.h>

#include <array>
#include <string>

namespace mesh2sdf
{

/// The padded box: voxel (i, j, k), 0 <= i < dims[0] ..., has its centre at
/// world position origin + (i, j, k) * voxelSize. Index space of the grid is
/// the same (i, j, k).
struct BoxGeometry {
    double voxelSize = 0;
    std::array<double, 3> origin{};
    std::array<int, 3> dims{};
    double voxelCount() const { return double(dims[0]) * dims[1] * dims[2]; }
};

/// Voxel size and box from --res or --voxel-size and --padding. --res N puts
/// N voxel centres along the padded box's longest side. Fails with one line
/// when a side would exceed kMaxResolution or be too small for the padding.
bool planBox(const TriangleMesh &mesh, const Options &opt, BoxGeometry &box, std::string &error);

struct BuildStats {
    double windingSeconds = 0;    // exact band distances and winding sign (not flood)
    uint64_t ambiguousVoxels = 0; // voxels signed from a winding number in (0.25, 0.75)
};

/// The signed (or, with SignMethod::None, unsigned) distance grid in world
/// units: a GRID_LEVEL_SET with background band * voxelSize and the box's
/// transform. Its stages fill `progress` from 0 to buildGridEnd(opt) %.
/// Where on the progress bar building ends and writing begins, in percent.
int buildGridEnd(const Options &opt);

openvdb::FloatGrid::Ptr buildGrid(const TriangleMesh &mesh, const BoxGeometry &box, const Options &opt,
                                  Progress &progress, BuildStats &stats);

} // namespace mesh2sdf

#endif
