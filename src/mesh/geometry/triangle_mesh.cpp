// sdftrace — a triangle mesh's edges (see triangle_mesh.h).
#include "geometry/triangle_mesh.h"

#include <algorithm>

namespace meshsdf
{

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
