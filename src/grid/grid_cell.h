/* sdftrace — reading a grid's voxel cells, shared by the sampler
 * (grid_sample.c) and the exact last-cell root (grid_root.c): world to
 * index, one stored value through the read accessor, the eight corners of
 * a trilinear cell through the leaf directory (grid_directory.h). Internal
 * header; every helper inlines, so a caller specialised on a grid type
 * keeps no branch on it. */
#ifndef SDFTRACE_GRID_CELL_H
#define SDFTRACE_GRID_CELL_H

#include <math.h>

#include "grid_directory.h"

_Static_assert(sizeof(pnanovdb_readaccessor_t) <= SDFT_SCRATCH_BYTES, "a read accessor must fit a thread's scratch");

static inline pnanovdb_readaccessor_t *accessor(sdft_scratch *s) { return (pnanovdb_readaccessor_t *)(void *)s->bytes; }

/* A deferred grid's leaf at byte `at`, holding voxel ijk, filled if it is
 * not yet (grid_deferred.c); nothing for a grid loaded whole, or for an
 * address that is not one of its leaves (a corrupt child offset is then
 * read as it stands, as in any grid, never filled out of place). */
GRID_INLINE void grid_leaf_ready(const sdft_grid *g, uint64_t at, pnanovdb_coord_t ijk)
{
    const grid_deferred *d = &g->deferred;
    if (!d->state)
        return;
    const uint64_t i = deferred_leaf_index(d, at);
    if (i < d->count && __atomic_load_n(&d->state[i], __ATOMIC_ACQUIRE) != LEAF_READY)
        grid_leaf_fill(g, at, ijk);
}

/* The stored value at voxel ijk and the tree level it came from
 * (0 leaf, 1 lower-node tile, 2 upper-node tile, 3 root tile, 4 background).
 * `type` is g->type, or a constant where the caller is specialised. */
GRID_INLINE float read_value(const sdft_grid *g, pnanovdb_grid_type_t type, pnanovdb_readaccessor_t *acc,
                             pnanovdb_coord_t ijk, uint32_t *level)
{
    pnanovdb_address_t a = pnanovdb_readaccessor_get_value_address_and_level(type, g->buf, acc, &ijk, level);
    if (*level == 0)
        grid_leaf_ready(g, acc->leaf.address.byte_offset, ijk);
    switch (type) {
    case PNANOVDB_GRID_TYPE_FLOAT:
        return pnanovdb_read_float(g->buf, a);
    case PNANOVDB_GRID_TYPE_DOUBLE:
        return (float)pnanovdb_read_double(g->buf, a);
    case PNANOVDB_GRID_TYPE_FP16:
        return pnanovdb_root_fp16_read_float(g->buf, a, &ijk, *level);
    case PNANOVDB_GRID_TYPE_FP8:
        return pnanovdb_root_fp8_read_float(g->buf, a, &ijk, *level);
    case PNANOVDB_GRID_TYPE_FP4:
        return pnanovdb_root_fp4_read_float(g->buf, a, &ijk, *level);
    default:
        return pnanovdb_root_fpn_read_float(g->buf, a, &ijk, *level);
    }
}

/* World to index. `diagonal` (g->diagonal, or a constant): the matrix is a
 * diagonal scale, whose products with 0 the full form would add. */
GRID_INLINE void to_index(const sdft_grid *g, int diagonal, sdft_vec3 p, float x[3])
{
    const float *m = g->w2i;
    if (diagonal) {
        x[0] = m[0] * p.x + g->w2i_t[0];
        x[1] = m[4] * p.y + g->w2i_t[1];
        x[2] = m[8] * p.z + g->w2i_t[2];
        return;
    }
    x[0] = m[0] * p.x + m[1] * p.y + m[2] * p.z + g->w2i_t[0];
    x[1] = m[3] * p.x + m[4] * p.y + m[5] * p.z + g->w2i_t[1];
    x[2] = m[6] * p.x + m[7] * p.y + m[8] * p.z + g->w2i_t[2];
}

/* floor(x) for |x| < 2^31 (callers check): floorf is a libm call on
 * baseline x86-64. Truncation is exact, and steps down below 0. */
static inline int32_t ifloor(float x)
{
    const int32_t i = (int32_t)x;
    return i - (x < (float)i);
}

static inline float lerp(float a, float b, float t) { return a + (b - a) * t; }

static inline float word_float(const sdft_grid *g, uint32_t w)
{
    return pnanovdb_read_float(g->buf, (pnanovdb_address_t){4u * w});
}

/* Value n (64 x + 8 y + z) of the leaf whose value table starts at word w:
 * a float, or a code of 16, 8 or 4 bits times the leaf's quantum plus its
 * minimum, the two floats before the table (pnanovdb_leaf_fp_read_float,
 * the same arithmetic). */
