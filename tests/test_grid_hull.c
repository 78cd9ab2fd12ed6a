/* sdftrace tests — a grid's hull (src/grid/grid_hull.c): every first root
 * found by brute-force marching lies in it, and a render started at it (and
 * hinted at its entries) gives the image rendered from the eye. */
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

/* ---- the hull ---------------------------------------------------------------------- */

/* p in hull box i and, where the field gives slabs, in slab i. */
static int in_hull_part(const sdft_field *f, size_t i, sdft_vec3 p)
{
    const sdft_aabb b = f->accel->hull[i];
    if (!(p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z && p.z <= b.hi.z))
        return 0;
    if (!f->accel->hull_slabs)
        return 1;
    const sdft_slab sl = f->accel->hull_slabs[i];
    const float d = sdft_dot(sl.n, p);
    return d >= sl.lo && d <= sl.hi;
}

/* The least of d . g over g in hull box i's gradient bounds: > 0 when a
 * ray along d rises wherever it crosses the box's cells. */
static float least_slope(const sdft_field *f, size_t i, sdft_vec3 d)
{
    const sdft_aabb gb = f->accel->hull_gradients[i];
    return fminf(d.x * gb.lo.x, d.x * gb.hi.x) + fminf(d.y * gb.lo.y, d.y * gb.hi.y) +
           fminf(d.z * gb.lo.z, d.z * gb.hi.z);
}

/* p in a part of the hull (box and slab) where a ray along d may first
 * reach 0: one whose gradient bounds do not rise along d. */
static int in_hull(const sdft_field *f, sdft_vec3 p, sdft_vec3 d)
{
    for (size_t i = 0; i < f->accel->hull_count; i++)
        if (in_hull_part(f, i, p) && !(least_slope(f, i, d) > 0.0f))
            return 1;
    return 0;
}

/* World gradient g (index gradient x through the grid's transform: W^T x)
 * in hull box i's gradient bounds, to a millionth of their size. */
static int in_gradient_bounds(const sdft_grid *g, const sdft_field *f, size_t i, const double x[3])
{
    const sdft_aabb gb = f->accel->hull_gradients[i];
    const float lo[3] = {gb.lo.x, gb.lo.y, gb.lo.z}, hi[3] = {gb.hi.x, gb.hi.y, gb.hi.z};
    double w[3];
    world_of_index_gradient(g, x, w);
    for (int k = 0; k < 3; k++) {
        const double slack = 1e-6 * (fabs(lo[k]) + fabs(hi[k]));
        if (!(w[k] >= lo[k] - slack && w[k] <= hi[k] + slack))
            return 0;
    }
    return 1;
}

/* Cells with corners of both signs, at random in g's active box: all
 * eight corners of each lie in one box of the hull and its slab, and the
 * box's gradient bounds hold every gradient of the cell's interpolant
 * (along each index axis the derivative lies between the least and the
 * greatest of that axis's four edge differences, so every gradient lies in
 * their box, whose eight corners, taken to world space, must lie in the
 * bounds). The slabs' mean thickness, in voxels; *narrow: the share of
 * boxes whose gradient bounds leave out 0 (those a view can drop). */
static double mixed_cells_in_hull(const sdft_grid *g, const sdft_field *f, int tries, int *mixed, double *narrow)
{
    int32_t lo[3], hi[3];
    sdft_grid_index_bounds(g, lo, hi);
    tu_rng r = tu_rng_seed(43);
    *mixed = 0;
    for (int i = 0; i < tries; i++) {
        int32_t c[3];
        for (int k = 0; k < 3; k++)
            c[k] = lo[k] + (int32_t)(tu_uniform(&r, 0.0f, 0.999f) * (float)(hi[k] - lo[k]));
        float v[8];
        cell_corners(g, c, v);
        int neg = 0;
        for (int k = 0; k < 8; k++)
            neg += v[k] <= 0.0f;
        if (neg == 0 || neg == 8)
            continue;
        (*mixed)++;
        sdft_vec3 w[8];
        for (int k = 0; k < 8; k++) {
            const float x[3] = {(float)(c[0] + (k & 1)), (float)(c[1] + (k >> 1 & 1)), (float)(c[2] + (k >> 2 & 1))};
            w[k] = grid_index_to_world(g, x);
        }
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int k = 0; k < 8; k++)
            for (int a = 0; a < 3; a++) {
                const int step = 1 << a;
                if (k & step)
                    continue;
                const double e = (double)v[k + step] - (double)v[k];
                lo[a] = fmin(lo[a], e), hi[a] = fmax(hi[a], e);
            }
        int held = 0;
        for (size_t b = 0; b < f->accel->hull_count && !held; b++) {
            held = 1;
            for (int k = 0; k < 8 && held; k++)
                held = in_hull_part(f, b, w[k]);
            for (int k = 0; k < 8 && held; k++) {
                const double x[3] = {k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]};
                held = in_gradient_bounds(g, f, b, x);
            }
        }
        if (!held)
            fail_msg("mixed cell (%d, %d, %d) lies in no hull box and its slab with its gradients", c[0], c[1], c[2]);
    }
    size_t without_zero = 0;
    for (size_t b = 0; b < f->accel->hull_count; b++) {
        const sdft_aabb gb = f->accel->hull_gradients[b];
        without_zero +=
            gb.lo.x > 0.0f || gb.hi.x < 0.0f || gb.lo.y > 0.0f || gb.hi.y < 0.0f || gb.lo.z > 0.0f || gb.hi.z < 0.0f;
    }
    *narrow = (double)without_zero / (double)f->accel->hull_count;
    double thick = 0.0;
    size_t slabs = 0;
    const float h = sdft_grid_voxel_size(g).x;
    for (size_t b = 0; b < f->accel->hull_count; b++) {
        const sdft_slab sl = f->accel->hull_slabs[b];
        const float n = sdft_length(sl.n);
        if (n > 0.0f && isfinite(sl.hi - sl.lo))
            thick += (sl.hi - sl.lo) / n / h, slabs++;
    }
    return slabs ? thick / (double)slabs : INFINITY;
}

