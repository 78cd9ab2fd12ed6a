/* Fields, grids and brute-force truths for the grid's tests: a union of
 * spheres and its bake, a cell's stored values and a point's cell read
 * voxel by voxel, the trilinear interpolant and its gradient in double,
 * rays into a box, the points a render hinted at, and grids compared voxel
 * by voxel. */
#ifndef SDFT_TEST_GRID_SUPPORT_H
#define SDFT_TEST_GRID_SUPPORT_H

#include <stddef.h>
#include <stdint.h>

#include "sdftrace/field.h"
#include "sdftrace/grid.h"
#include "sdftrace/trace.h"
#include "sdftrace/vec3.h"
#include "testutil.h"

/* Union of spheres (centre, radius): exact outside every sphere, a bound
 * inside; its field over [-1.2, 1.2]^3. */
extern const float spheres[4][4];
sdft_field spheres_field(void);

/* f baked at res^3 (full: every voxel, not a narrow band), written to path
 * when not NULL; fails the test on an error. */
sdft_grid *bake(const sdft_field *f, int res, int full, const char *path);
/* The spheres baked at res^3, and s prepared for its default field. */
sdft_grid *spheres_grid_with_scratch(int res, sdft_scratch *s);

/* The eight stored values of the cell whose lowest corner is i0 (v[k]:
 * corner i0 + (k & 1, k >> 1 & 1, k >> 2 & 1)). */
void cell_corners(const sdft_grid *g, const int32_t i0[3], float v[8]);
/* World point p in index space, in double through the grid's transform. */
void index_point(const sdft_grid *g, sdft_vec3 p, double x[3]);
/* The world gradient of index gradient x: W^T x. */
void world_of_index_gradient(const sdft_grid *g, const double x[3], double w[3]);
/* The cell holding world point p: its lowest corner i0, p's coordinates u
 * in it and its eight values. */
void cell_at(const sdft_grid *g, sdft_vec3 p, int32_t i0[3], double u[3], float v[8]);

/* A ray from outside box b towards a random point of its middle. */
sdft_ray ray_into(sdft_aabb b, float spread, tu_rng *r);

/* The trilinear interpolant of v at cell-local u, in double. */
double trilinear_d(const float v[8], const double u[3]);
/* The world gradient of that interpolant at u by central differences;
 * returns its length. */
double interpolant_gradient(const sdft_grid *g, const float v[8], const double u[3], double world[3]);

/* The points sdft_render hinted at (sdft_field_accel.prefetch), one
 * thread: record_hint keeps the first MOST_HINTS, hint_count counts all. */
enum { MOST_HINTS = 1 << 16 };
extern sdft_vec3 hints[MOST_HINTS];
extern int hint_count;
void record_hint(const void *ctx, sdft_vec3 p);

/* The same index box, active voxels, background, and every voxel's value
 * and active state (the box and two voxels round it). */
void same_voxels(const sdft_grid *a, const sdft_grid *b);
/* The figure baked at res^3 into the .vdb at `name` (a temporary path in
 * path), then opened twice with quant: g[0] with options `first`, g[1]
 * with `second`. */
void open_figure_twice(const char *name, int res, sdft_quant quant, sdft_grid_options first, sdft_grid_options second,
                       char *path, size_t path_len, sdft_grid *g[2]);

#endif
