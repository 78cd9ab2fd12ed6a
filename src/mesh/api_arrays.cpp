// sdftrace — a mesh from vertex and face arrays (see api.h): the
// same triangles, counts and welding as mesh2sdf's reader makes of a file.
#include "api.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace meshsdf::api
{

namespace
{

using meshsdf::TriangleMesh;

// Twice the squared area of triangle t, in double: zero for a degenerate one.
double doubledArea2(const TriangleMesh &mesh, const std::array<uint32_t, 3> &t)
{
    double e[2][3];
    for (int k = 0; k < 3; ++k) {
        e[0][k] = double(mesh.points[t[1]][k]) - double(mesh.points[t[0]][k]);
        e[1][k] = double(mesh.points[t[2]][k]) - double(mesh.points[t[0]][k]);
    }
    const double c[3] = {e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                         e[0][0] * e[1][1] - e[0][1] * e[1][0]};
    return c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
}

// Per point, the first point at the same position (-0 and +0 alike): the
// points sorted by position, each run of equal ones mapped to its smallest
// index.
std::vector<uint32_t> weldSorted(const std::vector<std::array<float, 3>> &points)
{
    std::vector<uint32_t> order(points.size());
    std::iota(order.begin(), order.end(), 0u);
    auto key = [&](uint32_t i) {
        const auto &p = points[i];
        return std::array<float, 3>{p[0] + 0.0f, p[1] + 0.0f, p[2] + 0.0f};
    };
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    std::vector<uint32_t> welded(points.size());
    for (size_t i = 0; i < order.size(); ++i)
        welded[order[i]] = i > 0 && key(order[i]) == key(order[i - 1]) ? welded[order[i - 1]] : order[i];
    return welded;
}

int64_t indexAt(const void *faces, sdft_mesh_dtype type, size_t i)
{
    switch (type) {
    case SDFT_MESH_INT32:
        return static_cast<const int32_t *>(faces)[i];
    case SDFT_MESH_UINT32:
        return static_cast<const uint32_t *>(faces)[i];
    default:
        return static_cast<const int64_t *>(faces)[i];
    }
}

} // namespace

sdft_error meshFromArrays(const void *vertices, sdft_mesh_dtype vertexType, size_t vertexCount, const void *faces,
                          sdft_mesh_dtype faceType, size_t faceCount, TriangleMesh &mesh, std::string &error)
{
    if (enumValue(vertexType) != SDFT_MESH_FLOAT32 && enumValue(vertexType) != SDFT_MESH_FLOAT64) {
        error = "vertices must be float32 or float64";
        return SDFT_EINVAL;
    }
    if (enumValue(faceType) != SDFT_MESH_INT32 && enumValue(faceType) != SDFT_MESH_UINT32 &&
        enumValue(faceType) != SDFT_MESH_INT64) {
        error = "faces must be int32, uint32 or int64";
        return SDFT_EINVAL;
    }
    if (vertexCount == 0 || faceCount == 0) {
        error = vertexCount == 0 ? "no vertices" : "no faces";
        return SDFT_EINVAL;
    }
    if (vertexCount >= std::numeric_limits<uint32_t>::max()) {
        error = "more than 2^32 - 2 vertices";
        return SDFT_EINVAL;
    }
    mesh = TriangleMesh{};
    mesh.points.resize(vertexCount);
    for (size_t v = 0; v < vertexCount; ++v)
        for (int k = 0; k < 3; ++k) {
            const size_t at = v * 3 + size_t(k);
            const float x = vertexType == SDFT_MESH_FLOAT32 ? static_cast<const float *>(vertices)[at]
                                                            : float(static_cast<const double *>(vertices)[at]);
            if (!std::isfinite(x)) {
                error = "mesh has a non-finite coordinate (vertex " + std::to_string(v) + ")";
                return SDFT_EFORMAT;
            }
            mesh.points[v][k] = x;
        }
    mesh.health.vertices = vertexCount;
    mesh.health.faces = faceCount;
    mesh.triangles.reserve(faceCount);
    for (size_t f = 0; f < faceCount; ++f) {
        std::array<uint32_t, 3> t;
        for (int k = 0; k < 3; ++k) {
            const int64_t i = indexAt(faces, faceType, f * 3 + size_t(k));
            if (i < 0 || uint64_t(i) >= vertexCount) {
                error = "face " + std::to_string(f) + " has vertex index " + std::to_string(i) + ", outside [0, " +
                        std::to_string(vertexCount) + ")";
                return SDFT_EINVAL;
            }
            t[k] = uint32_t(i);
        }
        if (doubledArea2(mesh, t) <= 0.0)
            ++mesh.health.degenerateFaces;
        else
            mesh.triangles.push_back(t);
    }
    mesh.health.triangles = mesh.triangles.size();
    if (mesh.triangles.empty()) {
        error = "mesh has no non-degenerate triangles";
        return SDFT_EFORMAT;
    }
    mesh.lo = {INFINITY, INFINITY, INFINITY};
    mesh.hi = {-INFINITY, -INFINITY, -INFINITY};
    std::vector<char> used(vertexCount, 0);
    for (const auto &t : mesh.triangles)
        for (uint32_t v : t) {
            used[v] = 1;
            for (int k = 0; k < 3; ++k) {
                mesh.lo[k] = std::min(mesh.lo[k], double(mesh.points[v][k]));
                mesh.hi[k] = std::max(mesh.hi[k], double(mesh.points[v][k]));
            }
        }
    const double extent = std::max({mesh.hi[0] - mesh.lo[0], mesh.hi[1] - mesh.lo[1], mesh.hi[2] - mesh.lo[2]});
    if (!(extent > 0.0)) {
        error = "mesh bounding box has zero size";
        return SDFT_EFORMAT;
    }
    mesh.welded = weldSorted(mesh.points);
    for (size_t v = 0; v < vertexCount; ++v)
        mesh.health.weldedVertices += used[v] && mesh.welded[v] != v;
    return SDFT_OK;
}

} // namespace meshsdf::api
