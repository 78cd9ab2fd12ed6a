/* Fields, grids and brute-force truths shared by the grid's tests
 * (grid_support.h). */
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
#include "sdftrace/scene.h"
#include "sdftrace/sdf.h"
#include "sdftrace/vdb.h"
#include "testutil.h"

/* ---- fields of our own ---------------------------------------------------- */

/* Union of spheres: exact outside every sphere, a bound inside. */
const float spheres[4][4] = {
    {0, 0, 0, 0.6f}, {0.7f, 0.2f, 0.1f, 0.35f}, {-0.5f, -0.4f, 0.3f, 0.3f}, {0.1f, 0.6f, -0.5f, 0.25f}};

static float spheres_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    float d = INFINITY;
    for (int i = 0; i < 4; i++)
        d = fminf(d, sdft_length(sdft_sub(p, sdft_v3(spheres[i][0], spheres[i][1], spheres[i][2]))) - spheres[i][3]);
    return d;
}

sdft_field spheres_field(void)
{
    return (sdft_field){.distance = spheres_distance, .bounds = {{-1.2f, -1.2f, -1.2f}, {1.2f, 1.2f, 1.2f}}};
}

sdft_grid *bake(const sdft_field *f, int res, int full, const char *path)
{
    sdft_bake_params p = sdft_bake_defaults();
    p.res = res;
    p.full = full;
    sdft_grid *g = NULL;
    char msg[256] = "";
    int rc = sdft_bake(f, &p, path, &g, NULL, msg, sizeof msg);
    if (rc)
        print_error("bake: %s\n", msg);
    assert_int_equal(rc, 0);
    assert_non_null(g);
    return g;
}

/* The spheres baked at res^3, and s prepared for its default field. */
sdft_grid *spheres_grid_with_scratch(int res, sdft_scratch *s)
{
    sdft_field f = spheres_field();
    sdft_grid *g = bake(&f, res, 0, NULL);
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_scratch_init(&gf, s);
    return g;
}

/* The eight stored values of the cell whose lowest corner is i0, voxel by
 * voxel through the public accessor (v[k]: corner i0 + (k & 1, k >> 1 & 1,
 * k >> 2 & 1)). */
void cell_corners(const sdft_grid *g, const int32_t i0[3], float v[8])
{
    for (int k = 0; k < 8; k++)
        v[k] = sdft_grid_voxel(g, i0[0] + (k & 1), i0[1] + (k >> 1 & 1), i0[2] + (k >> 2 & 1), NULL);
}

/* World point p in index space, in double through the grid's transform. */
void index_point(const sdft_grid *g, sdft_vec3 p, double x[3])
{
    for (int k = 0; k < 3; k++)
        x[k] = (double)g->w2i[3 * k] * p.x + (double)g->w2i[3 * k + 1] * p.y + (double)g->w2i[3 * k + 2] * p.z +
               (double)g->w2i_t[k];
}

/* The world gradient of index gradient x: W^T x (d/dp f(W p + t)). */
void world_of_index_gradient(const sdft_grid *g, const double x[3], double w[3])
{
    for (int k = 0; k < 3; k++)
        w[k] = g->w2i[k] * x[0] + g->w2i[3 + k] * x[1] + g->w2i[6 + k] * x[2];
}

/* The cell holding world point p, in double through the grid's transform:
 * its lowest corner i0, p's coordinates u in it and its eight values. */
void cell_at(const sdft_grid *g, sdft_vec3 p, int32_t i0[3], double u[3], float v[8])
{
    double x[3];
    index_point(g, p, x);
    for (int k = 0; k < 3; k++) {
        i0[k] = (int32_t)floor(x[k]);
        u[k] = x[k] - i0[k];
    }
    cell_corners(g, i0, v);
}

/* A ray from outside box b towards a random point of its middle (within
 * `spread` of the box's size of the centre), in a random direction. */
