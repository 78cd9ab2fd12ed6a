// mesh2sdf — reading a mesh through OpenMesh into a triangle soup, and the
// health check printed before converting.
#ifndef MESH2SDF_MESH_H
#define MESH2SDF_MESH_H

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace mesh2sdf
{

struct MeshHealth {
    size_t vertices = 0;
    size_t faces = 0;            // polygons as read
    size_t triangles = 0;        // after triangulation, degenerate ones dropped
    size_t boundaryEdges = 0;    // edges used by one triangle
    size_t nonManifoldEdges = 0; // edges used by three or more triangles
    size_t degenerateFaces = 0;  // zero-area triangles (skipped)
    bool closed() const { return boundaryEdges == 0 && nonManifoldEdges == 0; }
};

struct TriangleMesh {
    std::vector<std::array<float, 3>> points;
    std::vector<std::array<uint32_t, 3>> triangles;
    std::array<double, 3> lo{}, hi{}; // bounding box of the used points
    MeshHealth health;
    /// Per point, the first point at the same position (-0 and +0 alike):
    /// vertices welded by exact position, so that a seam of duplicated
    /// vertices joins its triangles (the health counts, the open edges).
    std::vector<uint32_t> welded;
};

/// Reads `path` (.obj .ply .off .stl .om) through OpenMesh, triangulates its
/// polygons (fans), drops zero-area triangles and computes the health counts
/// (edges are matched on vertices welded by exact position, so a seam of
/// duplicated vertices counts as closed). Returns false and sets `error` to
/// one line on a missing or unreadable file, an unknown extension, no faces,
/// non-finite coordinates or a zero-size bounding box.
bool loadMesh(const std::string &path, TriangleMesh &mesh, std::string &error);

/// True if `path` ends in an extension loadMesh reads (case-insensitive).
bool isMeshExtension(const std::string &path);

} // namespace mesh2sdf

#endif
