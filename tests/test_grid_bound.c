/* sdftrace tests — a grid's bounds beyond its band: the tree bound
 * (src/grid/grid_sample.c) and the far bound (src/grid/grid_bound.c) against
 * the true distance, the far bound's cells and corner distances against the
 * tree walk and brute force, and a trace with any bound against the first
 * sign change found by brute-force marching. */
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

/* ---- the tree bound ----------------------------------------------------------- */

/* For a scene whose SDF is only a bound (it may underestimate the distance):
 * the ball of radius r around p holds no point of the other side, judged at
 * 2 x 256 points of its surface and half-radius sphere. */
static int empty_sphere(const sdft_field *truth, sdft_vec3 p, float r, int outside)
{
    for (int k = 0; k < 512; k++) {
        float z = 1.0f - (2.0f * (float)(k % 256) + 1.0f) / 256.0f, rho = sqrtf(1.0f - z * z),
              phi = 2.3999632f * (float)k;
        float rr = k < 256 ? r : 0.5f * r;
        sdft_vec3 q = sdft_madd(p, sdft_v3(rho * cosf(phi), rho * sinf(phi), z), rr);
        float d = truth->distance(truth->ctx, NULL, q);
        if (outside ? d < 0.0f : d > 0.0f)
            return 0;
    }
    return 1;
}

/* Wherever the field answers from a tile or the background, |value| must not
 * exceed the distance to the surface and the sign must be the side. Points
 * range over the box grown by `margin` of its size on each side: a grid only
 * knows the surface inside the box it was baked over, so a scene whose
 * surface leaves its box (a ground plane) is checked inside it. */
static void check_bound(const sdft_field *truth, const sdft_grid *g, sdft_grid_bound bound, float margin,
                        int exact_inside, int bound_only, uint64_t seed, int *tiles_seen)
{
    sdft_field gf = sdft_grid_field(g, bound);
    sdft_scratch s;
    sdft_scratch_init(&gf, &s);
    sdft_aabb b = truth->bounds;
    sdft_vec3 e = sdft_sub(b.hi, b.lo);
    tu_rng r = tu_rng_seed(seed);
    for (int i = 0; i < 200000; i++) {
        sdft_vec3 p = sdft_v3(tu_uniform(&r, b.lo.x - margin * e.x, b.hi.x + margin * e.x),
                              tu_uniform(&r, b.lo.y - margin * e.y, b.hi.y + margin * e.y),
                              tu_uniform(&r, b.lo.z - margin * e.z, b.hi.z + margin * e.z));
        int level;
        float v = sdft_grid_sample(g, bound, &s, p, &level);
        if (level == 0)
            continue;
        float d = truth->distance(truth->ctx, NULL, p);
        (*tiles_seen)++;
        if (!(d * v > 0.0f) || (fabsf(v) > fabsf(d) * (1 + 1e-6f) && (d > 0 || exact_inside) &&
                                !(bound_only && empty_sphere(truth, p, fabsf(v), v > 0.0f))))
            fail_msg("%s bound %g at (%g, %g, %g), level %d, exceeds the distance %g",
                     bound == SDFT_GRID_BOUND_FAR ? "far" : "tree", v, p.x, p.y, p.z, level, d);
    }
}

static void test_tree_bound_never_exceeds_distance(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *g = bake(&f, 128, 0, NULL);
    int tiles = 0;
    check_bound(&f, g, SDFT_GRID_BOUND_TREE, 0.5f, 0, 0, 3, &tiles); /* far outside the band and the box */
    assert_true(tiles > 10000);
    sdft_grid_free(g);
}

static void test_tree_bound_on_a_scene(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 96, 0, NULL);
    int tiles = 0;
    check_bound(&sc->field, g, SDFT_GRID_BOUND_TREE, 0.0f, 1, 0, 4, &tiles);
    assert_true(tiles > 10000);
    sdft_grid_free(g);
}

/* ---- the far bound --------------------------------------------------------------- */

static void test_far_bound_never_exceeds_distance(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *g = bake(&f, 128, 0, NULL);
    int far = 0;
    check_bound(&f, g, SDFT_GRID_BOUND_FAR, 0.5f, 0, 0, 5, &far); /* far outside the band and the box */
    assert_true(far > 10000);
    sdft_grid_free(g);
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    g = bake(&sc->field, 96, 0, NULL);
    far = 0;
    /* figure's SDF underestimates far from its parts (a bound, not exact):
     * where the far bound exceeds it, check the ball is empty instead. */
    check_bound(&sc->field, g, SDFT_GRID_BOUND_FAR, 0.0f, 1, 1, 6, &far);
    assert_true(far > 10000);
    sdft_grid_free(g);
}

