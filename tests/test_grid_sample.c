/* sdftrace tests — a grid as a field (src/grid/grid_sample.c): trilinear
 * samples against a plane's exact SDF and the interpolant by brute force,
 * the specialised distance functions against the generic sampler, normals
 * against the interpolant's gradient, the batch call against one call at a
 * time, a scratch that serves one grid only, and a grid render against the
 * procedural one. */
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

/* f(p) = n . p + c with |n| = 1: a plane's exact SDF, linear. */
typedef struct linear {
    sdft_vec3 n;
    float c;
} linear;

static float linear_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)s;
    const linear *l = ctx;
    return sdft_dot(l->n, p) + l->c;
}

/* ---- trilinear sampling ----------------------------------------------------- */

static void test_linear_field_is_exact(void **state)
{
    (void)state;
    linear l = {sdft_normalize(sdft_v3(0.3f, -0.5f, 0.8f)), 0.1f};
    sdft_field f = {.distance = linear_distance, .ctx = &l, .bounds = {{-1, -1, -1}, {1, 1, 1}}};
    sdft_grid *g = bake(&f, 32, 1, NULL);
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_scratch s;
    sdft_scratch_init(&gf, &s);
    tu_rng r = tu_rng_seed(1);
    float worst = 0;
    for (int i = 0; i < 20000; i++) {
        /* Stay half a voxel inside the box's voxel centres so all 8 corners exist. */
        sdft_vec3 p = sdft_v3(tu_uniform(&r, -0.9f, 0.9f), tu_uniform(&r, -0.9f, 0.9f), tu_uniform(&r, -0.9f, 0.9f));
        int level;
        float v = sdft_grid_sample(g, SDFT_GRID_BOUND_FAR, &s, p, &level);
        assert_int_equal(level, 0);
        worst = fmaxf(worst, fabsf(v - linear_distance(&l, NULL, p)));
        /* The field, its gradient normal: the plane's normal. */
        sdft_vec3 n = sdft_field_normal(&gf, &s, p);
        assert_true(sdft_dot(n, l.n) > 0.9999f);
    }
    assert_true(worst < 2e-6f);
    sdft_grid_free(g);
}

static float lerpf(float a, float b, float t) { return a + (b - a) * t; }

static void test_trilinear_matches_brute_force(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(48, &s);
    /* Index = (world - lo) / h - 1/2 for a bake (voxel centres at lo + (i + 1/2) h). */
    const float h = sdft_grid_voxel_size(g).x;
    tu_rng r = tu_rng_seed(2);
    int checked = 0;
    for (int i = 0; i < 20000; i++) {
        sdft_vec3 p = sdft_v3(tu_uniform(&r, -1.1f, 1.1f), tu_uniform(&r, -1.1f, 1.1f), tu_uniform(&r, -1.1f, 1.1f));
        int level;
        float v = sdft_grid_sample(g, SDFT_GRID_BOUND_FAR, &s, p, &level);
        if (level != 0)
            continue;
        float x[3] = {(p.x + 1.2f) / h - 0.5f, (p.y + 1.2f) / h - 0.5f, (p.z + 1.2f) / h - 0.5f};
        int32_t i0[3] = {(int32_t)floorf(x[0]), (int32_t)floorf(x[1]), (int32_t)floorf(x[2])};
        float c[8];
        cell_corners(g, i0, c);
        float t[3] = {x[0] - i0[0], x[1] - i0[1], x[2] - i0[2]};
        float ref = lerpf(lerpf(lerpf(c[0], c[1], t[0]), lerpf(c[2], c[3], t[0]), t[1]),
                          lerpf(lerpf(c[4], c[5], t[0]), lerpf(c[6], c[7], t[0]), t[1]), t[2]);
        assert_true(fabsf(v - ref) < 1e-5f);
        checked++;
    }
    assert_true(checked > 1000);
    sdft_grid_free(g);
}

/* The grid's distance functions are specialised per grid type, transform
 * shape and bound; each gives the generic sampler's value. Clearing a baked
 * grid's diagonal flag sends it through the full 3x3 transform. */