/* A slab 0.6 thick, much wider than its box, which cuts it on four sides:
 * the grid holds values <= 0 (leaves and tiles) against the background
 * outside. */
static float cut_slab_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    return sdft_sd_box(p, sdft_v3(2.0f, 0.3f, 2.0f));
}

/* Every ray's first root of the interpolant, found by brute-force marching
 * in steps of a twentieth of a voxel from where the ray enters the grid's
 * box, lies in a box of the grid's hull: on the figure, whose hull is a
 * thin shell, not the box, and on a slab its box cuts, where the first
 * roots of rays entering through the cut faces are their entry points. */
static void test_hull_holds_every_first_root(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    const sdft_field slab = {.distance = cut_slab_distance, .bounds = {{-0.5f, -0.4f, -0.5f}, {0.5f, 0.4f, 0.5f}}};
    sdft_grid *grids[2] = {bake(&sc->field, 96, 0, NULL), bake(&slab, 128, 0, NULL)};
    for (int gi = 0; gi < 2; gi++) {
        sdft_grid *g = grids[gi];
        const float h = sdft_grid_voxel_size(g).x;
        const sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
        assert_true(gf.accel->hull_count > 100);
        const sdft_aabb bounds = sdft_grid_world_bounds(g);
        double hull_volume = 0.0;
        for (size_t i = 0; i < gf.accel->hull_count; i++) {
            const sdft_vec3 e = sdft_sub(gf.accel->hull[i].hi, gf.accel->hull[i].lo);
            hull_volume += (double)e.x * e.y * e.z;
        }
        const sdft_vec3 be = sdft_sub(bounds.hi, bounds.lo);
        print_message("%s: %zu hull boxes, %.1f%% of the box's volume\n", gi ? "cut slab" : "figure",
                      gf.accel->hull_count, 100.0 * hull_volume / ((double)be.x * be.y * be.z));
        if (gi == 0) {
            assert_true(hull_volume < 0.25 * (double)be.x * be.y * be.z);
            assert_non_null(gf.accel->hull_slabs);
            assert_non_null(gf.accel->hull_gradients);
            int mixed;
            double narrow;
            const double thick = mixed_cells_in_hull(g, &gf, 200000, &mixed, &narrow);
            print_message("%d mixed cells, each in a hull box and its slab with its gradients; slabs %.2f voxels "
                          "thick on average; %.1f%% of the gradient bounds leave out 0\n",
                          mixed, thick, 100.0 * narrow);
            assert_true(mixed > 1000);
            assert_true(thick < 5.0);
            assert_true(narrow > 0.3); /* a coarse grid: leaves of 8 voxels hold much of its curvature */
        }
        sdft_scratch s;
        sdft_scratch_init(&gf, &s);
        tu_rng r = tu_rng_seed(41);
        int roots = 0, at_entry = 0;
        for (int i = 0; i < 600; i++) {
            const sdft_ray ray = ray_into(bounds, 0.4f, &r);
            float t0, t1;
            if (!sdft_aabb_clip(bounds, ray.org, ray.dir, 0.0f, ray.tfar, &t0, &t1))
                continue;
            for (float t = t0; t <= t1; t += 0.05f * h) {
                const sdft_vec3 p = sdft_madd(ray.org, ray.dir, t);
                if (sdft_grid_sample(g, SDFT_GRID_BOUND_NONE, &s, p, NULL) <= 0.0f) {
                    if (!in_hull(&gf, p, ray.dir))
                        fail_msg("ray %d: first root near t = %g, (%g, %g, %g), in no hull box that may hold it", i, t,
                                 p.x, p.y, p.z);
                    roots++;
                    at_entry += t == t0;
                    break;
                }
            }
        }
        print_message("%d first roots (%d where the ray enters the box), all in the hull\n", roots, at_entry);
        assert_true(roots > 200);
        if (gi == 1)
            assert_true(at_entry > 50);
        sdft_grid_free(g);
    }
}