GRID_INLINE float leaf_value(const sdft_grid *g, pnanovdb_grid_type_t type, uint32_t w, uint32_t n)
{
    uint32_t code;
    switch (type) {
    case PNANOVDB_GRID_TYPE_FLOAT:
        return word_float(g, w + n);
    case PNANOVDB_GRID_TYPE_FP16:
        code = g->words[w + (n >> 1)] >> ((n & 1u) << 4) & 0xFFFFu;
        break;
    case PNANOVDB_GRID_TYPE_FP8:
        code = g->words[w + (n >> 2)] >> ((n & 3u) << 3) & 0xFFu;
        break;
    default: /* FP4 */
        code = g->words[w + (n >> 3)] >> ((n & 7u) << 2) & 0xFu;
        break;
    }
    return (float)code * word_float(g, w - 3u) + word_float(g, w - 4u);
}

/* The value of entry w of the directory at leaf offset n: from the leaf,
 * or the tile's +-background (w a tile marker). */
GRID_INLINE float entry_value(const sdft_grid *g, pnanovdb_grid_type_t type, uint32_t w, uint32_t n)
{
    if (w < GRID_TILE_MARKERS)
        return w == GRID_TILE_POSITIVE ? g->background : -g->background;
    return leaf_value(g, type, w, n);
}

/* The eight values of the cell whose lowest corner is i0 (v[k]: corner
 * i0 + (k & 1, k >> 1 & 1, k >> 2 & 1)), read through the leaf directory
 * (grid_leaves.c); 0 when a corner lies in no block the directory knows
 * (the accessor's path then). With `tiles` NULL only leaves count as
 * known; else tiles of +-background do too, and *tiles gets bit k set
 * for each corner k that came from one. Per axis the cell's two voxel
 * layers are the same block at offsets o and o + 1, or, when o = 7, two
 * blocks at offsets 7 and 0, the second in the chunk's apron; a value sits
 * at 64, 8 and 1 entries per x, y and z offset in its leaf. */
GRID_INLINE int cell_from_leaves(const sdft_grid *g, pnanovdb_grid_type_t type, pnanovdb_coord_t i0, float v[8],
                                 uint32_t *tiles)
{
    const grid_leaves *d = &g->leaves;
    const int32_t c[3] = {i0.x, i0.y, i0.z};
    const uint32_t lowest = tiles ? GRID_TILE_POSITIVE : GRID_TILE_MARKERS; /* entries below are unknown */
    uint32_t local;
    const uint32_t *e = directory_chunk(d, c, &local);
    if (!e)
        return 0;
    const uint32_t ox = (uint32_t)c[0] & 7u, oy = (uint32_t)c[1] & 7u, oz = (uint32_t)c[2] & 7u;
    if (ox != 7u && oy != 7u && oz != 7u) { /* the whole cell in one block: two of every three cells */
        const uint32_t w = e[local];
        if (w < lowest)
            return 0;
        if (w < GRID_TILE_MARKERS) {
            for (int k = 0; k < 8; k++)
                v[k] = w == GRID_TILE_POSITIVE ? g->background : -g->background;
            *tiles = 0xFFu;
            return 1;
        }
        const uint32_t n = 64u * ox + 8u * oy + oz;
        for (int k = 0; k < 8; k++)
            v[k] = leaf_value(g, type, w, n + 64u * (k & 1) + 8u * (k >> 1 & 1) + (k >> 2 & 1));
        if (tiles)
            *tiles = 0u;
        return 1;
    }
    /* Per axis the two voxel layers are offsets o and o + 1 of one block,
     * or, when o = 7, offset 7 and offset 0 of the next block. */
    const uint32_t o[3] = {ox, oy, oz};
    static const uint32_t per_offset[3] = {64u, 8u, 1u},
                          per_local[3] = {1u, GRID_CHUNK_SIDE, GRID_CHUNK_SIDE * GRID_CHUNK_SIDE};
    uint32_t next[3][2], offset[3][2], from_tiles = 0u;
    for (int k = 0; k < 3; k++) {
        next[k][0] = 0u, next[k][1] = o[k] == 7u ? per_local[k] : 0u;
        offset[k][0] = o[k] * per_offset[k], offset[k][1] = ((o[k] + 1u) & 7u) * per_offset[k];
    }
    for (int k = 0; k < 8; k++) {
        const int x = k & 1, y = k >> 1 & 1, z = k >> 2 & 1;
        const uint32_t w = e[local + next[0][x] + next[1][y] + next[2][z]];
        if (w < lowest)
            return 0;
        from_tiles |= (uint32_t)(w < GRID_TILE_MARKERS) << k;
        v[k] = entry_value(g, type, w, offset[0][x] + offset[1][y] + offset[2][z]);
    }
    if (tiles)
        *tiles = from_tiles;
    return 1;
}