static void test_specialised_fields_agree(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *g = bake(&f, 48, 0, NULL);
    assert_true(g->diagonal);
    sdft_scratch s;
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_scratch_init(&gf, &s);
    enum { N = 4000 };
    static float ref[3][N];
    static const sdft_grid_bound bounds[3] = {SDFT_GRID_BOUND_FAR, SDFT_GRID_BOUND_TREE, SDFT_GRID_BOUND_NONE};
    for (int pass = 0; pass < 2; pass++) {
        g->diagonal = pass == 0;
        for (int b = 0; b < 3; b++) {
            sdft_field bf = sdft_grid_field(g, bounds[b]);
            tu_rng r = tu_rng_seed(7);
            for (int i = 0; i < N; i++) {
                sdft_vec3 p =
                    sdft_v3(tu_uniform(&r, -1.5f, 1.5f), tu_uniform(&r, -1.5f, 1.5f), tu_uniform(&r, -1.5f, 1.5f));
                float v = bf.distance(bf.ctx, &s, p);
                assert_true(v == sdft_grid_sample(g, bounds[b], &s, p, NULL));
                if (pass == 0)
                    ref[b][i] = v;
                else
                    assert_float_equal(v, ref[b][i], 1e-6f * (1.0f + fabsf(ref[b][i])));
            }
        }
    }
    g->diagonal = 1;
    sdft_grid_free(g);
}

/* ---- normals ---------------------------------------------------------------------- */

/* A grid's normal is the gradient of the interpolant it traces, in the cell
 * holding the point (OpenVDB's BoxStencil gradient), taken to world space by
 * the transform: held to central differences of that interpolant in double,
 * read voxel by voxel (exact up to rounding, as the interpolant is linear
 * along each axis), on points of cells the surface crosses. */
static void test_normal_is_the_interpolant_gradient(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(48, &s);
    const sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    tu_rng r = tu_rng_seed(31);
    int checked = 0;
    double worst = 1.0;
    for (int i = 0; i < 20000; i++) {
        const sdft_vec3 p =
            sdft_v3(tu_uniform(&r, -1.1f, 1.1f), tu_uniform(&r, -1.1f, 1.1f), tu_uniform(&r, -1.1f, 1.1f));
        int32_t i0[3];
        double u[3];
        float v[8];
        cell_at(g, p, i0, u, v);
        int inside = 1, negative = 0;
        for (int k = 0; k < 3; k++) /* clear of the cell's faces, where float rounding could cross */
            inside &= u[k] > 0.01 && u[k] < 0.99;
        for (int k = 0; k < 8; k++)
            negative += v[k] < 0.0f;
        if (!inside || negative == 0 || negative == 8)
            continue;
        double world[3];
        const double len = interpolant_gradient(g, v, u, world);
        const sdft_vec3 n = sdft_field_normal(&gf, &s, p);
        const double cosine = (n.x * world[0] + n.y * world[1] + n.z * world[2]) / len;
        worst = fmin(worst, cosine);
        if (!(cosine > 0.99999))
            fail_msg("normal (%g, %g, %g) at (%g, %g, %g), the interpolant's gradient (%g, %g, %g)", n.x, n.y, n.z, p.x,
                     p.y, p.z, world[0] / len, world[1] / len, world[2] / len);
        checked++;
    }
    print_message("%d normals in cells the surface crosses, worst cosine %.8f\n", checked, worst);
    assert_true(checked > 500);
    sdft_grid_free(g);
}

/* ---- a grid renders like its scene ------------------------------------------------ */

static void test_grid_render_matches_procedural(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 256, 0, NULL);
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    const float h = sdft_grid_voxel_size(g).x;

    sdft_render_params rp = sdft_render_defaults();
    rp.width = 240, rp.height = 135;
    rp.camera = sc->camera;
    rp.light = sc->light;
    rp.shadows = 0;
    char msg[256];
    sdft_image a, b;
    assert_int_equal(sdft_image_alloc(&a, rp.width, rp.height, NULL, 0), 0);
    assert_int_equal(sdft_image_alloc(&b, rp.width, rp.height, NULL, 0), 0);
    assert_int_equal(sdft_render(&sc->field, &rp, &a, NULL, msg, sizeof msg), 0);
    assert_int_equal(sdft_render(&gf, &rp, &b, NULL, msg, sizeof msg), 0);
    int both = 0, close = 0, one = 0, n = rp.width * rp.height;
    for (int i = 0; i < n; i++) {
        int ha = a.status[i] == SDFT_HIT, hb = b.status[i] == SDFT_HIT;
        if (ha && hb) {
            both++;
            close += fabsf(a.depth[i] - b.depth[i]) <= 1.5f * h;
        } else if (ha != hb) {
            one++;
        }
    }
    print_message("grid vs procedural: %d of %d both-hit pixels within 1.5 voxels, %d hit in one only\n", close, both,
                  one);
    assert_true(both > n / 20);
    assert_true(close >= 0.99 * both);
    assert_true(one <= 0.005 * n);
    sdft_image_free(&a);
    sdft_image_free(&b);
    sdft_grid_free(g);
}