/* The far bound tests' grids: a scene's (the figure at 96^3) and a union of
 * spheres at 128^3. */
static void bake_far_bound_grids(sdft_grid *grids[2])
{
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_field spheres = spheres_field();
    grids[0] = bake(&sc->field, 96, 0, NULL);
    grids[1] = bake(&spheres, 128, 0, NULL);
}

/* The far bound's cells, classified through the leaf directory (regions
 * without leaves whole, blocks by their masks and tile markers), are the
 * cells the tree walk finds: the same corner table, bit for bit, for a
 * scene's grid and a union of spheres, at 4-voxel cells and at coarser
 * ones (as a big grid gets). */
static void test_far_cells_from_directory_match_tree(void **state)
{
    (void)state;
    sdft_grid *grids[2];
    bake_far_bound_grids(grids);
    for (int i = 0; i < 2; i++)
        for (size_t most = 1u << 24; most >= 128; most /= 16) { /* 4-voxel cells, then 8, 16 */
            sdft_grid *g = grids[i];
            grid_far_free(g);
            assert_int_equal(grid_far_build_cells(g, most), 0);
            const grid_far a = g->far;
            const size_t corners = (size_t)(a.n[0] + 1) * (a.n[1] + 1) * (a.n[2] + 1);
            g->far.corner = NULL;
            const grid_leaves directory = g->leaves;
            g->leaves.top = NULL; /* the tree walk */
            assert_int_equal(grid_far_build_cells(g, most), 0);
            g->leaves = directory;
            assert_int_equal(g->far.cell, a.cell);
            assert_memory_equal(g->far.corner, a.corner, corners * sizeof *a.corner);
            size_t occupied = 0;
            for (size_t k = 0; k < corners; k++)
                occupied += (a.corner[k] >> FAR_DISTANCE_BITS) == 0;
            print_message("cells of %d voxels: %zu corners, %zu of occupied cells\n", a.cell, corners, occupied);
            assert_true(occupied > 10);
            free(a.corner);
        }
    for (int i = 0; i < 2; i++)
        sdft_grid_free(grids[i]);
}

/* The far bound's corner distances are the Euclidean distances, in cells,
 * from each corner to the nearest corner of an occupied cell, found here by
 * brute force over every such corner, and stored as the table stores them:
 * quarters of a voxel, rounded down, saturated. For a scene's grid and a
 * union of spheres (lines of corners between two shells, whose nearest site
 * may lie ahead or behind), at 4-voxel cells and at coarser ones. */
