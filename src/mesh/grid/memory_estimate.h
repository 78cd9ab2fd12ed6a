// sdftrace — the conversion's peak memory, estimated before the grid is
// built, so that a size that would not fit (a resolution, voxel size, band,
// dense output on a machine too small) is refused with the estimate
// instead of swapping or being killed halfway.
#ifndef SDFT_MESH_GRID_MEMORY_ESTIMATE_H
#define SDFT_MESH_GRID_MEMORY_ESTIMATE_H

#include "geometry/triangle_mesh.h"
#include "grid/build.h"

#include <string>

namespace meshsdf
{

/// Bytes the conversion of `mesh` into `box` with `p` will need at its
/// peak (resident set), within about 25% (tests/test_untrusted.c).
double conversionPeakBytes(const TriangleMesh &mesh, const BoxGeometry &box, const sdft_mesh_grid_params &p);

/// False with one line in error ("needs ~37.2 GiB for ...; this machine
/// allows 24.0 GiB") when conversionPeakBytes does not fit
/// (src/common/memory_limit.h).
bool conversionFitsMemory(const TriangleMesh &mesh, const BoxGeometry &box, const sdft_mesh_grid_params &p,
                          std::string &error);

} // namespace meshsdf

#endif