/* The default render starts each primary ray at the hull: the same image
 * as with every ray from the eye (cones off), exact roots included, for
 * fewer evaluations, and the same as with every box of the hull (its far
 * side's too, which the gradient bounds leave out); with the eye inside the surface, where the hull
 * promises nothing, the same image too (every ray hits at the eye); and
 * through a lens so narrow that every box projects billions of pixels off
 * the image, nothing hit and nothing written outside the tiles' bins. */
static void test_render_from_the_hull(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 128, 0, NULL);
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    const float h = sdft_grid_voxel_size(g).x;
    sdft_render_params rp = sdft_render_defaults();
    rp.width = 160, rp.height = 90;
    rp.camera = sc->camera;
    rp.shadows = 0, rp.depth_only = 1;
    for (int view = 0; view < 3; view++) {
        const int inside = view == 1;
        if (view == 2) { /* 80 degrees to the left through a 1e-5-degree lens: every box in front, billions of
                          * pixels to the right of the image */
            const sdft_vec3 d = sdft_normalize(sdft_sub(sc->camera.at, sc->camera.from));
            const sdft_vec3 left = sdft_normalize(sdft_cross(sc->camera.up, d));
            rp.camera = sc->camera, rp.camera.fov_deg = 1e-5f;
            rp.camera.at = sdft_add(rp.camera.from, sdft_add(sdft_scale(d, 0.17f), sdft_scale(left, 0.98f)));
        }
        if (inside) { /* a point of the figure's interior, found by the field itself */
            sdft_scratch s;
            sdft_scratch_init(&gf, &s);
            tu_rng r = tu_rng_seed(43);
            sdft_vec3 p;
            do
                p = sdft_v3(tu_uniform(&r, gf.bounds.lo.x, gf.bounds.hi.x),
                            tu_uniform(&r, gf.bounds.lo.y, gf.bounds.hi.y),
                            tu_uniform(&r, gf.bounds.lo.z, gf.bounds.hi.z));
            while (!(sdft_field_distance(&gf, &s, p) < -2.0f * h));
            rp.camera.from = p;
        }
        sdft_image a, b;
        sdft_render_stats sa, sb;
        char msg[256];
        assert_int_equal(sdft_image_alloc(&a, rp.width, rp.height, NULL, 0), 0);
        assert_int_equal(sdft_image_alloc(&b, rp.width, rp.height, NULL, 0), 0);
        assert_int_equal(sdft_render(&gf, &rp, &a, &sa, msg, sizeof msg), 0);
        sdft_render_params off = rp;
        off.cones = 0;
        assert_int_equal(sdft_render(&gf, &off, &b, &sb, msg, sizeof msg), 0);
        int n = rp.width * rp.height, hits = 0, same = 0, differ = 0;
        for (int i = 0; i < n; i++) {
            if ((a.status[i] == SDFT_HIT) != (b.status[i] == SDFT_HIT)) {
                differ++;
                continue;
            }
            if (a.status[i] != SDFT_HIT)
                continue;
            hits++;
            same += fabsf(a.depth[i] - b.depth[i]) <= 1e-3f * h;
        }
        print_message("%s: %d hits, %d at the same depth, %d hit in one only; evaluations %llu against %llu\n",
                      view == 0   ? "eye outside"
                      : view == 1 ? "eye inside"
                                  : "looking aside",
                      hits, same, differ, (unsigned long long)(sa.steps + sa.cone_steps), (unsigned long long)sb.steps);
        assert_true(view == 2 ? hits == 0 : hits > n / (inside ? 1 : 10) - 1);
        assert_true(same >= 0.995 * hits);
        assert_true(differ <= n / 1000);
        if (view == 0) {
            assert_true(2 * (sa.steps + sa.cone_steps) < sb.steps);
            /* Without the gradient bounds every box of the hull counts, the
             * far side's too: the same image, no fewer evaluations. */
            sdft_field all_boxes = gf;
            sdft_field_accel no_gradients = *gf.accel;
            no_gradients.hull_gradients = NULL;
            all_boxes.accel = &no_gradients;
            assert_int_equal(sdft_render(&all_boxes, &rp, &b, &sb, msg, sizeof msg), 0);
            int changed = 0;
            for (int i = 0; i < n; i++)
                changed += a.status[i] != b.status[i] || (a.status[i] == SDFT_HIT && a.depth[i] != b.depth[i]);
            print_message("without the gradient bounds: %d pixels differ; evaluations %llu against %llu\n", changed,
                          (unsigned long long)sb.steps, (unsigned long long)sa.steps);
            assert_int_equal(changed, 0);
            assert_true(sa.steps <= sb.steps);
        }
        sdft_image_free(&a);
        sdft_image_free(&b);
    }
    sdft_grid_free(g);
}