/* The batch call (sdft_field_distances) on a grid: every point is hinted
 * before its evaluation, in order; the values are the ones sdft_field_distance
 * gives one call at a time, bit for bit (NaN and far points included), and
 * without the bound they are the trilinear interpolant of the stored voxels
 * (brute force through the public accessor). On a field without hints, the
 * analytic distances. */
static sdft_field batch_inner;
static size_t batch_evaluated, batch_hinted_then[1100];

static float batch_logging_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    if (batch_evaluated < 1100)
        batch_hinted_then[batch_evaluated] = (size_t)hint_count;
    batch_evaluated++;
    return batch_inner.distance(ctx, s, p);
}

static void test_field_distances_batch(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(48, &s);
    enum { N = 1100 };
    static sdft_vec3 p[N];
    static float batch[N], one[N];
    tu_rng r = tu_rng_seed(31);
    for (int i = 0; i < N; i++) /* the box and beyond it */
        p[i] = sdft_v3(tu_uniform(&r, -1.6f, 1.6f), tu_uniform(&r, -1.6f, 1.6f), tu_uniform(&r, -1.6f, 1.6f));
    p[7] = sdft_v3(NAN, 0.0f, 0.0f), p[8] = sdft_v3(1e30f, -1e30f, 0.0f);
    static const size_t counts[] = {0, 1, SDFT_FIELD_DISTANCES_AHEAD, SDFT_FIELD_DISTANCES_AHEAD + 1, N};
    for (int bound = 0; bound < 2; bound++) {
        const sdft_field gf =
            bound ? sdft_grid_field(g, SDFT_GRID_BOUND_FAR) : sdft_grid_field(g, SDFT_GRID_BOUND_NONE);
        assert_non_null(gf.accel->prefetch);
        sdft_field logged = gf;
        sdft_field_accel hinting = *gf.accel;
        hinting.prefetch = record_hint;
        batch_inner = gf;
        logged.distance = batch_logging_distance, logged.accel = &hinting;
        for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++) {
            const size_t n = counts[c];
            hint_count = 0, batch_evaluated = 0;
            memset(batch, 0xff, sizeof batch);
            sdft_field_distances(&logged, &s, p, n, batch);
            assert_int_equal(batch_evaluated, n);
            assert_int_equal(hint_count, n);
            for (size_t i = 0; i < n; i++) {
                assert_memory_equal(&hints[i], &p[i], sizeof p[i]);
                assert_true(batch_hinted_then[i] > i); /* p[i] hinted before its evaluation */
                one[i] = sdft_field_distance(&gf, &s, p[i]);
            }
            assert_memory_equal(batch, one, n * sizeof *batch);
            if (c == 4 || bound)
                continue;
            int inside = 0;
            for (size_t i = 0; i < n; i++) {
                int32_t i0[3];
                double u[3];
                float v[8];
                if (!(fabsf(p[i].x) <= 1.1f && fabsf(p[i].y) <= 1.1f && fabsf(p[i].z) <= 1.1f))
                    continue;
                cell_at(g, p[i], i0, u, v);
                const double x00 = v[0] + (v[1] - v[0]) * u[0], x10 = v[2] + (v[3] - v[2]) * u[0];
                const double x01 = v[4] + (v[5] - v[4]) * u[0], x11 = v[6] + (v[7] - v[6]) * u[0];
                const double y0 = x00 + (x10 - x00) * u[1], y1 = x01 + (x11 - x01) * u[1];
                assert_float_equal(batch[i], y0 + (y1 - y0) * u[2], 2e-6);
                inside++;
            }
            assert_true(n < 100 || inside > (int)n / 4);
        }
    }
    /* A field without hints: the analytic distance of the union of spheres. */
    const sdft_field sf = spheres_field();
    sdft_field_distances(&sf, &s, p, N, batch);
    for (int i = 9; i < N; i++) {
        double d = INFINITY;
        for (int k = 0; k < 4; k++) {
            const double dx = p[i].x - spheres[k][0], dy = p[i].y - spheres[k][1], dz = p[i].z - spheres[k][2];
            d = fmin(d, sqrt(dx * dx + dy * dy + dz * dz) - spheres[k][3]);
        }
        assert_float_equal(batch[i], d, 1e-5);
    }
    sdft_grid_free(g);
}

