// sdftrace — OpenVDB's own mesh-to-volume band and flood-fill sign
// (--sign flood), for comparison with the exact band and winding sign.
// A file of its own: OpenVDB's MeshToVolume is most of the mesh
// component's compile time, and apart it builds beside the rest.
#ifndef SDFT_MESH_GRID_FLOOD_GRID_H
#define SDFT_MESH_GRID_FLOOD_GRID_H

#include "geometry/triangle_mesh.h"
#include "grid/build.h"
#include "progress/progress.h"

#include <openvdb/openvdb.h>

namespace meshsdf
{

/// OpenVDB's level set of `mesh` in `box`'s index space (openvdb::tools::
/// meshToVolume), `band` voxels each side, with `xform`; `progress` may
/// stop it.
openvdb::FloatGrid::Ptr floodGrid(const TriangleMesh &mesh, const BoxGeometry &box,
                                  const openvdb::math::Transform &xform, float band, Progress &progress);

} // namespace meshsdf

#endif
