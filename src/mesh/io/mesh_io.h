// sdftrace — reading a mesh file into a TriangleMesh: the one entry point
// that dispatches on the extension to the readers of this folder (OpenMesh's
// for OBJ, OFF, STL and OM, ours for PLY, assimp's for the interchange
// formats), and the checks every reader's polygons then go through.
#ifndef SDFT_MESH_IO_MESH_IO_H
#define SDFT_MESH_IO_MESH_IO_H

#include "geometry/triangle_mesh.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace meshsdf
{

/// Reads `path`: .obj .off .stl .om through OpenMesh's readers, .ply
/// through ply_read.h (faces and tristrips), .gltf .glb .fbx .dae .3mf
/// through assimp (assimp_read.h: a scene flattened in world space),
/// keeping every face the file has on the file's vertices, whatever their
/// orientation; triangulates its polygons (fans), drops zero-area triangles,
/// welds the vertices by position and computes the health counts but the
/// edges' (countEdges, or orientMesh, gives those). Faces the reader could
/// not take (a corner out of range, fewer than three corners, a corner
/// repeated) are left out and counted (health.skippedFaces); what was taken
/// with a doubt (those faces, a PLY header's free text) is said in
/// `warnings`, one line each, when given. Returns false and sets `error` to
/// one line on a missing or unreadable file, a folder, an unknown
/// extension, no faces, a coordinate that is not finite or of absurd size
/// (beyond kAbsurdCoordinate, or subnormal: what a reader that read past
/// its data makes of other bytes), or a zero-size bounding box.
bool loadMesh(const std::string &path, TriangleMesh &mesh, std::string &error,
              std::vector<std::string> *warnings = nullptr);

/// Coordinates beyond this magnitude are refused as garbage: 1e15 of any
/// unit is no model's.
constexpr double kAbsurdCoordinate = 1e15;

/// True if `path` ends in an extension loadMesh reads (case-insensitive).
bool isMeshExtension(const std::string &path);

/// True if the n corners are a polygon: three or more, all distinct (what
/// OpenMesh's importer takes; every reader is held to it).
bool isPolygon(const uint32_t *corners, size_t n);

} // namespace meshsdf

#endif
