/* sdftrace tests — the exact first root in a cell (src/grid/grid_root.c):
 * grid_cell_root against brute force on random and near-planar cells, and a
 * grid's hits and normals against its interpolant, in double. */
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "grid_internal.h"
#include "grid_support.h"
#include "sdftrace/grid.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/sdf.h"
#include "sdftrace/vdb.h"
#include "testutil.h"

/* ---- the exact last-cell root ---------------------------------------------------- */

/* Brute force: the first s in [0, len] where f(u0 + s du) <= 0, by samples
 * 1/20000 of the way apart and bisection between the last two; -1 if none. */
static double brute_root(const float v[8], const double u0[3], const double du[3], double len)
{
    enum { SAMPLES = 20000 };
    double prev = 0.0;
    for (int i = 0; i <= SAMPLES; i++) {
        const double s = len * i / SAMPLES, u[3] = {u0[0] + s * du[0], u0[1] + s * du[1], u0[2] + s * du[2]};
        if (trilinear_d(v, u) <= 0.0) {
            if (i == 0)
                return 0.0;
            double lo = prev, hi = s;
            for (int k = 0; k < 60; k++) {
                const double mid = 0.5 * (lo + hi),
                             um[3] = {u0[0] + mid * du[0], u0[1] + mid * du[1], u0[2] + mid * du[2]};
                if (trilinear_d(v, um) <= 0.0)
                    hi = mid;
                else
                    lo = mid;
            }
            return hi;
        }
        prev = s;
    }
    return -1.0;
}

/* The distance along unit du from u inside the unit cube to its boundary
 * (backwards when sign < 0). */
static double to_boundary(const double u[3], const double du[3], double sign)
{
    double best = INFINITY;
    for (int k = 0; k < 3; k++) {
        const double d = sign * du[k];
        if (d > 0.0)
            best = fmin(best, (1.0 - u[k]) / d);
        else if (d < 0.0)
            best = fmin(best, -u[k] / d);
    }
    return best;
}

/* The solver and brute force on the ray along du (normalised here) across
 * the whole cell through q, from where it enters: the solver's answer
 * (*s when 1), brute force's root in *want (-1: none); -1 for a du too
 * short to aim with. u0 gets the entry point (cell-local). */
static int cell_root_across(const float v[8], const double q[3], double du[3], double shortest, double u0[3], double *s,
                            double *want)
{
    const double len = sqrt(du[0] * du[0] + du[1] * du[1] + du[2] * du[2]);
    if (!(len > shortest))
        return -1;
    for (int k = 0; k < 3; k++)
        du[k] /= len;
    const double back = to_boundary(q, du, -1.0), across = back + to_boundary(q, du, 1.0);
    for (int k = 0; k < 3; k++)
        u0[k] = q[k] - back * du[k];
    *want = brute_root(v, u0, du, across);
    return grid_cell_root(v, u0, du, across, s);
}

/* grid_cell_root against brute force on random cells and rays across
 * them: half aimed through a point of the surface along its tangent
 * plane (grazing, tilted by at most 3 degrees), the rest in random
 * directions. Roots agree to 1e-3 of a voxel; where brute force sees none,
 * the solver's root is a touch (the interpolant there is ~0). */
