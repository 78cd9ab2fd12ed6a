// src/mesh/sign: the winding number, fast and exact, and the sign of every
// voxel it decides, held to mesh_support.h's brute-force winding number
// (the Van Oosterom-Strackee solid angles of every triangle) on a closed
// and an open sphere; the solid angles four at a time against one at a
// time; a block's flood against its definition.
#include "distance/band.h"
#include "sign/block_flood.h"
#include "sign/solid_angles.h"
#include "sign/winding.h"
#include "sign/winding_sign.h"

#include <cmath>
#include <random>

// Last: cmocka's macros would rename members of the headers above.
#include "mesh_unit.h"

namespace
{

using meshsdf::TriangleMesh;

std::array<double, 3> randomPoint(std::mt19937_64 &random, double extent)
{
    std::uniform_real_distribution<double> u(-extent, extent);
    return {u(random), u(random), u(random)};
}

// FastWinding's exact sum is the brute force's; its hierarchical value is
// within the margin every sign decision keeps for it (winding_sign.cpp's
// kMargin = 0.1; seen up to 0.068 here, near the sphere's centre) and
// close on average; one triangle's solid angle is exact.
void winding_numbers(void **)
{
    std::mt19937_64 random(5);
    double error = 0;
    int points = 0;
    for (bool hole : {false, true}) {
        TriangleMesh m = unit::sphere({0, 0, 0}, 1, 16, hole);
        mesh truth = unit::truth(m);
        const meshsdf::FastWinding fast(m.points, m.triangles, true);
        for (int n = 0; n < 400; ++n) {
            const auto q = randomPoint(random, 1.5);
            const double want = winding(&truth, q.data());
            assert_true(std::fabs(fast.bruteForce(q) - want) < 1e-9);
            assert_true(std::fabs(fast(q) - want) < 0.1);
            error += std::fabs(fast(q) - want);
            ++points;
            if (!hole && std::fabs(std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) - 1) > 0.05)
                assert_true(std::fabs(want - (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] < 1 ? 1 : 0)) < 1e-9);
        }
        mesh_free(&truth);
    }
    // The order-2 term counts: mean error 0.0044 with it, 0.0105 with it
    // negated.
    assert_true(error / points < 0.007);
    const meshsdf::Vec3 a{1, 0, 0}, b{0, 1, 0}, c{0, 0, 1}, o{0, 0, 0};
    assert_true(std::fabs(meshsdf::triangleWinding(a, b, c, o) - 1.0 / 8) < 1e-12); // an octant
}

// The solid angles of groups of four triangles: vector lanes and scalar
// agree to rounding, and each is one triangle's solid angle.
void solid_angles(void **)
{
    std::mt19937_64 random(9);
    std::uniform_real_distribution<double> u(-1, 1);
    double groups[2 * meshsdf::kSolidAngleGroup];
    for (double &x : groups)
        x = u(random);
    for (int n = 0; n < 200; ++n) {
        const double q[3] = {2 * u(random), 2 * u(random), 2 * u(random)};
        double one = 0;
        for (int t = 0; t < 7; ++t) {
            const double *g = groups + (t / 4) * meshsdf::kSolidAngleGroup;
            const int l = t % 4;
            double corner[3][3];
            for (int v = 0; v < 3; ++v)
                for (int k = 0; k < 3; ++k)
                    corner[v][k] = g[(v * 3 + k) * 4 + l] - q[k];
            one += meshsdf::solidAngleOver4Pi(corner[0], corner[1], corner[2]);
        }
        const double scalar = meshsdf::solidAnglesOver4Pi(groups, 7, q, false),
                     vector = meshsdf::solidAnglesOver4Pi(groups, 7, q, true);
        assert_true(std::fabs(scalar - one) < 1e-12 && std::fabs(vector - one) < 1e-12);
    }
}

// The sign of every voxel of a band block and of whole cubes off the band,
// against the brute-force winding number wherever it is clear of 1/2.
void voxel_signs(void **)
{
    for (bool hole : {false, true}) {
        TriangleMesh m = unit::sphere({0, 0, 0}, 1, 12, hole);
        mesh truth = unit::truth(m);
        const meshsdf::FastWinding fast(m.points, m.triangles, true);
        const std::array<double, 3> origin{-1.55, -1.5, -1.45};
        const double h = 0.1, r = 2;
        const meshsdf::WindingSign sign(meshsdf::EdgeField(m), fast, origin, h, r, true);
        size_t checked = 0;
        for (int bx = 0; bx < 32; bx += 8)
            for (int by = 0; by < 32; by += 8)
                for (int bz = 0; bz < 32; bz += 8) {
                    float d[meshsdf::kBlockSize];
                    double w[meshsdf::kBlockSize];
                    for (int v = 0; v < meshsdf::kBlockSize; ++v) {
                        const double p[3] = {origin[0] + (bx + v / 64) * h, origin[1] + (by + v / 8 % 8) * h,
                                             origin[2] + (bz + v % 8) * h};
                        const double dist = mesh_distance(&truth, p);
                        d[v] = dist < r * h ? float(dist) : INFINITY; // the exact band, as band.h gives it
                        w[v] = winding(&truth, p);
                    }
                    sign.signBlock({bx, by, bz}, d);
                    for (int v = 0; v < meshsdf::kBlockSize; ++v) {
                        if (std::fabs(w[v] - 0.5) < 0.1)
                            continue;
                        ++checked;
                        if (std::signbit(d[v]) != (w[v] > 0.5))
                            fail_msg("block %d %d %d voxel %d: %g, winding %g", bx, by, bz, v, double(d[v]), w[v]);
                    }
                }
        assert_true(checked > 20000);
        // A cube off the band whole: the one around the centre is inside
        // a closed sphere; a far one is outside either way.
        if (!hole)
            assert_int_equal(sign.cubeSide({13, 13, 14}, 4), -1);
        const meshsdf::WindingSign far(meshsdf::EdgeField(m), fast, {5, 5, 5}, h, r, true);
        assert_int_equal(far.cubeSide({0, 0, 0}, 16), 1);
        mesh_free(&truth);
    }
}

// A block's flood: with every voxel far from the mesh it joins the whole
// set it may walk; with every voxel on the mesh it joins the seed alone.
void block_flood(void **)
{
    float farAway[meshsdf::kBlockSize], onIt[meshsdf::kBlockSize];
    std::fill(farAway, farAway + meshsdf::kBlockSize, 10.0f);
    std::fill(onIt, onIt + meshsdf::kBlockSize, 0.0f);
    meshsdf::VoxelMask within;
    for (int v = 0; v < meshsdf::kBlockSize; ++v)
        if (v % 8 < 4) // z below 4: a slab
            within.add(v);
    int layers = 0;
    const meshsdf::VoxelMask all = meshsdf::BlockFlood(farAway, 1.0).flood(0, within, 64, layers);
    for (int v = 0; v < meshsdf::kBlockSize; ++v)
        assert_int_equal(all.has(v), v % 8 < 4);
    assert_true(layers >= 1 && layers <= 7); // the slab's far corner, 7 diagonal steps away
    const meshsdf::VoxelMask seed = meshsdf::BlockFlood(onIt, 1.0).flood(9, within, 64, layers);
    for (int v = 0; v < meshsdf::kBlockSize; ++v)
        assert_int_equal(seed.has(v), v == 9);
}

} // namespace

int main()
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(winding_numbers),
        cmocka_unit_test(solid_angles),
        cmocka_unit_test(voxel_signs),
        cmocka_unit_test(block_flood),
    };
    return cmocka_run_group_tests_name("mesh_sign", tests, nullptr, nullptr);
}