/* The distance from p to the nearest face of a hull box's part (the box
 * and its slab) that holds it (INFINITY when none does). */
static float hull_face_distance(const sdft_field *f, sdft_vec3 p)
{
    float best = INFINITY;
    for (size_t i = 0; i < f->accel->hull_count; i++) {
        const sdft_aabb b = f->accel->hull[i];
        const sdft_vec3 in = sdft_min_v(sdft_sub(p, b.lo), sdft_sub(b.hi, p));
        float depth = sdft_minf(in.x, sdft_minf(in.y, in.z));
        if (f->accel->hull_slabs && sdft_length(f->accel->hull_slabs[i].n) > 0.0f) {
            const sdft_slab sl = f->accel->hull_slabs[i];
            const float d = sdft_dot(sl.n, p), n = sdft_length(sl.n);
            depth = sdft_minf(depth, sdft_minf(d - sl.lo, sl.hi - d) / n);
        }
        if (depth >= -1e-5f)
            best = sdft_minf(best, fabsf(depth));
    }
    return best;
}

/* With the hull, the render hints the field at each traced ray's entry
 * into it: every hit pixel's ray has a hinted point on it, on a hull box's
 * face, before its hit; and the image is the one rendered without hints. */
static void test_render_hints_hull_entries(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 128, 0, NULL);
    const sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_field hinted = gf, plain = gf;
    sdft_field_accel hinting = *gf.accel, silent = *gf.accel;
    hinting.prefetch = record_hint, silent.prefetch = NULL;
    hinted.accel = &hinting, plain.accel = &silent;
    const float h = sdft_grid_voxel_size(g).x;
    sdft_render_params rp = sdft_render_defaults();
    rp.width = 96, rp.height = 54, rp.threads = 1;
    rp.camera = sc->camera;
    rp.shadows = 0;
    sdft_image a, b;
    char msg[256];
    assert_int_equal(sdft_image_alloc(&a, rp.width, rp.height, NULL, 0), 0);
    assert_int_equal(sdft_image_alloc(&b, rp.width, rp.height, NULL, 0), 0);
    hint_count = 0;
    assert_int_equal(sdft_render(&hinted, &rp, &a, NULL, msg, sizeof msg), 0);
    assert_int_equal(sdft_render(&plain, &rp, &b, NULL, msg, sizeof msg), 0);
    assert_true(hint_count > 0 && hint_count <= MOST_HINTS);
    const int n = rp.width * rp.height;
    assert_memory_equal(a.rgb, b.rgb, 3 * (size_t)n * sizeof *a.rgb);
    assert_memory_equal(a.depth, b.depth, (size_t)n * sizeof *a.depth);
    int hits = 0;
    for (int i = 0; i < n; i++) {
        if (a.status[i] != SDFT_HIT)
            continue;
        hits++;
        const sdft_ray ray = sdft_camera_ray(&rp.camera, rp.width, rp.height, (float)(i % rp.width) + 0.5f,
                                             (float)(i / rp.width) + 0.5f);
        int found = 0;
        for (int k = 0; k < hint_count && !found; k++) {
            const sdft_vec3 q = sdft_sub(hints[k], ray.org);
            const float t = sdft_dot(q, ray.dir);
            found = sdft_length(sdft_cross(q, ray.dir)) <= 1e-4f * h && t <= a.depth[i] &&
                    hull_face_distance(&gf, hints[k]) <= 1e-3f * h;
        }
        if (!found)
            fail_msg("pixel %d: no hint at its ray's entry into the hull", i);
    }
    print_message("%d hints, %d hit pixels, each hinted at its entry\n", hint_count, hits);
    assert_true(hits > n / 10);
    assert_true(hint_count < 2 * n);
    sdft_image_free(&a);
    sdft_image_free(&b);
    sdft_grid_free(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hull_holds_every_first_root),
        cmocka_unit_test(test_render_from_the_hull),
        cmocka_unit_test(test_render_hints_hull_entries),
    };
    return cmocka_run_group_tests_name("grid_hull", tests, NULL, NULL);
}
