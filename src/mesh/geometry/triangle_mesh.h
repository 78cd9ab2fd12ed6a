// sdftrace — the triangle mesh every algorithm of the mesh component works
// on: float vertices, triangles on them, the box, the welded numbering and
// the health counts; and its edges (which triangles share one). Nothing
// here reads a file: io/mesh_io.h makes meshes of files.
#ifndef SDFT_MESH_GEOMETRY_TRIANGLE_MESH_H
#define SDFT_MESH_GEOMETRY_TRIANGLE_MESH_H

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace meshsdf
{

struct MeshHealth {
    size_t vertices = 0;
    size_t faces = 0;            // polygons as read
    size_t triangles = 0;        // after triangulation, degenerate ones dropped
    size_t boundaryEdges = 0;    // edges used by one triangle
    size_t nonManifoldEdges = 0; // edges used by three or more triangles
    size_t degenerateFaces = 0;  // zero-area triangles (skipped)
    size_t skippedFaces = 0;     // faces of the file left out as malformed: a corner out of range, fewer
                                 // than three corners, a corner repeated
    size_t weldedVertices = 0;   // used vertices at the position of an earlier one
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

/// Twice the squared area of triangle (a, b, c), in double: zero for a
/// degenerate one, and its square root twice the area.
inline double doubleArea2(const std::array<float, 3> &a, const std::array<float, 3> &b, const std::array<float, 3> &c)
{
    const double e1[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
    const double e2[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    const double x = e1[1] * e2[2] - e1[2] * e2[1], y = e1[2] * e2[0] - e1[0] * e2[2],
                 z = e1[0] * e2[1] - e1[1] * e2[0];
    return x * x + y * y + z * z;
}

/// Sets mesh.lo and mesh.hi: the box of the points its triangles use.
void computeBox(TriangleMesh &mesh);

/// What every way of taking a mesh in does once its triangles are in
/// place: the box, the welded numbering (TriangleMesh::welded) and
/// health.weldedVertices. False, with nothing welded, when the box has
/// zero size.
bool finishTriangles(TriangleMesh &mesh);

/// One triangle edge: corner `halfEdge % 3` of triangle `halfEdge / 3` to
/// the next corner, keyed by its welded endpoints (smaller in the high
/// half).
struct EdgeUse {
    uint64_t key;
    uint32_t halfEdge;
};

/// Every triangle's three edges sorted by key (a counting sort on the
/// smaller endpoint), so that the triangles sharing an edge stand in one run;
/// within a run, in triangle order.
std::vector<EdgeUse> edgeUses(const TriangleMesh &mesh);

/// The welded vertex a half-edge starts from and the one it ends at.
inline uint32_t edgeFrom(const TriangleMesh &mesh, uint32_t halfEdge)
{
    return mesh.welded[mesh.triangles[halfEdge / 3][halfEdge % 3]];
}
inline uint32_t edgeTo(const TriangleMesh &mesh, uint32_t halfEdge)
{
    return mesh.welded[mesh.triangles[halfEdge / 3][(halfEdge % 3 + 1) % 3]];
}

/// Sets health.boundaryEdges and health.nonManifoldEdges from `edges`
/// (edgeUses(mesh)): runs of one use and of three or more. Edges are
/// matched on the welded vertices, so a seam of duplicated vertices counts
/// as closed.
void countEdges(TriangleMesh &mesh, const std::vector<EdgeUse> &edges);

} // namespace meshsdf

#endif
