/* sdftrace — what the renderer's frame loop (render.c) and its hull
 * (render_hull.c) share: the tile and block sizes, a tile's ray
 * directions, and the hull's boxes binned to tiles. Internal header. */
#ifndef SDFTRACE_RENDER_HULL_H
#define SDFTRACE_RENDER_HULL_H

#include <stdint.h>

#include "sdftrace/camera.h"
#include "sdftrace/field.h"

enum { TILE = 16, BLOCK = 4 };

/* The unit directions of the primary rays through a tile's pixels, one
 * array per axis, pixel (x, y) of the tile whose first pixel is (tx, ty)
 * at (y - ty) * TILE + (x - tx): computed once per tile for the hull's
 * slab tests, the traces and the sky. */
typedef struct tile_dirs {
    float d[3][TILE * TILE];
} tile_dirs;

/* The field's hull boxes (sdft_field_accel.hull) that each tile's rays may
 * meet: tile t's are box[first[t] .. first[t + 1]), each with its pixel
 * rectangle rect[4 i .. 4 i + 3] (x0, y0, x1, y1, inclusive). */
typedef struct hull_bins {
    uint32_t *first, *box;
    int32_t *rect;
} hull_bins;

/* Bins the hull boxes of a (which has some) to the tiles of a width x
 * height image seen through v that they may cover, leaving out those whose
 * gradient bounds face away from the eye. 0, or -1 out of memory (then
 * free hb all the same). */
int render_hull_bin(const sdft_field_accel *a, const sdft_view *v, int width, int height, int threads, hull_bins *hb);
void render_hull_bins_free(hull_bins *hb);

/* Each pixel's span of the hull of a seen from the eye o: span[0][i],
 * span[1][i] the entry into the first box of tile `tile`'s bin that pixel
 * i's ray (direction td) meets and the exit from the last, or both INFINITY
 * when it meets none; where a gives slabs (hull_slabs), the part of the ray
 * in a box is the part also in its slab. Slab tests against the pixel's
 * own ray, as traced. Pixels [x0, x1) x [y0, y1) of the image. */
void render_hull_spans(const hull_bins *hb, const sdft_field_accel *a, sdft_vec3 o, int tile, const tile_dirs *td,
                       int x0, int y0, int x1, int y1, float (*span)[TILE * TILE]);

/* 1 when the eye is where field f is positive, so that each primary
 * ray's first root lies in the field's hull (field.h): outside the field's
 * box (its distance to it, tnear, > 0; the hull's promise covers rays that
 * enter it), or inside it where the field is > 0. */
int render_eye_outside(const sdft_field *f, sdft_vec3 eye, float tnear);

/* 1 when one of the tile's pixels [x0, x1) x [y0, y1) (tile coordinates)
 * has a span of the hull: the others are misses that need no trace. */
int render_block_meets_hull(float (*span)[TILE * TILE], int x0, int y0, int x1, int y1);

#endif
