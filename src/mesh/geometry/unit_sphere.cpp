// sdftrace — the mesh's sphere and --normalize (see unit_sphere.h).
#include "geometry/unit_sphere.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace meshsdf
{

namespace
{

// DeepSDF's margin (BoundingCubeNormalization's max_distance_buffer).
constexpr double kMargin = 1.03;

} // namespace

MeshSphere meshSphere(const TriangleMesh &mesh)
{
    MeshSphere s;
    for (int k = 0; k < 3; ++k)
        s.centre[k] = 0.5 * (mesh.lo[k] + mesh.hi[k]);
    std::vector<char> used(mesh.points.size(), 0);
    for (const auto &t : mesh.triangles)
        used[t[0]] = used[t[1]] = used[t[2]] = 1;
    double far2 = 0;
    for (size_t i = 0; i < mesh.points.size(); ++i) {
        if (!used[i])
            continue;
        double d2 = 0;
        for (int k = 0; k < 3; ++k) {
            const double d = mesh.points[i][k] - s.centre[k];
            d2 += d * d;
        }
        far2 = std::max(far2, d2);
    }
    s.radius = kMargin * std::sqrt(far2);
    return s;
}

void normalizeMesh(TriangleMesh &mesh, const MeshSphere &sphere)
{
    const double scale = 1 / sphere.radius;
    for (auto &p : mesh.points)
        for (int k = 0; k < 3; ++k)
            p[k] = float((p[k] - sphere.centre[k]) * scale);
    computeBox(mesh); // again, of the rounded points
}

} // namespace meshsdf
