// sdftrace — the exact narrow band of a triangle mesh: every voxel whose
// centre lies nearer than the half-width to some triangle, with its exact
// distance, block by block (OpenVDB's 8^3 leaves). No OpenVDB here: the
// caller turns blocks into leaves.
#ifndef SDFT_MESH_DISTANCE_BAND_H
#define SDFT_MESH_DISTANCE_BAND_H

#include "geometry/triangle_mesh.h"

#include <array>
#include <functional>

namespace meshsdf
{

constexpr int kBlockLog2 = 3; // OpenVDB's FloatTree leaf: 8^3 voxels
constexpr int kBlockDim = 1 << kBlockLog2;
constexpr int kBlockSize = kBlockDim * kBlockDim * kBlockDim;

/// Receives one block: `origin` is its first voxel's index (a multiple of
/// 8), `distance[(x * 8 + y) * 8 + z]` (OpenVDB's leaf order) the exact
/// unsigned distance in world units of voxel origin + (x, y, z), or +inf
/// where that is not below the half-width; the sink may change it (it is
/// scratch). Called concurrently from worker threads, once per block that
/// has a voxel in the band.
using BandBlockSink = std::function<void(const std::array<int, 3> &origin, float *distance)>;

/// The band of `mesh` on the voxel grid whose voxel (i, j, k) has its centre
/// at origin + (i, j, k) * voxelSize; `halfWidth` in voxels. `progress` (may
/// be empty) receives 0..100 as blocks complete. `simd`: with AVX2 where
/// the processor has it (false: without; the same band to rounding).
void exactBand(const TriangleMesh &mesh, const std::array<double, 3> &origin, double voxelSize, double halfWidth,
               const BandBlockSink &sink, const std::function<void(int)> &progress, bool simd = true);

} // namespace meshsdf

#endif
