// src/mesh/samples: the point query and DeepSDF's training samples, held
// to mesh_support.h's brute-force signed distance; the counts of each kind
// of row; the same rows for any thread count; Morton order a permutation.
#include "geometry/unit_sphere.h"
#include "progress/progress.h"
#include "samples/query.h"
#include "samples/samples.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <random>

// Last: cmocka's macros would rename members of the headers above.
#include "mesh_unit.h"

namespace
{

using meshsdf::TriangleMesh;

// Signed distances and winding numbers at points, in Morton order and in
// packets, against brute force; the winding number within the default
// evaluation's stated bound, 5e-3.
void point_query(void **)
{
    TriangleMesh m = unit::sphere({0.2, 0, 0}, 1, 12);
    mesh truth = unit::truth(m);
    const meshsdf::PointQuery query(m, true);
    std::mt19937_64 random(2);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    const size_t n = 500;
    std::vector<double> xyz(3 * n);
    for (double &x : xyz)
        x = u(random);
    const std::vector<size_t> order = meshsdf::mortonOrder(xyz, meshsdf::meshSphere(m));
    size_t seen = 0;
    query.evaluate(xyz.data(), order.data(), 0, n, {true, true}, [&](size_t i, double d, double w) {
        const double *p = &xyz[3 * i];
        const double want = mesh_sdf(&truth, p);
        assert_true(std::fabs(std::fabs(d) - std::fabs(want)) <= 1e-9 * (1 + std::fabs(want)));
        assert_true(std::fabs(w - 0.5) < 5e-3 || (d < 0) == (want < 0));
        assert_true(std::fabs(w - winding(&truth, p)) <= 5e-3);
        assert_true(query.winding(p) == w);
        ++seen;
    });
    assert_int_equal(seen, n);
    mesh_free(&truth);
}

// round(share n) uniform rows, the rest near, the first sigma's half
// rounded up.
void counts(void **)
{
    const meshsdf::SampleCounts a = meshsdf::sampleCounts(250000, 0.06);
    assert_int_equal(a.uniform, 15000);
    assert_int_equal(a.near[0], 117500);
    assert_int_equal(a.near[1], 117500);
    const meshsdf::SampleCounts b = meshsdf::sampleCounts(11, 0.5);
    assert_int_equal(b.uniform, 6); // 5.5 rounds up
    assert_int_equal(b.near[0], 3);
    assert_int_equal(b.near[1], 2);
    assert_int_equal(meshsdf::sampleCounts(3, 1.0).uniform, 3);
}

std::vector<float> draw(const TriangleMesh &m, const sdft_mesh_sample_params &p, int threads)
{
    const meshsdf::MeshSphere sphere = meshsdf::meshSphere(m);
    std::vector<float> rows(size_t(p.count) * 4);
    tbb::task_arena arena(threads);
    arena.execute([&] {
        const meshsdf::PointQuery query(m, true);
        meshsdf::Progress progress(nullptr, nullptr, nullptr);
        meshsdf::drawSamples(m, sphere, query, p, rows.data(), progress);
    });
    return rows;
}

// Rows: near ones first within a few sigmas of the surface, then uniform
// ones in the sphere's cube; every distance the brute force's; the same
// bytes for one thread and two.
void samples(void **)
{
    TriangleMesh m = unit::sphere({1, 2, 3}, 2, 10);
    mesh truth = unit::truth(m);
    sdft_mesh_sample_params p = sdft_mesh_sample_params_defaults();
    p.count = 9000; // three chunks
    p.seed = 4;
    const std::vector<float> rows = draw(m, p, 1), again = draw(m, p, 2);
    assert_memory_equal(rows.data(), again.data(), rows.size() * sizeof(float));
    const meshsdf::MeshSphere sphere = meshsdf::meshSphere(m);
    const meshsdf::SampleCounts c = meshsdf::sampleCounts(size_t(p.count), p.uniform_share);
    for (size_t i = 0; i < size_t(p.count); ++i) {
        const double q[3] = {rows[i * 4], rows[i * 4 + 1], rows[i * 4 + 2]};
        const double want = mesh_sdf(&truth, q);
        const double w = winding(&truth, q);
        if (std::fabs(w - 0.5) > 0.1)
            assert_true(std::fabs(rows[i * 4 + 3] - want) <= 2e-6 * (1 + std::fabs(want)));
        if (i < c.near[0] + c.near[1]) // sigma 0.07 of the radius: 6 sigmas is far
            assert_true(std::fabs(want) < 6 * p.near_sigma[0] * sphere.radius * std::sqrt(3.0));
        else
            for (int k = 0; k < 3; ++k)
                assert_true(std::fabs(q[k] - sphere.centre[k]) <= sphere.radius * (1 + 1e-6));
    }
    p.seed = 5;
    const std::vector<float> other = draw(m, p, 2);
    assert_memory_not_equal(rows.data(), other.data(), rows.size() * sizeof(float));
    mesh_free(&truth);
}

// Morton order: every point once, and points near in space near in order.
void morton_order(void **)
{
    std::vector<double> xyz;
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j)
            xyz.insert(xyz.end(), {i / 16.0, j / 16.0, 0.0});
    xyz.insert(xyz.end(), {NAN, 0, 0});
    const std::vector<size_t> order = meshsdf::mortonOrder(xyz, meshsdf::MeshSphere{{0.5, 0.5, 0.5}, 0.5});
    std::vector<size_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (size_t i = 0; i < sorted.size(); ++i)
        assert_int_equal(sorted[i], i);
    assert_int_equal(order[0], 0); // the low corner first (NaN is placed there too)
    size_t far = 0;
    for (size_t j = 1; j < 256; ++j) {
        const size_t a = order[j - 1], b = order[j];
        if (a < 256 && b < 256 && std::fabs(xyz[a * 3] - xyz[b * 3]) + std::fabs(xyz[a * 3 + 1] - xyz[b * 3 + 1]) > 0.3)
            ++far;
    }
    assert_true(far < 16); // a Z-curve jumps rarely
}

} // namespace

int main()
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(point_query),
        cmocka_unit_test(counts),
        cmocka_unit_test(samples),
        cmocka_unit_test(morton_order),
    };
    return cmocka_run_group_tests_name("mesh_samples", tests, nullptr, nullptr);
}