static void test_far_corner_distances_match_brute_force(void **state)
{
    (void)state;
    sdft_grid *grids[2];
    bake_far_bound_grids(grids);
    size_t ahead_seen = 0;
    for (int i = 0; i < 2; i++)
        for (size_t most = 1u << 24; most >= 1u << 12; most >>= 12) {
            sdft_grid *g = grids[i];
            grid_far_free(g);
            assert_int_equal(grid_far_build_cells(g, most), 0);
            const grid_far *f = &g->far;
            const int nv[3] = {f->n[0] + 1, f->n[1] + 1, f->n[2] + 1};
            const size_t corners = (size_t)nv[0] * nv[1] * nv[2];
            unsigned char *site = calloc(corners, 1);
            int(*sites)[3] = malloc(corners * sizeof *sites);
            assert_non_null(site);
            assert_non_null(sites);
            size_t count = 0;
            for (int z = 0; z < f->n[2]; z++)
                for (int y = 0; y < f->n[1]; y++)
                    for (int x = 0; x < f->n[0]; x++)
                        if ((f->corner[((size_t)z * nv[1] + y) * nv[0] + x] >> FAR_DISTANCE_BITS) == 0)
                            for (int k = 0; k < 8; k++) /* an occupied cell: its corners are sites */
                                site[((size_t)(z + (k >> 2)) * nv[1] + (size_t)(y + (k >> 1 & 1))) * nv[0] +
                                     (size_t)(x + (k & 1))] = 1;
            for (int z = 0; z < nv[2]; z++)
                for (int y = 0; y < nv[1]; y++)
                    for (int x = 0; x < nv[0]; x++)
                        if (site[((size_t)z * nv[1] + y) * nv[0] + x])
                            sites[count][0] = x, sites[count][1] = y, sites[count][2] = z, count++;
            assert_true(count > 10);
            const double most_code = (double)((1u << FAR_DISTANCE_BITS) - 1u);
            size_t ahead = 0; /* corners whose nearest site along x lies ahead of them, not behind */
            for (int z = 0; z < nv[2]; z++)
                for (int y = 0; y < nv[1]; y++)
                    for (int x = 0; x < nv[0]; x++) {
                        long best = LONG_MAX;
                        for (size_t j = 0; j < count; j++) {
                            const long dx = x - sites[j][0], dy = y - sites[j][1], dz = z - sites[j][2];
                            const long d2 = dx * dx + dy * dy + dz * dz;
                            best = d2 < best ? d2 : best;
                        }
                        const double q = FAR_DISTANCE_SCALE * f->cell * sqrt((double)best);
                        const unsigned want = (unsigned)(q < most_code ? q : most_code);
                        const unsigned got =
                            f->corner[((size_t)z * nv[1] + y) * nv[0] + x] & ((1u << FAR_DISTANCE_BITS) - 1u);
                        if (got != want)
                            fail_msg("cells of %d voxels, corner (%d, %d, %d): distance %u, brute force %u", f->cell, x,
                                     y, z, got, want);
                        int behind = -1, after = -1;
                        for (int b = x - 1; b >= 0 && behind < 0; b--)
                            behind = site[((size_t)z * nv[1] + y) * nv[0] + b] ? x - b : -1;
                        for (int a = x + 1; a < nv[0] && after < 0; a++)
                            after = site[((size_t)z * nv[1] + y) * nv[0] + a] ? a - x : -1;
                        ahead +=
                            behind > 0 && after > 0 && after < behind && !site[((size_t)z * nv[1] + y) * nv[0] + x];
                    }
            print_message("cells of %d voxels: %zu corners, %zu sites, %zu nearer a site ahead\n", f->cell, corners,
                          count, ahead);
            ahead_seen += ahead;
            free(site);
            free(sites);
        }
    assert_true(ahead_seen > 100); /* between the spheres */
    for (int i = 0; i < 2; i++)
        sdft_grid_free(grids[i]);
}

/* The far bound is continuous: points a hundredth of a voxel apart differ
 * by far less than a voxel (the tree bound jumps by the band at every tile
 * edge). The corner correction's square root is steep only right at cell
 * edges, so allow a few hundredths there. */
static void test_far_bound_is_continuous(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(128, &s);
    const float h = sdft_grid_voxel_size(g).x, step = 0.01f * h;
    tu_rng r = tu_rng_seed(7);
    int pairs = 0;
    for (int i = 0; i < 20000; i++) {
        sdft_vec3 p = sdft_v3(tu_uniform(&r, -1.8f, 1.8f), tu_uniform(&r, -1.8f, 1.8f), tu_uniform(&r, -1.8f, 1.8f));
        sdft_vec3 d = sdft_normalize(sdft_v3(tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)));
        int la, lb;
        float a = sdft_grid_sample(g, SDFT_GRID_BOUND_FAR, &s, p, &la),
              b = sdft_grid_sample(g, SDFT_GRID_BOUND_FAR, &s, sdft_madd(p, d, step), &lb);
        if (la != 5 || lb != 5)
            continue;
        pairs++;
        if (fabsf(a - b) > 0.25f * h)
            fail_msg("far bound jumps by %g over %g at (%g, %g, %g)", fabsf(a - b), step, p.x, p.y, p.z);
    }
    assert_true(pairs > 5000);
    sdft_grid_free(g);
}

/* 1 when the eight voxels of p's trilinear cell all lie in leaves of g's
 * tree (PNanoVDB's accessor, not the leaf directory), 0 when not, -1 when
 * p lies within 1e-3 voxel of a cell face (float rounding may pick the
 * neighbour). */
static int cell_in_leaves(const sdft_grid *g, sdft_vec3 p)
{
    double x[3];
    int32_t i0[3];
    for (int k = 0; k < 3; k++) {
        x[k] = (double)g->w2i[3 * k] * p.x + (double)g->w2i[3 * k + 1] * p.y + (double)g->w2i[3 * k + 2] * p.z +
               (double)g->w2i_t[k];
        i0[k] = (int32_t)floor(x[k]);
        if (x[k] - i0[k] < 1e-3 || x[k] - i0[k] > 1.0 - 1e-3)
            return -1;
    }
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(&acc, g->root);
    for (int k = 0; k < 8; k++) {
        pnanovdb_coord_t c = {i0[0] + (k & 1), i0[1] + (k >> 1 & 1), i0[2] + (k >> 2 & 1)};
        uint32_t level;
        pnanovdb_readaccessor_get_value_address_and_level(g->type, g->buf, &acc, &c, &level);
        if (level != 0)
            return 0;
    }
    return 1;
}