static void test_cell_root_against_brute_force(void **state)
{
    (void)state;
    tu_rng r = tu_rng_seed(21);
    int roots = 0, grazing = 0;
    for (int i = 0; i < 6000; i++) {
        float v[8];
        for (int k = 0; k < 8; k++)
            v[k] = tu_uniform(&r, -1.0f, 1.0f);
        double q[3] = {tu_uniform(&r, 0.05f, 0.95f), tu_uniform(&r, 0.05f, 0.95f), tu_uniform(&r, 0.05f, 0.95f)};
        double du[3] = {tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)};
        if (i % 2 == 0) {
            /* Move q onto the surface along a random line, then aim along
             * its tangent plane: n x (random), tilted a little along n. */
            double lo = -2.0, hi = 2.0, base[3] = {q[0], q[1], q[2]};
            double fl, fh;
            {
                const double a[3] = {base[0] + lo * du[0], base[1] + lo * du[1], base[2] + lo * du[2]},
                             b[3] = {base[0] + hi * du[0], base[1] + hi * du[1], base[2] + hi * du[2]};
                fl = trilinear_d(v, a), fh = trilinear_d(v, b);
            }
            if (fl * fh >= 0.0)
                continue;
            for (int k = 0; k < 80; k++) {
                const double mid = 0.5 * (lo + hi),
                             m[3] = {base[0] + mid * du[0], base[1] + mid * du[1], base[2] + mid * du[2]};
                if ((trilinear_d(v, m) > 0.0) == (fl > 0.0))
                    lo = mid;
                else
                    hi = mid;
            }
            for (int k = 0; k < 3; k++)
                q[k] = base[k] + lo * du[k];
            if (q[0] < 0.02 || q[0] > 0.98 || q[1] < 0.02 || q[1] > 0.98 || q[2] < 0.02 || q[2] > 0.98)
                continue;
            double n[3];
            for (int k = 0; k < 3; k++) {
                double a[3] = {q[0], q[1], q[2]}, b[3] = {q[0], q[1], q[2]};
                a[k] -= 1e-6, b[k] += 1e-6;
                n[k] = (trilinear_d(v, b) - trilinear_d(v, a)) / 2e-6;
            }
            const double w[3] = {tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)};
            const double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), tilt = tu_uniform(&r, -0.05f, 0.05f);
            double tg[3] = {n[1] * w[2] - n[2] * w[1], n[2] * w[0] - n[0] * w[2], n[0] * w[1] - n[1] * w[0]};
            const double tl = sqrt(tg[0] * tg[0] + tg[1] * tg[1] + tg[2] * tg[2]);
            if (!(tl > 1e-6) || !(nn > 1e-6))
                continue;
            for (int k = 0; k < 3; k++)
                du[k] = tg[k] / tl + tilt * n[k] / nn;
            grazing++;
        }
        double u0[3], s, want;
        const int found = cell_root_across(v, q, du, 1e-9, u0, &s, &want);
        if (found < 0)
            continue;
        if (want >= 0.0) {
            if (!found || fabs(s - want) > 1e-3)
                fail_msg("cell %d: root %s%g, brute force %g", i, found ? "" : "none, ", found ? s : 0.0, want);
            roots++;
        } else if (found) {
            const double u[3] = {u0[0] + s * du[0], u0[1] + s * du[1], u0[2] + s * du[2]};
            if (fabs(trilinear_d(v, u)) > 1e-6)
                fail_msg("cell %d: root at %g where brute force sees none, f = %g", i, s, trilinear_d(v, u));
        }
    }
    print_message("%d cells with a root, %d rays grazing\n", roots, grazing);
    assert_true(roots > 2000);
    assert_true(grazing > 500);
}

/* Cells whose values are a plane's, to within eta (0 to 1e-6): the
 * interpolant along a ray is a line plus at most eta, so the solver may
 * take the chord's root (grid_root.c) where that is provably within
 * 2^-30 of the segment, and must step on where it is not. Roots agree
 * with brute force to 1e-9 of a voxel. */
