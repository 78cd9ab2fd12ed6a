// src/mesh/distance: the exact narrow band and the nearest-triangle
// search, held to mesh_support.h's brute-force distance over every
// triangle: every voxel nearer than the half-width is in the band with its
// exact distance, no band value overstates, and the vector and scalar rows
// agree.
#include "distance/band.h"
#include "distance/nearest_triangle.h"
#include "distance/packet_rows.h"
#include "distance/wide_tree.h"

#include <cmath>
#include <map>
#include <mutex>
#include <random>

// Last: cmocka's macros would rename members of the headers above.
#include "mesh_unit.h"

namespace
{

using meshsdf::TriangleMesh;

struct Band {
    std::map<std::array<int, 3>, std::vector<float>> blocks; // origin -> 512 distances
};

Band band(const TriangleMesh &m, const std::array<double, 3> &origin, double h, double r, bool simd)
{
    Band b;
    std::mutex lock;
    meshsdf::exactBand(
        m, origin, h, r,
        [&](const std::array<int, 3> &at, float *d) {
            std::lock_guard<std::mutex> hold(lock);
            assert_true(at[0] % 8 == 0 && at[1] % 8 == 0 && at[2] % 8 == 0);
            b.blocks[at].assign(d, d + meshsdf::kBlockSize);
        },
        {}, simd);
    return b;
}

// A sphere on a 24^3 grid whose voxels do not line up with it: each
// voxel's band value against brute force, with and without vector rows.
void band_is_exact(void **)
{
    TriangleMesh m = unit::sphere({1.1, 1.0, 0.9}, 0.7, 9);
    mesh truth = unit::truth(m);
    const std::array<double, 3> origin{0.1, 0.05, -0.02};
    const double h = 0.09, r = 2.5;
    for (bool simd : {true, false}) {
        const Band b = band(m, origin, h, r, simd);
        size_t inBand = 0;
        for (int i = 0; i < 24; ++i)
            for (int j = 0; j < 24; ++j)
                for (int k = 0; k < 24; ++k) {
                    const double p[3] = {origin[0] + i * h, origin[1] + j * h, origin[2] + k * h};
                    const double d = mesh_distance(&truth, p);
                    const auto block = b.blocks.find({i & ~7, j & ~7, k & ~7});
                    const float v = block == b.blocks.end()
                                        ? INFINITY
                                        : block->second[size_t(((i & 7) * 8 + (j & 7)) * 8 + (k & 7))];
                    if (d < r * h) {
                        ++inBand;
                        if (!(std::fabs(v - d) <= 1e-5 * (1 + d)))
                            fail_msg("voxel %d %d %d: band %g, exact %g", i, j, k, double(v), d);
                    } else {
                        assert_true(std::isinf(v) || std::fabs(v - d) <= 1e-5 * (1 + d)); // never overstated
                    }
                }
        assert_true(inBand > 1000);
    }
    mesh_free(&truth);
}

// The search for one point (the points' wide tree) and for a packet of 4^3
// voxel centres (the grids' tree), with and without vector rows, against
// brute force.
void nearest_triangle(void **)
{
    TriangleMesh m = unit::sphere({0, 0, 0}, 1, 12, true);
    mesh truth = unit::truth(m);
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> u(-1.6, 1.6);
    const meshsdf::NearestTriangle vector(m, true, true), scalar(m, false, false);
    const meshsdf::WideTree wideVector(m, true), wideScalar(m, false);
    for (int n = 0; n < 300; ++n) {
        const double p[3] = {u(random), u(random), u(random)};
        const double d2 = mesh_distance(&truth, p) * mesh_distance(&truth, p);
        for (const meshsdf::WideTree *t : {&wideVector, &wideScalar})
            assert_true(std::fabs(t->nearest(p).d2 - d2) <= 1e-9 * (1 + d2));
    }
    for (int n = 0; n < 20; ++n) {
        const double corner[3] = {u(random), u(random), u(random)}, spacing = 0.07;
        double best[2][64];
        uint32_t nearest[2][64];
        for (int s = 0; s < 2; ++s) {
            std::fill(best[s], best[s] + 64, INFINITY);
            std::fill(nearest[s], nearest[s] + 64, meshsdf::NearestTriangle::kNone);
            (s ? scalar : vector).packetDistance2(corner, spacing, best[s], nearest[s]);
        }
        for (int v = 0; v < 64; ++v) {
            const double p[3] = {corner[0] + (v / 16) * spacing, corner[1] + (v / 4 % 4) * spacing,
                                 corner[2] + (v % 4) * spacing};
            const double d = mesh_distance(&truth, p);
            for (int s = 0; s < 2; ++s) {
                assert_true(std::fabs(best[s][v] - d * d) <= 1e-9 * (1 + d * d));
                assert_true(nearest[s][v] != meshsdf::NearestTriangle::kNone);
            }
        }
    }
    mesh_free(&truth);
}

} // namespace

int main()
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(band_is_exact),
        cmocka_unit_test(nearest_triangle),
    };
    return cmocka_run_group_tests_name("mesh_distance", tests, nullptr, nullptr);
}
