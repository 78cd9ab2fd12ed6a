// sdftrace — a triangle mesh's box, welding and edges (see triangle_mesh.h).
#include "geometry/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

namespace meshsdf
{

void computeBox(TriangleMesh &mesh)
{
    mesh.lo = {INFINITY, INFINITY, INFINITY};
    mesh.hi = {-INFINITY, -INFINITY, -INFINITY};
    for (const auto &t : mesh.triangles)
        for (uint32_t v : t)
            for (int k = 0; k < 3; ++k) {
                mesh.lo[k] = std::min(mesh.lo[k], double(mesh.points[v][k]));
                mesh.hi[k] = std::max(mesh.hi[k], double(mesh.points[v][k]));
            }
}

namespace
{

// TriangleMesh::welded for `points`: per point, the first point at the same
// position (-0 and +0 alike).
std::vector<uint32_t> weldByPosition(const std::vector<std::array<float, 3>> &points)
{
    struct Key {
        float x, y, z;
        bool operator==(const Key &o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct KeyHash {
        size_t operator()(const Key &k) const
        {
            uint32_t b[3];
            std::memcpy(b, &k, sizeof b);
            return (size_t(b[0]) * 73856093u) ^ (size_t(b[1]) * 19349663u) ^ (size_t(b[2]) * 83492791u);
        }
    };
    std::unordered_map<Key, uint32_t, KeyHash> first;
    first.reserve(points.size());
    std::vector<uint32_t> welded(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const auto &p = points[i];
        // + 0.0f makes -0 +0, so that equal keys hash alike.
        welded[i] = first.emplace(Key{p[0] + 0.0f, p[1] + 0.0f, p[2] + 0.0f}, uint32_t(i)).first->second;
    }
    return welded;
}

} // namespace

bool finishTriangles(TriangleMesh &mesh)
{
    computeBox(mesh);
    const double extent = std::max({mesh.hi[0] - mesh.lo[0], mesh.hi[1] - mesh.lo[1], mesh.hi[2] - mesh.lo[2]});
    if (!(extent > 0.0))
        return false;
    mesh.welded = weldByPosition(mesh.points);
    std::vector<char> used(mesh.points.size(), 0);
    for (const auto &t : mesh.triangles)
        for (uint32_t v : t)
            used[v] = 1;
    for (size_t v = 0; v < mesh.points.size(); ++v)
        mesh.health.weldedVertices += used[v] && mesh.welded[v] != v;
    return true;
}

std::vector<EdgeUse> edgeUses(const TriangleMesh &mesh)
{
    const size_t n = mesh.triangles.size() * 3;
    // Counting sort on the smaller endpoint.
    std::vector<uint32_t> start(mesh.points.size() + 1, 0);
    for (uint32_t h = 0; h < n; ++h)
        ++start[std::min(edgeFrom(mesh, h), edgeTo(mesh, h)) + 1];
    for (size_t v = 1; v < start.size(); ++v)
        start[v] += start[v - 1];
    std::vector<EdgeUse> edges(n);
    for (uint32_t h = 0; h < n; ++h) {
        const uint32_t a = edgeFrom(mesh, h), b = edgeTo(mesh, h);
        edges[start[std::min(a, b)]++] = {(uint64_t(std::min(a, b)) << 32) | std::max(a, b), h};
    }
    // Each bucket by key, insertion sort (a vertex has few edges; equal keys
    // keep their half-edge order).
    for (size_t v = 0, begin = 0; v + 1 < start.size(); begin = start[v++])
        for (size_t i = begin + 1; i < start[v]; ++i)
            for (size_t j = i; j > begin && edges[j].key < edges[j - 1].key; --j)
                std::swap(edges[j], edges[j - 1]);
    return edges;
}

void countEdges(TriangleMesh &mesh, const std::vector<EdgeUse> &edges)
{
    mesh.health.boundaryEdges = mesh.health.nonManifoldEdges = 0;
    for (size_t i = 0, j; i < edges.size(); i = j) {
        for (j = i + 1; j < edges.size() && edges[j].key == edges[i].key;)
            ++j;
        mesh.health.boundaryEdges += j - i == 1;
        mesh.health.nonManifoldEdges += j - i > 2;
    }
}

} // namespace meshsdf