static void test_cell_root_on_near_planar_cells(void **state)
{
    (void)state;
    tu_rng r = tu_rng_seed(23);
    static const double etas[4] = {0.0, 1e-12, 1e-9, 1e-6};
    int roots = 0;
    for (int i = 0; i < 4000; i++) {
        const double eta = etas[i % 4];
        const double n[3] = {tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)};
        const double q[3] = {tu_uniform(&r, 0.1f, 0.9f), tu_uniform(&r, 0.1f, 0.9f), tu_uniform(&r, 0.1f, 0.9f)};
        float v[8];
        for (int k = 0; k < 8; k++) { /* the plane through q with normal n, plus up to eta */
            const double c[3] = {k & 1, k >> 1 & 1, k >> 2 & 1};
            v[k] = (float)(n[0] * (c[0] - q[0]) + n[1] * (c[1] - q[1]) + n[2] * (c[2] - q[2]) +
                           eta * tu_uniform(&r, -1, 1));
        }
        double du[3] = {tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)};
        double u0[3], s, want;
        const int found = cell_root_across(v, q, du, 1e-3, u0, &s, &want);
        if (found < 0)
            continue;
        if (want > 0.0) {
            if (!found || fabs(s - want) > 1e-9)
                fail_msg("cell %d (eta %g): root %s%.12g, brute force %.12g", i, eta, found ? "" : "none, ",
                         found ? s : 0.0, want);
            roots++;
        }
    }
    print_message("%d near-planar cells with a root\n", roots);
    assert_true(roots > 1000);
}

/* A grid's ray hits the first root of its interpolant exactly: the
 * interpolant, in double from the stored voxels, changes sign within 1e-3
 * of a voxel around the hit (or touches 0 there), and is positive on a
 * fine sampling of the two voxels before it; and the hit's normal is the
 * interpolant's gradient there, in the cell the ray reaches it from
 * (central differences in double, taken to world space), where the hit
 * is an exact root, and none where it is not. */
static double grid_interpolant(const sdft_grid *g, sdft_vec3 p)
{
    int32_t i0[3];
    double u[3];
    float v[8];
    cell_at(g, p, i0, u, v);
    return trilinear_d(v, u);
}

static void test_exact_root_on_a_grid(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 96, 0, NULL);
    const float h = sdft_grid_voxel_size(g).x;
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    assert_non_null(gf.accel->root);
    sdft_scratch s;
    sdft_scratch_init(&gf, &s);
    tu_rng r = tu_rng_seed(22);
    int hits = 0, exact = 0;
    for (int i = 0; i < 400; i++) {
        const sdft_ray ray = ray_into(sdft_grid_world_bounds(g), 0.3f, &r);
        for (int m = 0; m < SDFT_METHOD_COUNT; m++) {
            sdft_trace_params tp = sdft_trace_defaults();
            tp.method = (sdft_method)m;
            tp.omega = sdft_default_omega((sdft_method)m);
            sdft_hit hit = sdft_trace(&gf, &s, &ray, &tp);
            if (hit.status != SDFT_HIT)
                continue;
            hits++;
            if (hit.distance != 0.0f) { /* the root walk gave up (none within its cells): refined as before */
                assert_true(hit.normal.x == 0.0f && hit.normal.y == 0.0f && hit.normal.z == 0.0f);
                continue;
            }
            exact++;
            int32_t i0[3];
            double u[3], x[3], world[3];
            float v[8];
            cell_at(g, sdft_madd(ray.org, ray.dir, hit.t - 1e-3f * h), i0, u, v);
            index_point(g, sdft_madd(ray.org, ray.dir, hit.t), x);
            for (int k = 0; k < 3; k++) /* the hit's coordinates in that cell */
                u[k] = x[k] - i0[k];
            const double len = interpolant_gradient(g, v, u, world);
            const double cosine = (hit.normal.x * world[0] + hit.normal.y * world[1] + hit.normal.z * world[2]) / len;
            if (!(cosine > 0.9999 && fabsf(sdft_length(hit.normal) - 1.0f) < 1e-5f))
                fail_msg("%s: ray %d, normal (%g, %g, %g) at its exact hit, the interpolant's gradient (%g, %g, %g)",
                         sdft_method_name(tp.method), i, hit.normal.x, hit.normal.y, hit.normal.z, world[0] / len,
                         world[1] / len, world[2] / len);
            const double before = grid_interpolant(g, sdft_madd(ray.org, ray.dir, hit.t - 1e-3f * h));
            const double after = grid_interpolant(g, sdft_madd(ray.org, ray.dir, hit.t + 1e-3f * h));
            const double at = grid_interpolant(g, sdft_madd(ray.org, ray.dir, hit.t));
            if (!(before > 0.0 && after <= 0.0) && !(fabs(at) < 1e-4 * h))
                fail_msg("%s: ray %d hits at %g, interpolant %g / %g / %g around it", sdft_method_name(tp.method), i,
                         hit.t, before, at, after);
            for (int k = 1; k <= 200; k++) {
                const float t = hit.t - 1e-3f * h - 2.0f * h * (float)k / 200.0f;
                if (grid_interpolant(g, sdft_madd(ray.org, ray.dir, t)) <= 0.0)
                    fail_msg("%s: ray %d hits at %g, beyond an earlier root near %g", sdft_method_name(tp.method), i,
                             hit.t, t);
            }
        }
    }
    print_message("%d hits, %d of them exact roots\n", hits, exact);
    assert_true(exact > 300);
    assert_true(exact > hits * 9 / 10);
    sdft_grid_free(g);
}

