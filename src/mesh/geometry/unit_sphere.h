// sdftrace — the sphere around a mesh that training samples are measured
// by and --normalize maps onto the unit sphere, as DeepSDF's preprocessing
// does: centred on the bounding box's centre, its radius 1.03 times the
// largest distance from that centre to a vertex of a face.
#ifndef SDFT_MESH_GEOMETRY_UNIT_SPHERE_H
#define SDFT_MESH_GEOMETRY_UNIT_SPHERE_H

#include "geometry/triangle_mesh.h"

#include <array>

namespace meshsdf
{

/// A point x of the mesh's frame is (x - centre) / radius in the unit frame.
struct MeshSphere {
    std::array<double, 3> centre{};
    double radius = 1;
};

/// The sphere of `mesh` (its lo, hi and the vertices its triangles use).
MeshSphere meshSphere(const TriangleMesh &mesh);

/// Maps the mesh into the unit frame of `sphere` (points, lo, hi).
void normalizeMesh(TriangleMesh &mesh, const MeshSphere &sphere);

} // namespace meshsdf

#endif
