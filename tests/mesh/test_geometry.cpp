// src/mesh/geometry: the triangle mesh's box, welding, health and edges;
// the mesh's sphere and normalizing; the point-triangle distance; the
// median split. Truth from the construction and from mesh_support.h's
// independent point-triangle distance.
#include "geometry/median_split.h"
#include "geometry/triangle_distance.h"
#include "geometry/unit_sphere.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

// Last: cmocka's macros would rename members of the headers above.
#include "mesh_unit.h"

namespace
{

using meshsdf::TriangleMesh;

// The box is the used points', welding joins equal positions (-0 and +0
// too) to the first of them, and a mesh of no extent is refused.
void box_and_welding(void **)
{
    TriangleMesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {-0.0f, 0, 0}, {1, 0, 0}, {9, 9, 9}};
    m.triangles = {{0, 1, 2}, {3, 4, 2}};
    assert_true(meshsdf::finishTriangles(m));
    assert_true(m.lo[0] == 0 && m.lo[1] == 0 && m.lo[2] == 0);
    assert_true(m.hi[0] == 1 && m.hi[1] == 2 && m.hi[2] == 0); // point 5 is not used
    const std::vector<uint32_t> welded = {0, 1, 2, 0, 1, 5};
    assert_true(m.welded == welded);
    assert_int_equal(m.health.weldedVertices, 2);

    TriangleMesh flat;
    flat.points = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
    flat.triangles = {{0, 1, 2}};
    assert_false(meshsdf::finishTriangles(flat));
}

// Welding many points, few of them distinct (long runs of one position,
// across the blocks the parallel weld is cut into, -0 beside +0), against
// a map of each position's first point.
void welding_many(void **)
{
    TriangleMesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}};
    std::mt19937 random(7);
    for (int i = 0; i < 50000; ++i) {
        std::array<float, 3> p;
        for (float &c : p) {
            const unsigned pick = random() % 6;
            c = pick == 0 ? -0.0f : float(pick - 1) * 0.25f;
        }
        m.points.push_back(p);
    }
    assert_true(meshsdf::finishTriangles(m));
    std::map<std::array<float, 3>, uint32_t> first; // -0 < +0 is false: one key for both
    for (uint32_t i = 0; i < m.points.size(); ++i) {
        const uint32_t expected = first.emplace(m.points[i], i).first->second;
        if (m.welded[i] != expected)
            fail_msg("point %u welded to %u, not %u", i, m.welded[i], expected);
    }
    assert_int_equal(first.size(), 5 * 5 * 5);
}

// Twice the squared area: a right triangle of legs 3 and 4 has area 6.
void areas(void **)
{
    assert_true(meshsdf::doubleArea2({0, 0, 0}, {3, 0, 0}, {0, 4, 0}) == 144.0);
    assert_true(meshsdf::doubleArea2({0, 0, 0}, {1, 1, 1}, {2, 2, 2}) == 0.0);
}

// Edges: the closed cube has none on its boundary; taking a triangle off
// opens three; a fin on an edge makes it non-manifold. Uses of one edge
// stand together, in triangle order.
void edges(void **)
{
    TriangleMesh m = unit::cube();
    std::vector<meshsdf::EdgeUse> uses = meshsdf::edgeUses(m);
    assert_int_equal(uses.size(), 36);
    meshsdf::countEdges(m, uses);
    assert_int_equal(m.health.boundaryEdges, 0);
    assert_int_equal(m.health.nonManifoldEdges, 0);
    assert_true(m.health.closed());
    for (size_t i = 1; i < uses.size(); ++i)
        assert_true(uses[i - 1].key < uses[i].key ||
                    (uses[i - 1].key == uses[i].key && uses[i - 1].halfEdge < uses[i].halfEdge));

    TriangleMesh open = unit::cube();
    open.triangles.pop_back();
    meshsdf::countEdges(open, meshsdf::edgeUses(open));
    assert_int_equal(open.health.boundaryEdges, 3);

    TriangleMesh fin = unit::cube();
    fin.points.push_back({0.5f, 0.5f, -1});
    fin.welded.push_back(uint32_t(fin.points.size() - 1));
    fin.triangles.push_back({0, 1, uint32_t(fin.points.size() - 1)}); // on the cube's edge 0-1
    meshsdf::countEdges(fin, meshsdf::edgeUses(fin));
    assert_int_equal(fin.health.nonManifoldEdges, 1);
    assert_int_equal(fin.health.boundaryEdges, 2);
}

// The sphere: the box's centre, 1.03 times the farthest used vertex;
// normalizing maps it onto the unit sphere.
void sphere(void **)
{
    TriangleMesh m = unit::cube();
    for (auto &p : m.points)
        p = {p[0] * 2 + 1, p[1] * 2 + 1, p[2] * 2 + 1}; // [1, 3]^3
    meshsdf::computeBox(m);
    const meshsdf::MeshSphere s = meshsdf::meshSphere(m);
    for (int k = 0; k < 3; ++k)
        assert_true(s.centre[k] == 2);
    assert_true(std::fabs(s.radius - 1.03 * std::sqrt(3.0)) < 1e-12);
    meshsdf::normalizeMesh(m, s);
    for (int k = 0; k < 3; ++k) {
        assert_true(std::fabs(m.lo[k] + 1 / 1.03 / std::sqrt(3.0)) < 1e-6);
        assert_true(std::fabs(m.hi[k] - 1 / 1.03 / std::sqrt(3.0)) < 1e-6);
    }
}

// Ericson's closest-point regions against mesh_support.h's plane-and-edges
// distance, at random points near random triangles (slivers included).
void triangle_distance(void **)
{
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int n = 0; n < 20000; ++n) {
        double t[9], p[3];
        for (double &x : t)
            x = u(random);
        if (n % 10 == 0) // a sliver: c on the line ab, a little off it
            for (int k = 0; k < 3; ++k)
                t[6 + k] = 0.3 * t[k] + 0.7 * t[3 + k] + 1e-4 * u(random);
        for (double &x : p)
            x = 2 * u(random);
        const double want = tri_dist2(p, t, t + 3, t + 6), got = meshsdf::triangleDistance2(t, p);
        assert_true(std::fabs(got - want) <= 1e-8 * (1 + want));
    }
}

// The median split: the first half's centroids lie no further along the
// longest axis than the second half's.
void median_split(void **)
{
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<std::array<double, 3>> c(101);
    for (auto &x : c)
        x = {10 * u(random), u(random), u(random)}; // x is the longest axis
    std::vector<uint32_t> order(c.size());
    for (uint32_t i = 0; i < order.size(); ++i)
        order[i] = i;
    const uint32_t half = meshsdf::splitAtMedian(order, 0, uint32_t(order.size()), c);
    assert_int_equal(half, 50);
    double left = -1, right = 1e9;
    for (uint32_t i = 0; i < half; ++i)
        left = std::max(left, c[order[i]][0]);
    for (uint32_t i = half; i < order.size(); ++i)
        right = std::min(right, c[order[i]][0]);
    assert_true(left <= right);
    std::sort(order.begin(), order.end());
    for (uint32_t i = 0; i < order.size(); ++i)
        assert_int_equal(order[i], i);
}

} // namespace

int main()
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(box_and_welding), cmocka_unit_test(welding_many), cmocka_unit_test(areas),
        cmocka_unit_test(edges),           cmocka_unit_test(sphere),       cmocka_unit_test(triangle_distance),
        cmocka_unit_test(median_split),
    };
    return cmocka_run_group_tests_name("mesh_geometry", tests, nullptr, nullptr);
}
