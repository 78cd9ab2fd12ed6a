// sdftrace tests — what the mesh component's module tests (tests/mesh/,
// C++ over src/mesh's internal headers) share: small meshes built by hand,
// the same mesh as tests/support/mesh_support.h's brute-force truth
// (exact distances and winding numbers over every triangle), and a path
// in the tests' temporary folder.
#ifndef SDFT_TEST_MESH_UNIT_H
#define SDFT_TEST_MESH_UNIT_H

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/triangle_mesh.h"

// cmocka last: its skip() and fail() macros would rename members of the
// C++ headers above.
extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "mesh_support.h"
#include "testutil.h"
}

namespace unit
{

// A mesh of the given points and triangles, finished as an intake
// finishes one (box, welding), its health counts set from them.
inline meshsdf::TriangleMesh makeMesh(const std::vector<std::array<float, 3>> &points,
                                      const std::vector<std::array<uint32_t, 3>> &triangles)
{
    meshsdf::TriangleMesh m;
    m.points = points;
    m.triangles = triangles;
    m.health.vertices = points.size();
    m.health.faces = m.health.triangles = triangles.size();
    assert_true(meshsdf::finishTriangles(m));
    return m;
}

// The unit cube [0, 1]^3, its 12 triangles facing outward.
inline meshsdf::TriangleMesh cube()
{
    return makeMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
                    {{0, 2, 1},
                     {0, 3, 2},
                     {4, 5, 6},
                     {4, 6, 7},
                     {0, 1, 5},
                     {0, 5, 4},
                     {2, 3, 7},
                     {2, 7, 6},
                     {1, 2, 6},
                     {1, 6, 5},
                     {0, 4, 7},
                     {0, 7, 3}});
}

// A sphere of radius r about c, `rings` rings of 2 * rings triangles
// around (closed, facing outward); with `hole`, the cap at the top left
// open (an open mesh).
inline meshsdf::TriangleMesh sphere(const std::array<double, 3> &c, double r, int rings, bool hole = false)
{
    const double pi = 3.14159265358979323846;
    std::vector<std::array<float, 3>> points = {{float(c[0]), float(c[1]), float(c[2] + r)}};
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < 2 * rings; ++j) {
            const double th = pi * i / rings, ph = pi * j / rings;
            points.push_back({float(c[0] + r * std::sin(th) * std::cos(ph)),
                              float(c[1] + r * std::sin(th) * std::sin(ph)), float(c[2] + r * std::cos(th))});
        }
    points.push_back({float(c[0]), float(c[1]), float(c[2] - r)});
    const uint32_t n = uint32_t(2 * rings), bottom = uint32_t(points.size() - 1);
    auto at = [&](int i, int j) { return uint32_t(1 + (i - 1) * n + uint32_t(j) % n); };
    std::vector<std::array<uint32_t, 3>> tris;
    for (int j = 0; j < int(n) && !hole; ++j)
        tris.push_back({0, at(1, j), at(1, j + 1)});
    for (int i = 1; i + 1 < rings; ++i)
        for (int j = 0; j < int(n); ++j) {
            tris.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            tris.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    for (int j = 0; j < int(n); ++j)
        tris.push_back({bottom, at(rings - 1, j + 1), at(rings - 1, j)});
    return makeMesh(points, tris);
}

// The same mesh as the brute-force truth's arrays (mesh_support.h); free
// it with mesh_free.
inline mesh truth(const meshsdf::TriangleMesh &m)
{
    mesh b = {};
    for (const auto &p : m.points)
        mesh_vertex(&b, p[0], p[1], p[2]);
    for (const auto &t : m.triangles)
        mesh_triangle(&b, int(t[0]), int(t[1]), int(t[2]));
    return b;
}

// A file in the tests' temporary folder.
inline std::string tmp(const char *name) { return std::string(SDFT_TEST_TMP) + "/" + name; }

} // namespace unit

#endif
