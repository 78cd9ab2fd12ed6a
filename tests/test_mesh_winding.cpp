// The winding tree (src/mesh/sign/winding.h) held to brute force: the
// winding number summed over every triangle in double precision with
// libm's atan2 (the tree's exact solid angles use a faster arctangent), on
// open meshes (a cut sphere, a scan-like patch, the shared meshes with
// faces removed) and closed ones, at points near the surface on both sides,
// just inside an open scan, and far away. The fast evaluation within 5e-3,
// the exact one within 1e-5 and within its own proven bound, and the side
// of 1/2 that both give; the tree the same for any thread count.
#include "io/mesh_io.h"
#include "mesh_shapes.h"
#include "sign/winding.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

using namespace meshsdf;
using shapes::Soup;

namespace
{

constexpr double kPi = 3.14159265358979323846;

Soup fromMesh(const char *name)
{
    TriangleMesh mesh;
    std::string error;
    const std::string path = std::string(SDFT_MESH_DIR) + "/" + name;
    if (!loadMesh(path, mesh, error))
        fail_msg("%s: %s", path.c_str(), error.c_str());
    Soup s;
    s.points = mesh.points;
    s.triangles = mesh.triangles;
    return s;
}

struct Errors {
    double fast = 0, exact = 0, exactOverBound = 0;
    int sideWrong = 0, exactSideWrong = 0, clear = 0;
};

// The tree's answers at `points` against brute force.
Errors measure(const char *name, const Soup &s, const std::vector<Vec3> &points)
{
    const FastWinding tree(s.points, s.triangles);
    const shapes::Brute brute(s);
    Errors e;
    for (const Vec3 &q : points) {
        const double truth = brute.winding(q.data());
        const double w = tree(q);
        const WindingValue x = tree.exact(q);
        e.fast = std::max(e.fast, std::abs(w - truth));
        e.exact = std::max(e.exact, std::abs(x.w - truth));
        e.exactOverBound = std::max(e.exactOverBound, std::abs(x.w - truth) / (x.bound * (1 + 1e-9) + 1e-15));
        // The side of 1/2: the fast one wherever it is clear of the fast
        // error, the exact one wherever rounding cannot decide it.
        if (std::abs(truth - 0.5) > 5e-3) {
            ++e.clear;
            e.sideWrong += (tree.side(q).w > 0.5) != (truth > 0.5);
        }
        // The exact side's margin is proven too.
        const WindingValue side = tree.side(q, WindingAccuracy::Exact);
        e.exactOverBound = std::max(e.exactOverBound, std::abs(side.w - truth) / (side.bound * (1 + 1e-9) + 1e-15));
        if (std::abs(truth - 0.5) > 1e-6)
            e.exactSideWrong += (side.w > 0.5) != (truth > 0.5);
    }
    print_message("%-24s %4zu points: fast error %.2g, exact %.2g (%.2g of its bound), sides wrong %d + %d of %d\n",
                  name, points.size(), e.fast, e.exact, e.exactOverBound, e.sideWrong, e.exactSideWrong, e.clear);
    return e;
}

void expectWithin(const Errors &e)
{
    assert_true(e.fast <= 5e-3);
    assert_true(e.exact <= 1e-5);
    assert_true(e.exactOverBound <= 1);
    assert_int_equal(e.sideWrong, 0);
    assert_int_equal(e.exactSideWrong, 0);
}

void checkShape(const char *name, const Soup &s, int near, int far)
{
    const std::string n = name;
    expectWithin(measure((n + " near").c_str(), s, shapes::nearPoints(s, near, 1)));
    expectWithin(measure((n + " far").c_str(), s, shapes::farPoints(s, far, 2)));
}

void test_open_generated(void **)
{
    checkShape("cut sphere", shapes::cutSphere(), 400, 200);
    checkShape("scan patch", shapes::scanPatch(), 400, 200);
    checkShape("rough scan", shapes::sphere(0, 0, 0, 1, 80, 160, 110 * kPi / 180, 0.08, 3), 300, 100);
    checkShape("holed sphere", shapes::withoutFaces(shapes::sphere(0, 0, 0, 1, 40, 80), 7), 300, 100);
}

// Points just inside an open scan, where the winding number is between 1/2
// and 1 and a poor far field flips signs: under the patch's middle, at up
// to a tenth of its radius from it.
void test_inside_open_scan(void **)
{
    const Soup s = shapes::scanPatch();
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Vec3> points;
    for (int i = 0; i < 400; ++i) {
        const double theta = 1.5 * u(rng), phi = 2 * kPi * u(rng), r = 1 - 0.1 * std::pow(u(rng), 3);
        points.push_back(
            {r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi), r * std::cos(theta)});
    }
    expectWithin(measure("inside scan patch", s, points));
}