/* ---- a scratch remembers its grid ------------------------------------------------ */

/* A scratch prepared for one grid is refused by every entry point given
 * another grid's field, never read through the first grid's cached
 * accessor; fields of the same grid with another bound share it. */
static void test_scratch_remembers_its_grid(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *a = bake(&f, 32, 0, NULL), *b = bake(&sc->field, 40, 0, NULL);
    sdft_field fa = sdft_grid_field(a, SDFT_GRID_BOUND_FAR), fb = sdft_grid_field(b, SDFT_GRID_BOUND_FAR),
               fa_tree = sdft_grid_field(a, SDFT_GRID_BOUND_TREE);
    sdft_scratch s;
    sdft_scratch_init(&fa, &s);
    const sdft_trace_params p = sdft_trace_defaults();
    sdft_ray rays[4];
    for (int k = 0; k < 4; k++)
        rays[k] = (sdft_ray){.org = {0.1f * k, 0.05f, 4}, .tnear = 0, .dir = {0, 0, -1}, .tfar = INFINITY};
    sdft_hit hits[4];
    char msg[256];

    assert_int_equal(sdft_trace(&fa, &s, &rays[0], &p).status, SDFT_HIT);
    assert_int_equal(sdft_trace(&fa_tree, &s, &rays[0], &p).status, SDFT_HIT); /* the same grid */
    sdft_hit wrong = sdft_trace(&fb, &s, &rays[0], &p);
    assert_int_equal(wrong.status, SDFT_INVALID);
    assert_int_equal(wrong.steps, 0);
    sdft_trace_stream(&fb, &s, rays, hits, 4, &p);
    for (int k = 0; k < 4; k++)
        assert_int_equal(hits[k].status, SDFT_INVALID);
    uint32_t steps = 0;
    assert_true(sdft_cone_march(&fb, &s, rays[0].org, rays[0].dir, 0.01f, 0.0f, 10.0f, &steps) == 0.0f);
    assert_int_equal(steps, 0);
    assert_int_equal(sdft_trace_check(&fb, &s, &p, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "another field"));
    int level = 0;
    assert_true(isnan(sdft_grid_sample(b, SDFT_GRID_BOUND_FAR, &s, sdft_v3(0, 0, 0), &level)));
    assert_int_equal(level, -1);
    assert_false(isnan(sdft_grid_sample(a, SDFT_GRID_BOUND_FAR, &s, sdft_v3(0, 0, 0), &level)));

    /* Prepared for b, it serves b and no longer a. */
    sdft_scratch_init(&fb, &s);
    assert_int_not_equal(sdft_trace(&fb, &s, &rays[0], &p).status, SDFT_INVALID);
    assert_int_equal(sdft_trace(&fa, &s, &rays[0], &p).status, SDFT_INVALID);
    /* A procedural field keeps no state: it takes any scratch, and its own
     * scratch serves no grid. */
    assert_int_equal(sdft_trace(&f, &s, &rays[0], &p).status, SDFT_HIT);
    sdft_scratch_init(&f, &s);
    assert_int_equal(sdft_trace(&fa, &s, &rays[0], &p).status, SDFT_INVALID);
    sdft_grid_free(a);
    sdft_grid_free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_linear_field_is_exact),
        cmocka_unit_test(test_trilinear_matches_brute_force),
        cmocka_unit_test(test_specialised_fields_agree),
        cmocka_unit_test(test_normal_is_the_interpolant_gradient),
        cmocka_unit_test(test_grid_render_matches_procedural),
        cmocka_unit_test(test_field_distances_batch),
        cmocka_unit_test(test_scratch_remembers_its_grid),
    };
    return cmocka_run_group_tests_name("grid_sample", tests, NULL, NULL);
}
