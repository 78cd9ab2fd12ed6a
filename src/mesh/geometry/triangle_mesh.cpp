// sdftrace — a triangle mesh's box, welding and edges (see triangle_mesh.h).
#include "geometry/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

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
// position (-0 and +0 alike). The points sorted by position, then by
// index, in parallel: each run of one position starts with its first
// point. Coordinates are finite here, and finite floats are equal exactly
// when their bits are, once + 0.0f has made -0 +0.
std::vector<uint32_t> weldByPosition(const std::vector<std::array<float, 3>> &points)
{
    struct Keyed {
        uint64_t xy;
        uint32_t z, index;
        bool samePlace(const Keyed &o) const { return xy == o.xy && z == o.z; }
        bool operator<(const Keyed &o) const { return xy != o.xy ? xy < o.xy : z != o.z ? z < o.z : index < o.index; }
    };
    const size_t n = points.size();
    std::vector<Keyed> keyed(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
            uint32_t b[3];
            for (int k = 0; k < 3; ++k) {
                const float c = points[i][k] + 0.0f;
                std::memcpy(&b[k], &c, sizeof c);
            }
            keyed[i] = {uint64_t(b[0]) << 32 | b[1], b[2], uint32_t(i)};
        }
    });
    tbb::parallel_sort(keyed.begin(), keyed.end()); // keys distinct: one order for any thread count
    std::vector<uint32_t> welded(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t> &r) {
        size_t first = r.begin(); // the start of the run r begins in
        while (first > 0 && keyed[first - 1].samePlace(keyed[r.begin()]))
            --first;
        for (size_t k = r.begin(); k != r.end(); ++k) {
            if (!keyed[k].samePlace(keyed[first]))
                first = k;
            welded[keyed[k].index] = keyed[first].index;
        }
    });
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