/* A ray that passes within eps of a grid's surface without meeting it:
 * stepping to eps calls it a hit (the papers' rule), the exact root does
 * not, having walked the cells to the ray's end, and brute-force sampling
 * of the interpolant finds no root on it; a ray that does cross the
 * surface hits at the root either way. Rays passing the spheres' largest
 * at 0.2 to 1.6 voxels from it, and a few through it, with eps two voxels, so that the march
 * lands within eps before the exact root is due (on the interpolant alone,
 * whose values outside the band are the background's three voxels). */
static void test_exact_root_passes_a_near_miss(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(48, &s);
    const sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_NONE); /* the interpolant alone: the far bound's values
                                                                     * can be below two voxels */
    sdft_scratch_init(&gf, &s);
    const float h = sdft_grid_voxel_size(g).x;
    int passed = 0, papers_hit = 0, crossed = 0;
    for (int i = 0; i < 40; i++) {
        /* Towards -x, at height y above the sphere of radius 0.6 round the
         * origin, in the plane z = -0.2 (clear of the other spheres). */
        const float z = -0.2f, miss = (i < 35 ? 0.2f + 0.04f * (float)i : -0.5f - 0.1f * (float)(i - 35)) * h;
        const float y = sqrtf((0.6f + miss) * (0.6f + miss) - z * z);
        const sdft_ray ray = {.org = {1.3f, y, z}, .tnear = 0.0f, .dir = {-1.0f, 0.0f, 0.0f}, .tfar = 1.3f};
        sdft_trace_params tp = sdft_trace_defaults();
        tp.eps = 2.0f * h;
        const sdft_hit exact = sdft_trace(&gf, &s, &ray, &tp);
        tp.exact_root = 0;
        const sdft_hit stepped = sdft_trace(&gf, &s, &ray, &tp);
        float root = INFINITY;
        for (float t = 0.0f; t <= ray.tfar && root == INFINITY; t += 0.01f * h)
            if (grid_interpolant(g, sdft_madd(ray.org, ray.dir, t)) <= 0.0)
                root = t;
        if (root == INFINITY) {
            if (exact.status != SDFT_MISS)
                fail_msg("ray %d passes %g voxels from the sphere: status %d at t = %g with the exact root", i,
                         miss / h, exact.status, exact.t);
            passed++;
            papers_hit += stepped.status == SDFT_HIT;
        } else {
            assert_int_equal(exact.status, SDFT_HIT);
            assert_true(fabsf(exact.t - root) <= 0.02f * h);
            crossed++;
        }
    }
    print_message("%d rays pass the sphere by (%d of them hits when stepping to eps), %d cross it\n", passed,
                  papers_hit, crossed);
    assert_true(passed >= 30 && papers_hit >= 20 && crossed >= 3);
    sdft_grid_free(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cell_root_against_brute_force),
        cmocka_unit_test(test_cell_root_on_near_planar_cells),
        cmocka_unit_test(test_exact_root_on_a_grid),
        cmocka_unit_test(test_exact_root_passes_a_near_miss),
    };
    return cmocka_run_group_tests_name("grid_root", tests, NULL, NULL);
}