// The centre of an open hemisphere sees exactly half of every direction's
// sphere: w = 1/2 there, and near it the side is a matter of the last
// digits. The exact side must match brute force at every point it can tell.
void test_side_near_half(void **)
{
    const Soup s = shapes::sphere(0, 0, 0, 1, 40, 80, kPi / 2);
    const FastWinding tree(s.points, s.triangles);
    const shapes::Brute brute(s);
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(-1, 1);
    int decided = 0, wrong = 0;
    double worst = 0;
    for (int i = 0; i < 300; ++i) {
        const double scale = std::pow(10.0, -6 + 5 * (u(rng) + 1) / 2);
        const Vec3 q{scale * u(rng), scale * u(rng), scale * u(rng)};
        const double truth = brute.winding(q.data());
        const WindingValue side = tree.side(q, WindingAccuracy::Exact);
        worst = std::max(worst, std::abs(side.w - truth) / (side.bound * (1 + 1e-9) + 1e-15));
        if (std::abs(truth - 0.5) > 1e-6) { // beyond the rounding the bound allows
            ++decided;
            wrong += (side.w > 0.5) != (truth > 0.5);
        }
    }
    print_message("hemisphere centre: %d points decided, %d wrong, error / bound %.2g\n", decided, wrong, worst);
    assert_true(decided > 200);
    assert_int_equal(wrong, 0);
    assert_true(worst <= 1);
}

void test_shared_meshes_with_holes(void **)
{
    const char *names[] = {"spot.obj", "fandisk.obj", "suzanne.obj", "teapot.obj"};
    for (const char *name : names) {
        const Soup s = fromMesh(name);
        checkShape(name, s, 200, 100);
        checkShape((std::string(name) + " holed").c_str(), shapes::withoutFaces(s, 11), 200, 100);
    }
    // The largest, fewer points: brute force is 69k triangles a point.
    const Soup bunny = fromMesh("stanford-bunny.obj");
    checkShape("bunny", bunny, 150, 50);
    checkShape("bunny holed", shapes::withoutFaces(bunny, 9), 150, 50);
}

// Closed parts together: nested shells (the winding number counts them),
// touching cubes, a gear train. The centre of concentric spheres sees
// every expansion's error with one sign.
void test_assemblies(void **)
{
    checkShape("nested shells", shapes::nestedShells(3), 300, 100);
    checkShape("cube grid", shapes::cubeGrid(3), 300, 100);
    checkShape("gear train", shapes::gearTrain(3), 300, 100);
    const Soup shells = shapes::nestedShells(5);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    std::vector<Vec3> centre;
    for (int i = 0; i < 200; ++i)
        centre.push_back({u(rng), u(rng), u(rng)});
    expectWithin(measure("nested shells centre", shells, centre));
}

// The tree and its answers do not depend on the thread count, nor on
// AVX2 for the expansions (the leaves' sums may differ by rounding).
void test_threads_and_simd(void **)
{
    const Soup s = shapes::withoutFaces(shapes::sphere(0, 0, 0, 1, 60, 120, kPi, 0.02, 4), 5);
    const std::vector<Vec3> points = shapes::nearPoints(s, 200, 7);
    std::vector<double> serial, parallel;
    {
        tbb::task_arena one(1);
        one.execute([&] {
            const FastWinding tree(s.points, s.triangles);
            for (const Vec3 &q : points)
                serial.push_back(tree(q));
        });
    }
    const FastWinding tree(s.points, s.triangles), plain(s.points, s.triangles, false);
    double simdDifference = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        parallel.push_back(tree(points[i]));
        simdDifference = std::max(simdDifference, std::abs(plain(points[i]) - parallel[i]));
    }
    assert_true(serial == parallel);
    assert_true(simdDifference < 1e-12);
}

// The nearest-triangle search of the same tree against brute force.
void test_distance(void **)
{
    const Soup s = shapes::withoutFaces(fromMesh("fandisk.obj"), 13);
    const FastWinding tree(s.points, s.triangles);
    const shapes::Brute brute(s);
    std::vector<Vec3> points = shapes::nearPoints(s, 100, 11);
    const std::vector<Vec3> far = shapes::farPoints(s, 100, 12);
    points.insert(points.end(), far.begin(), far.end());
    for (const Vec3 &q : points) {
        const double truth = brute.distance(q.data());
        assert_true(std::abs(tree.distance(q) - truth) <= 1e-9 * (1 + truth));
    }
}

} // namespace

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_open_generated), cmocka_unit_test(test_inside_open_scan),
        cmocka_unit_test(test_side_near_half), cmocka_unit_test(test_shared_meshes_with_holes),
        cmocka_unit_test(test_assemblies),     cmocka_unit_test(test_threads_and_simd),
        cmocka_unit_test(test_distance),
    };
    return cmocka_run_group_tests_name("mesh_winding", tests, nullptr, nullptr);
}
