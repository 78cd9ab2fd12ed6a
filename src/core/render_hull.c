/* sdftrace — the renderer's use of a field's hull (sdft_field_accel.hull):
 * binning its boxes to the tiles their screen rectangles touch, leaving out
 * those that face away from the eye, and each pixel's span of the boxes it
 * meets, by exact ray-box and ray-slab tests against the ray as traced
 * (render.c says how a frame uses them). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_hull.h"
#include "render_pixel.h"

/* The pixel rectangle (x0, y0, x1, y1, inclusive, clipped to the image)
 * that holds every pixel whose ray may meet box b, with a hundredth of a
 * pixel's margin for rounding; 0 when it is empty (b wholly behind the eye
 * or off the image). The projection of
 * a box wholly in front of the eye lies in that of its corners' hull. */
static int box_rect(const sdft_view *v, int width, int height, sdft_aabb b, int32_t r[4])
{
    const sdft_vec3 w =
        sdft_madd(sdft_madd(v->top_left, v->right_per_px, 0.5f * (float)width), v->down_per_px, 0.5f * (float)height);
    const float ra = sdft_dot(v->right_per_px, v->right_per_px), da = sdft_dot(v->down_per_px, v->down_per_px);
    float px0 = INFINITY, px1 = -INFINITY, py0 = INFINITY, py1 = -INFINITY;
    int behind = 0;
    for (int k = 0; k < 8; k++) {
        const sdft_vec3 q =
            sdft_sub(sdft_v3((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z), v->from);
        const float depth = sdft_dot(q, w);
        if (!(depth > 1e-6f * sdft_length(q))) {
            behind++;
            continue;
        }
        const float px = sdft_dot(q, v->right_per_px) / (depth * ra), py = sdft_dot(q, v->down_per_px) / (depth * da);
        px0 = sdft_minf(px0, px), px1 = sdft_maxf(px1, px);
        py0 = sdft_minf(py0, py), py1 = sdft_maxf(py1, py);
    }
    if (behind == 8)
        return 0;
    float x0 = -1.0f, y0 = -1.0f, x1 = (float)width, y1 = (float)height;
    if (!behind) { /* pixel x's centre is x + 1/2: x in [px0 - 1/2, px1 - 1/2], with a margin for rounding */
        const float m = 0.01f;
        x0 = sdft_maxf(x0, ceilf(px0 + 0.5f * (float)width - 0.5f - m)),
        x1 = sdft_minf(x1, floorf(px1 + 0.5f * (float)width - 0.5f + m));
        y0 = sdft_maxf(y0, ceilf(py0 + 0.5f * (float)height - 0.5f - m)),
        y1 = sdft_minf(y1, floorf(py1 + 0.5f * (float)height - 0.5f + m));
    }
    if (!(x0 <= x1 && y0 <= y1 && x0 <= (float)(width - 1) && y0 <= (float)(height - 1) && x1 >= 0.0f && y1 >= 0.0f))
        return 0; /* off the image (and no cast of a huge float below) */
    r[0] = x0 < 0.0f ? 0 : (int32_t)x0, r[1] = y0 < 0.0f ? 0 : (int32_t)y0;
    r[2] = x1 > (float)(width - 1) ? width - 1 : (int32_t)x1,
    r[3] = y1 > (float)(height - 1) ? height - 1 : (int32_t)y1;
    return r[0] <= r[2] && r[1] <= r[3];
}

/* 1 when no ray from the eye e can first reach 0 in box b, given that
 * the field's gradient there lies in the box g (sdft_field_accel.hull_gradients):
 * every ray that meets b does so at points p = e + t d, t > 0, and the
 * field rises along it there when d . grad > 0, that is (p - e) . grad >
 * 0. Over p in b and grad in g that product is, axis by axis, a product
 * of two intervals, whose least value is the least of its four corners';
 * the sum of those is a lower bound of (p - e) . grad. It must exceed its
 * rounding (each product's relative error 2^-24, the sum's a few times
 * that, of the terms' magnitude) with room to spare. An unbounded g gives
 * -inf or NaN terms: never away. */
static int faces_away(sdft_vec3 e, sdft_aabb b, sdft_aabb g)
{
    const float p0[3] = {b.lo.x - e.x, b.lo.y - e.y, b.lo.z - e.z}, p1[3] = {b.hi.x - e.x, b.hi.y - e.y, b.hi.z - e.z};
    const float g0[3] = {g.lo.x, g.lo.y, g.lo.z}, g1[3] = {g.hi.x, g.hi.y, g.hi.z};
    float least = 0.0f, size = 0.0f;
    for (int k = 0; k < 3; k++) {
        const float m = sdft_minf(sdft_minf(p0[k] * g0[k], p0[k] * g1[k]), sdft_minf(p1[k] * g0[k], p1[k] * g1[k]));
        least += m, size += fabsf(m);
    }
    return least > 1e-5f * size;
}

/* Bins the field's hull boxes to the tiles they may cover, leaving out
 * those whose gradient bounds face away from the eye (faces_away). 0, or
 * -1 out of memory. */
int render_hull_bin(const sdft_field_accel *a, const sdft_view *v, int width, int height, int threads, hull_bins *hb)
{
    const int tiles_x = (width + TILE - 1) / TILE, tiles = tiles_x * ((height + TILE - 1) / TILE);
    const size_t n = a->hull_count;
    hb->first = calloc((size_t)tiles + 1, sizeof *hb->first);
    hb->rect = malloc(4 * n * sizeof *hb->rect);
    if (!hb->first || !hb->rect)
        return -1;
    uint64_t total = 0;
#pragma omp parallel for schedule(static) reduction(+ : total) num_threads(threads)
    for (size_t i = 0; i < n; i++) {
        int32_t *r = hb->rect + 4 * i;
        if ((a->hull_gradients && faces_away(v->from, a->hull[i], a->hull_gradients[i])) ||
            !box_rect(v, width, height, a->hull[i], r)) {
            r[0] = 1, r[2] = 0;
            continue;
        }
        for (int ty = r[1] / TILE; ty <= r[3] / TILE; ty++)
            for (int tx = r[0] / TILE; tx <= r[2] / TILE; tx++) {
                __atomic_fetch_add(&hb->first[ty * tiles_x + tx + 1], 1u, __ATOMIC_RELAXED);
                total++;
            }
    }
    if (total > UINT32_MAX)
        return -1;
    for (int t = 0; t < tiles; t++)
        hb->first[t + 1] += hb->first[t];
    hb->box = malloc((total ? total : 1) * sizeof *hb->box);
    uint32_t *fill = malloc((size_t)tiles * sizeof *fill);
    if (!hb->box || !fill) {
        free(fill);
        return -1;
    }
    memcpy(fill, hb->first, (size_t)tiles * sizeof *fill);
#pragma omp parallel for schedule(static) num_threads(threads)
    for (size_t i = 0; i < n; i++) {
        const int32_t *r = hb->rect + 4 * i;
        if (r[0] > r[2])
            continue;
        for (int ty = r[1] / TILE; ty <= r[3] / TILE; ty++)
            for (int tx = r[0] / TILE; tx <= r[2] / TILE; tx++)
                hb->box[__atomic_fetch_add(&fill[ty * tiles_x + tx], 1u, __ATOMIC_RELAXED)] = (uint32_t)i;
    }
    free(fill);
    return 0;
}

void render_hull_bins_free(hull_bins *hb)
{
    free(hb->first), free(hb->box), free(hb->rect);
    *hb = (hull_bins){0};
}

/* Each pixel's span of the hull: span[0][i], span[1][i] the entry into the
 * first box of tile `tile`'s bin that pixel i's ray meets and the exit from
 * the last, or both INFINITY when it meets none; where the field gives
 * slabs (hull_slabs), the part of the ray in a box is the part also in its
 * slab. Slab tests against the pixel's own ray, as traced. */
void render_hull_spans(const hull_bins *hb, const sdft_field_accel *a, sdft_vec3 o, int tile, const tile_dirs *td,
                       int x0, int y0, int x1, int y1, float (*span)[TILE * TILE])
{
    const sdft_aabb *hull = a->hull;
    const sdft_slab *slabs = a->hull_slabs, everywhere = {{0.0f, 0.0f, 0.0f}, -INFINITY, INFINITY};
    float inv[3][TILE * TILE];
    for (int i = 0; i < TILE * TILE; i++)
        span[0][i] = INFINITY, span[1][i] = -INFINITY;
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < TILE * TILE; i++)
            inv[k][i] = render_slope(td->d[k][i]);
    for (uint32_t j = hb->first[tile]; j < hb->first[tile + 1]; j++) {
        const uint32_t b = hb->box[j];
        const int32_t *r = hb->rect + 4 * (size_t)b;
        const int rx0 = r[0] > x0 ? r[0] : x0, rx1 = r[2] < x1 - 1 ? r[2] : x1 - 1;
        const int ry0 = r[1] > y0 ? r[1] : y0, ry1 = r[3] < y1 - 1 ? r[3] : y1 - 1;
        const float lo[3] = {hull[b].lo.x - o.x, hull[b].lo.y - o.y, hull[b].lo.z - o.z};
        const float hi[3] = {hull[b].hi.x - o.x, hull[b].hi.y - o.y, hull[b].hi.z - o.z};
        const sdft_slab sl = slabs ? slabs[b] : everywhere;
        const float on = sdft_dot(sl.n, o), slo = sl.lo - on, shi = sl.hi - on; /* the slab from the eye */
        for (int y = ry0; y <= ry1; y++) {
            const int row = (y - y0) * TILE + (rx0 - x0); /* pixel rx0's index in the tile */
            float *restrict in = span[0] + row, *restrict out = span[1] + row;
            const float *restrict ix = inv[0] + row, *restrict iy = inv[1] + row, *restrict iz = inv[2] + row;
            const float *restrict dx = td->d[0] + row, *restrict dy = td->d[1] + row, *restrict dz = td->d[2] + row;
            for (int x = 0; x <= rx1 - rx0; x++)
                render_hull_box_span(lo, hi, sl.n, slo, shi, ix[x], iy[x], iz[x], dx[x], dy[x], dz[x], &in[x], &out[x]);
        }
    }
    for (int i = 0; i < TILE * TILE; i++)
        if (!(span[0][i] <= span[1][i]))
            span[0][i] = span[1][i] = INFINITY;
}

/* 1 when one of the tile's pixels [x0, x1) x [y0, y1) (tile coordinates)
 * has a span of the hull: the others are misses that need no trace. */
int render_block_meets_hull(float (*span)[TILE * TILE], int x0, int y0, int x1, int y1)
{
    int meets = 0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++)
            meets |= span[0][y * TILE + x] < INFINITY;
    return meets;
}

int render_eye_outside(const sdft_field *f, sdft_vec3 eye, float tnear)
{
    if (tnear > 0.0f)
        return 1;
    sdft_scratch s;
    sdft_scratch_init(f, &s);
    return sdft_field_distance(f, &s, eye) > 0.0f;
}
