// sdftrace — a mesh from vertex and face arrays (see api.h): the
// same triangles, counts and welding as mesh2sdf's reader makes of a file.
#include "api.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace meshsdf::api
{

namespace
{

using meshsdf::TriangleMesh;

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
        if (meshsdf::doubleArea2(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]) <= 0.0)
            ++mesh.health.degenerateFaces;
        else
            mesh.triangles.push_back(t);
    }
    mesh.health.triangles = mesh.triangles.size();
    if (mesh.triangles.empty()) {
        error = "mesh has no non-degenerate triangles";
        return SDFT_EFORMAT;
    }
    if (!meshsdf::finishTriangles(mesh)) {
        error = "mesh bounding box has zero size";
        return SDFT_EFORMAT;
    }
    return SDFT_OK;
}

} // namespace meshsdf::api