/* The eight values of the cell whose lowest corner is i0, through the
 * directory where it holds them, else through the read accessor (tiles and
 * background included). Returns 1 when they all came from leaves. */
GRID_INLINE int cell_values(const sdft_grid *g, pnanovdb_grid_type_t type, pnanovdb_readaccessor_t *acc,
                            pnanovdb_coord_t i0, float v[8])
{
    uint32_t tiles;
    if (has_directory(type) && g->leaves.top && cell_from_leaves(g, type, i0, v, &tiles))
        return tiles == 0u;
    int leaves = 1;
    for (int k = 0; k < 8; k++) {
        uint32_t level;
        v[k] = read_value(g, type, acc, (pnanovdb_coord_t){i0.x + (k & 1), i0.y + (k >> 1 & 1), i0.z + (k >> 2 & 1)},
                          &level);
        leaves &= level == 0;
    }
    return leaves;
}

/* The four differences of cell values v along index axis k, each edge's
 * far end less its near end, in double (exact for the floats of a band):
 * e[P + 2 Q] for the edge at P, Q in {0, 1} on the other two axes, in
 * order. Along axis k the interpolant's derivative is their bilinear
 * blend over P and Q. */
static inline void cell_edges(const float v[8], int k, double e[4])
{
    static const int stride[3] = {1, 2, 4}; /* v's index step along x, y and z */
    const int p = k == 0 ? 1 : 0, r = k == 2 ? 1 : 2;
    for (int i = 0; i < 4; i++) {
        const int near = (i & 1) * stride[p] + (i >> 1) * stride[r];
        e[i] = (double)v[near + stride[k]] - (double)v[near];
    }
}

/* Whether index-space gradient d is too flat to give a normal: below a
 * millionth of the band's half-width per voxel (off the surface, in a
 * tile or the background). */
static inline int gradient_is_flat(const sdft_grid *g, const float d[3])
{
    return !(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 1e-12f * g->background * g->background);
}

/* The gradient, in index space, of the trilinear interpolant of cell
 * values v along the line u0 + s du (cell-local coordinates), as a
 * quadratic in s: component k is q[0][k] + s q[1][k] + s^2 q[2][k]. Along
 * axis k the derivative is the bilinear blend, over the other two
 * coordinates P and Q, of the axis's four edge differences e_PQ
 * (cell_edges): e00 + P a + Q b + P Q c with a =
 * e10 - e00, b = e01 - e00, c = e00 - e10 - e01 + e11; with P = p0 + s dp
 * and Q = q0 + s dq that is the quadratic. At s = 0 it is the gradient at
 * u0; given ahead of the root s, the gradient there is two steps away. */
static inline void cell_gradient_along(const float v[8], const double u0[3], const double du[3], double q[3][3])
{
    for (int k = 0; k < 3; k++) {
        const int p = k == 0 ? 1 : 0, r = k == 2 ? 1 : 2; /* the other two axes, in order */
        double e[4];                                      /* e[P + 2 Q] */
        cell_edges(v, k, e);
        const double a = e[1] - e[0], b = e[2] - e[0], c = e[0] - e[1] - e[2] + e[3];
        q[0][k] = e[0] + u0[p] * a + u0[r] * b + u0[p] * u0[r] * c;
        q[1][k] = du[p] * a + du[r] * b + c * (u0[p] * du[r] + u0[r] * du[p]);
        q[2][k] = c * du[p] * du[r];
    }
}

/* The unit world normal along index-space gradient d: d taken to world
 * space by the world-to-index map's transpose (the gradient of f(A w + t)
 * is A^T times f's), normalized (sdft_normalize: (0, 0, 0) stays). */
static inline sdft_vec3 world_normal(const sdft_grid *g, const float d[3])
{
    const float *m = g->w2i;
    return sdft_normalize(sdft_v3(m[0] * d[0] + m[3] * d[1] + m[6] * d[2], m[1] * d[0] + m[4] * d[1] + m[7] * d[2],
                                  m[2] * d[0] + m[5] * d[1] + m[8] * d[2]));
}

static inline float trilerp(const float v[8], float tx, float ty, float tz)
{
    float x00 = lerp(v[0], v[1], tx), x10 = lerp(v[2], v[3], tx);
    float x01 = lerp(v[4], v[5], tx), x11 = lerp(v[6], v[7], tx);
    return lerp(lerp(x00, x10, ty), lerp(x01, x11, ty), tz);
}

#endif
