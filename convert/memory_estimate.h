// mesh2sdf — the conversion's peak memory, estimated before the grid is
// built, so that a size that would not fit (--res, --voxel-size, --band,
// --full, --npy on a machine too small) is refused with the estimate
// instead of swapping or being killed halfway.
#ifndef MESH2SDF_MEMORY_ESTIMATE_H
#define MESH2SDF_MEMORY_ESTIMATE_H

#include "grid.h"
#include "mesh.h"
#include "options.h"

#include <string>

namespace mesh2sdf
{

/// Bytes the conversion of `mesh` into `box` with `opt` will need at its
/// peak (resident set), within about 25% (tests/test_untrusted.c).
double conversionPeakBytes(const TriangleMesh &mesh, const BoxGeometry &box, const Options &opt);

/// False with one line in error ("needs ~37.2 GiB for ...; this machine
/// allows 24.0 GiB") when conversionPeakBytes does not fit
/// (src/common/memory_limit.h).
bool conversionFitsMemory(const TriangleMesh &mesh, const BoxGeometry &box, const Options &opt, std::string &error);

/// The same for --check-sign's `points` (--check-points).
bool checkPointsFitMemory(int points, std::string &error);

/// The same for `count` training samples (--samples, samples.h).
bool trainingSamplesFitMemory(size_t count, std::string &error);

} // namespace mesh2sdf

#endif