/* Inside leaves the default field is the trilinear value alone, the
 * background included: where the eight voxels of a point's cell lie in
 * leaves and the trilinear value there is the background, the FAR field
 * returns that very value at level 0, without the far bound (which used
 * to raise it in empty 4^3 cells of a leaf); outside leaves the far bound
 * still raises the field. */
static void test_far_bound_is_not_asked_in_leaves(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(128, &s);
    const float bg = sdft_grid_background(g);
    tu_rng r = tu_rng_seed(11);
    int at_background = 0, raised = 0;
    for (int i = 0; i < 200000; i++) {
        sdft_vec3 p = sdft_v3(tu_uniform(&r, -1.8f, 1.8f), tu_uniform(&r, -1.8f, 1.8f), tu_uniform(&r, -1.8f, 1.8f));
        int tree_level, far_level;
        const float tree = sdft_grid_sample(g, SDFT_GRID_BOUND_TREE, &s, p, &tree_level);
        const float far = sdft_grid_sample(g, SDFT_GRID_BOUND_FAR, &s, p, &far_level);
        const int in_leaves = cell_in_leaves(g, p);
        if (in_leaves == 1 && fabsf(tree) >= bg) {
            at_background++;
            if (far != tree || far_level != 0)
                fail_msg("in leaves at (%g, %g, %g): FAR %g (level %d), trilinear %g", p.x, p.y, p.z, far, far_level,
                         tree);
        }
        raised += in_leaves == 0 && far_level == 5 && fabsf(far) > fabsf(tree);
    }
    assert_true(at_background > 1000);
    assert_true(raised > 1000);
    sdft_grid_free(g);
}

/* No variant, with any bound, ever hits beyond the first sign change of the
 * grid's trilinear field along the ray, found by brute-force marching in
 * steps of a twentieth of a voxel. */
static void test_grid_trace_is_safe(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 96, 0, NULL);
    const float h = sdft_grid_voxel_size(g).x;
    sdft_field plain = sdft_grid_field(g, SDFT_GRID_BOUND_NONE);
    sdft_scratch s;
    sdft_scratch_init(&plain, &s);
    sdft_aabb b = sdft_grid_world_bounds(g);
    tu_rng r = tu_rng_seed(8);
    int hits = 0;
    for (int i = 0; i < 300; i++) {
        const sdft_ray ray = ray_into(b, 0.4f, &r);
        float t0, t1, first = INFINITY;
        if (sdft_aabb_clip(b, ray.org, ray.dir, ray.tnear, ray.tfar, &t0, &t1))
            for (float t = t0; t <= t1; t += 0.05f * h)
                if (plain.distance(plain.ctx, &s, sdft_madd(ray.org, ray.dir, t)) <= 0.0f) {
                    first = t;
                    break;
                }
        for (int bound = 0; bound < 3; bound++) {
            sdft_field gf = sdft_grid_field(g, (sdft_grid_bound)bound);
            for (int m = 0; m < SDFT_METHOD_COUNT; m++) {
                sdft_trace_params tp = sdft_trace_defaults();
                tp.method = (sdft_method)m;
                tp.omega = sdft_default_omega((sdft_method)m);
                sdft_hit hit = sdft_trace(&gf, &s, &ray, &tp);
                if (hit.status == SDFT_HIT && hit.t > first + 0.1f * h)
                    fail_msg("%s (bound %d) hits at t %g, beyond the first sign change at %g",
                             sdft_method_name(tp.method), bound, hit.t, first);
                if (isfinite(first) && hit.status == SDFT_MISS)
                    fail_msg("%s (bound %d) misses a ray that crosses the surface at t %g", sdft_method_name(tp.method),
                             bound, first);
                hits += hit.status == SDFT_HIT;
            }
        }
    }
    assert_true(hits > 300);
    sdft_grid_free(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tree_bound_never_exceeds_distance),
        cmocka_unit_test(test_tree_bound_on_a_scene),
        cmocka_unit_test(test_far_bound_never_exceeds_distance),
        cmocka_unit_test(test_far_bound_is_continuous),
        cmocka_unit_test(test_far_bound_is_not_asked_in_leaves),
        cmocka_unit_test(test_far_cells_from_directory_match_tree),
        cmocka_unit_test(test_far_corner_distances_match_brute_force),
        cmocka_unit_test(test_grid_trace_is_safe),
    };
    return cmocka_run_group_tests_name("grid_bound", tests, NULL, NULL);
}