sdft_ray ray_into(sdft_aabb b, float spread, tu_rng *r)
{
    const sdft_vec3 c = sdft_scale(sdft_add(b.lo, b.hi), 0.5f), e = sdft_sub(b.hi, b.lo);
    const float reach = 2.0f * sdft_length(e);
    sdft_vec3 dir = sdft_normalize(sdft_v3(tu_uniform(r, -1, 1), tu_uniform(r, -1, 1), tu_uniform(r, -1, 1)));
    sdft_vec3 aim = sdft_v3(c.x + tu_uniform(r, -spread, spread) * e.x, c.y + tu_uniform(r, -spread, spread) * e.y,
                            c.z + tu_uniform(r, -spread, spread) * e.z);
    return (sdft_ray){.org = sdft_madd(aim, dir, -reach), .tnear = 0.0f, .dir = dir, .tfar = 2.0f * reach};
}

/* The trilinear interpolant of v at cell-local u, in double: the truth the
 * cubic root finder is held to. */
double trilinear_d(const float v[8], const double u[3])
{
    double f = 0.0;
    for (int k = 0; k < 8; k++)
        f += v[k] * ((k & 1) ? u[0] : 1.0 - u[0]) * ((k >> 1 & 1) ? u[1] : 1.0 - u[1]) *
             ((k >> 2 & 1) ? u[2] : 1.0 - u[2]);
    return f;
}

/* The world gradient of the interpolant of cell values v at cell-local u
 * (which may lie a little outside the cell: the cell's own polynomial), by
 * central differences in double, exact up to rounding as the interpolant
 * is linear along each axis; returns its length. */
double interpolant_gradient(const sdft_grid *g, const float v[8], const double u[3], double world[3])
{
    double grad[3];
    for (int k = 0; k < 3; k++) {
        double a[3] = {u[0], u[1], u[2]}, b[3] = {u[0], u[1], u[2]};
        a[k] += 1e-3, b[k] -= 1e-3;
        grad[k] = (trilinear_d(v, a) - trilinear_d(v, b)) / 2e-3;
    }
    world_of_index_gradient(g, grad, world);
    return sqrt(world[0] * world[0] + world[1] * world[1] + world[2] * world[2]);
}

/* The points sdft_render hinted at (sdft_field_accel.prefetch), one thread. */
sdft_vec3 hints[MOST_HINTS];
int hint_count;

void record_hint(const void *ctx, sdft_vec3 p)
{
    (void)ctx;
    if (hint_count < MOST_HINTS)
        hints[hint_count] = p;
    hint_count++;
}

void same_voxels(const sdft_grid *a, const sdft_grid *b)
{
    int32_t lo[3], hi[3], lo2[3], hi2[3];
    sdft_grid_index_bounds(a, lo, hi);
    sdft_grid_index_bounds(b, lo2, hi2);
    assert_memory_equal(lo, lo2, sizeof lo);
    assert_memory_equal(hi, hi2, sizeof hi);
    assert_int_equal(sdft_grid_active_voxels(a), sdft_grid_active_voxels(b));
    assert_true(sdft_grid_background(a) == sdft_grid_background(b));
    for (int32_t k = lo[2] - 2; k <= hi[2] + 2; k++)
        for (int32_t j = lo[1] - 2; j <= hi[1] + 2; j++)
            for (int32_t i = lo[0] - 2; i <= hi[0] + 2; i++) {
                int aa, ab;
                float va = sdft_grid_voxel(a, i, j, k, &aa), vb = sdft_grid_voxel(b, i, j, k, &ab);
                if (va != vb || aa != ab)
                    fail_msg("voxel (%d, %d, %d): %g/%d in memory, %g/%d from the file", i, j, k, va, aa, vb, ab);
            }
}

/* The figure baked at res^3 into the .vdb at `name` (a temporary path in
 * path), then opened twice with quant: g[0] with options `first`, g[1]
 * with `second`. */
void open_figure_twice(const char *name, int res, sdft_quant quant, sdft_grid_options first, sdft_grid_options second,
                       char *path, size_t path_len, sdft_grid *g[2])
{
    char msg[256];
    tu_tmp(path, path_len, name);
    if (!tu_file_exists(path)) {
        const sdft_scene *sc = sdft_scene_find("figure");
        assert_non_null(sc);
        sdft_grid_free(bake(&sc->field, res, 0, path));
    }
    const sdft_grid_options o[2] = {first, second};
    for (int k = 0; k < 2; k++) {
        sdft_grid_options ok = o[k];
        ok.quant = quant;
        const int rc = tu_open_with(path, NULL, &ok, &g[k], msg, sizeof msg);
        if (rc)
            print_error("%s\n", msg);
        assert_int_equal(rc, 0);
    }
}
