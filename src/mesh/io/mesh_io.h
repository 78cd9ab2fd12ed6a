// sdftrace — reading a mesh file into a TriangleMesh: the one entry point
// that dispatches on the extension to the readers of this folder (OpenMesh's
// for OBJ, OFF, STL and OM, ours for PLY, assimp's for the interchange
// formats), and the checks every reader's polygons then go through.
#ifndef SDFT_MESH_IO_MESH_IO_H
#define SDFT_MESH_IO_MESH_IO_H

#include "geometry/triangle_mesh.h"

#include <string>

namespace meshsdf
{

/// Reads `path`: .obj .off .stl .om through OpenMesh's readers, .ply
/// through ply_read.h (faces and tristrips), .gltf .glb .fbx .dae .3mf
/// through assimp (assimp_read.h: a scene flattened in world space),
/// keeping every face the file has on the file's vertices, whatever their
/// orientation; triangulates its polygons (fans), drops zero-area triangles,
/// welds the vertices by position and computes the health counts but the
/// edges' (countEdges, or orientMesh, gives those). Returns false and sets `error` to one line on a missing or
/// unreadable file, an unknown extension, no faces, non-finite coordinates
/// or a zero-size bounding box.
bool loadMesh(const std::string &path, TriangleMesh &mesh, std::string &error);

/// True if `path` ends in an extension loadMesh reads (case-insensitive).
bool isMeshExtension(const std::string &path);

} // namespace meshsdf

#endif
