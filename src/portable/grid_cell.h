/* sdftrace — reading a grid's voxel cells, shared by the sampler
 * (grid_sample.h) and the exact last-cell root (grid_root.h): world to
 * index, one stored value through the read accessor, the eight corners of
 * a trilinear cell through the leaf directory (grid_leaves.c). Every
 * helper inlines, so a caller specialised on a grid type keeps no branch
 * on it. Portable (portable.h, grid_layout.h): in C over sdft_grid
 * (grid_internal.h), in the shader over its grid_shape. */
#ifndef SDFTRACE_GRID_CELL_H
#define SDFTRACE_GRID_CELL_H

#if !defined(SDFT_GLSL)
#include <math.h>

#include "grid_internal.h"
#endif
#include "grid_layout.h"

/* A voxel's coordinates. */
PORT_INLINE pnanovdb_coord_t grid_coord(int32_t x, int32_t y, int32_t z)
{
    pnanovdb_coord_t c;
    c.x = x;
    c.y = y;
    c.z = z;
    return c;
}

/* The stored value at voxel ijk and the tree level it came from
 * (0 leaf, 1 lower-node tile, 2 upper-node tile, 3 root tile, 4 background).
 * `type` is the grid's type, or a constant where the caller is
 * specialised. */
PORT_INLINE float read_value(GRID_REF g, pnanovdb_grid_type_t type, PNANOVDB_INOUT(pnanovdb_readaccessor_t) acc,
                             pnanovdb_coord_t ijk, PORT_OUT(uint32_t) level)
{
    pnanovdb_address_t a =
        pnanovdb_readaccessor_get_value_address_and_level(type, GRID(g).buf, acc, PNANOVDB_REF(ijk), level);
    if (PORT_DEREF(level) == 0u)
        GRID_LEAF_READY(g, PNANOVDB_DEREF(acc).leaf.address.byte_offset, ijk);
    if (type == PNANOVDB_GRID_TYPE_FLOAT)
        return pnanovdb_read_float(GRID(g).buf, a);
    if (type == PNANOVDB_GRID_TYPE_DOUBLE)
        return PORT_FLOAT(pnanovdb_read_double(GRID(g).buf, a));
    if (type == PNANOVDB_GRID_TYPE_FP16)
        return pnanovdb_root_fp16_read_float(GRID(g).buf, a, PNANOVDB_REF(ijk), PORT_DEREF(level));
    if (type == PNANOVDB_GRID_TYPE_FP8)
        return pnanovdb_root_fp8_read_float(GRID(g).buf, a, PNANOVDB_REF(ijk), PORT_DEREF(level));
    if (type == PNANOVDB_GRID_TYPE_FP4)
        return pnanovdb_root_fp4_read_float(GRID(g).buf, a, PNANOVDB_REF(ijk), PORT_DEREF(level));
    return pnanovdb_root_fpn_read_float(GRID(g).buf, a, PNANOVDB_REF(ijk), PORT_DEREF(level));
}

/* World to index. `diagonal` (the grid's, or a constant): the matrix is a
 * diagonal scale, whose products with 0 the full form would add. */
PORT_INLINE void to_index(GRID_REF g, int diagonal, sdft_vec3 p, PORT_ARRAY_OUT float x[3])
{
    if (diagonal != 0) {
        x[0] = GRID(g).w2i[0] * p.x + GRID(g).w2i_t[0];
        x[1] = GRID(g).w2i[4] * p.y + GRID(g).w2i_t[1];
        x[2] = GRID(g).w2i[8] * p.z + GRID(g).w2i_t[2];
        return;
    }
    x[0] = GRID(g).w2i[0] * p.x + GRID(g).w2i[1] * p.y + GRID(g).w2i[2] * p.z + GRID(g).w2i_t[0];
    x[1] = GRID(g).w2i[3] * p.x + GRID(g).w2i[4] * p.y + GRID(g).w2i[5] * p.z + GRID(g).w2i_t[1];
    x[2] = GRID(g).w2i[6] * p.x + GRID(g).w2i[7] * p.y + GRID(g).w2i[8] * p.z + GRID(g).w2i_t[2];
}

/* floor(x) for |x| < 2^31 (callers check): floorf is a libm call on
 * baseline x86-64. Truncation is exact, and steps down below 0. */
PORT_INLINE int32_t ifloor(float x)
{
    const int32_t i = PORT_INT(x);
    return i - PORT_INT(x < PORT_FLOAT(i));
}

PORT_INLINE float lerp(float a, float b, float t) { return a + (b - a) * t; }

PORT_INLINE float word_float(GRID_REF g, uint32_t w) { return pnanovdb_uint32_as_float(GRID_WORD(g, w)); }

/* Whether grids of `type` have a leaf directory (grid_leaves.c). */
PORT_INLINE bool has_directory(pnanovdb_grid_type_t type)
{
    return type == PNANOVDB_GRID_TYPE_FLOAT || type == PNANOVDB_GRID_TYPE_FP16 || type == PNANOVDB_GRID_TYPE_FP8 ||
           type == PNANOVDB_GRID_TYPE_FP4;
}

/* Value n (64 x + 8 y + z) of the leaf whose value table starts at word w:
 * a float, or a code of 16, 8 or 4 bits times the leaf's quantum plus its
 * minimum, the two floats before the table (pnanovdb_leaf_fp_read_float,
 * the same arithmetic). */
PORT_INLINE float leaf_value(GRID_REF g, pnanovdb_grid_type_t type, uint32_t w, uint32_t n)
{
    uint32_t code;
    if (type == PNANOVDB_GRID_TYPE_FLOAT)
        return word_float(g, w + n);
    if (type == PNANOVDB_GRID_TYPE_FP16)
        code = GRID_WORD(g, w + (n >> 1)) >> ((n & 1u) << 4) & 0xFFFFu;
    else if (type == PNANOVDB_GRID_TYPE_FP8)
        code = GRID_WORD(g, w + (n >> 2)) >> ((n & 3u) << 3) & 0xFFu;
    else /* FP4 */
        code = GRID_WORD(g, w + (n >> 3)) >> ((n & 7u) << 2) & 0xFu;
    return PORT_FLOAT(code) * word_float(g, w - 3u) + word_float(g, w - 4u);
}

/* The value of entry w of the directory at leaf offset n: from the leaf,
 * or the tile's +-background (w a tile marker). */
PORT_INLINE float entry_value(GRID_REF g, pnanovdb_grid_type_t type, uint32_t w, uint32_t n)
{
    if (w < GRID_TILE_MARKERS)
        return w == GRID_TILE_POSITIVE ? GRID(g).background : -GRID(g).background;
    return leaf_value(g, type, w, n);
}

/* The directory's chunk holding voxel c's block: 1, with *chunk its place
 * and *local that block's entry in it; 0 when c lies outside the regions
 * or in one without a chunk (grid_leaves.c). */
PORT_INLINE int directory_chunk(GRID_REF g, const int32_t c[3], PORT_OUT(uint32_t) local,
                                PORT_OUT(GRID_CHUNK_REF) chunk_at)
{
    uint32_t r[3];
    for (int k = 0; k < 3; k++) {
        r[k] = PORT_UINT((c[k] >> 6) - GRID(g).leaves.r0[k]);
        if (r[k] >= PORT_UINT(GRID(g).leaves.nr[k])) /* below r0 wraps above nr */
            return 0;
    }
    const uint32_t chunk = GRID_TOP(
        g, (PORT_INDEX(r[2]) * PORT_INDEX(GRID(g).leaves.nr[1]) + r[1]) * PORT_INDEX(GRID(g).leaves.nr[0]) + r[0]);
    if (chunk == 0u)
        return 0;
    PORT_DEREF(local) = (PORT_UINT(c[0]) >> 3 & 7u) + GRID_CHUNK_SIDE * (PORT_UINT(c[1]) >> 3 & 7u) +
                        GRID_CHUNK_SIDE * GRID_CHUNK_SIDE * (PORT_UINT(c[2]) >> 3 & 7u);
    PORT_DEREF(chunk_at) = GRID_CHUNK_BASE(g, PORT_INDEX(chunk - 1u) * GRID_CHUNK_ENTRIES);
    return 1;
}

/* The eight values of the cell whose lowest corner is i0 (v[k]: corner
 * i0 + (k & 1, k >> 1 & 1, k >> 2 & 1)), read through the leaf directory
 * (grid_leaves.c); 0 when a corner lies in no block the directory knows
 * (the accessor's path then). With `with_tiles` 0 only leaves count as
 * known; else tiles of +-background do too, and *tiles gets bit k set for
 * each corner k that came from one. Per axis the cell's two voxel layers
 * are the same block at offsets o and o + 1, or, when o = 7, two blocks at
 * offsets 7 and 0, the second in the chunk's apron; a value sits at 64, 8
 * and 1 entries per x, y and z offset in its leaf. */
PORT_INLINE int cell_from_leaves(GRID_REF g, pnanovdb_grid_type_t type, pnanovdb_coord_t i0, PORT_ARRAY_OUT float v[8],
                                 int with_tiles, PORT_OUT(uint32_t) tiles)
{
    const int32_t c[3] = {i0.x, i0.y, i0.z};
    const uint32_t lowest = with_tiles != 0 ? GRID_TILE_POSITIVE : GRID_TILE_MARKERS; /* entries below are unknown */
    uint32_t local;
    GRID_CHUNK_REF e;
    if (directory_chunk(g, c, PORT_REF(local), PORT_REF(e)) == 0)
        return 0;
    const uint32_t ox = PORT_UINT(c[0]) & 7u, oy = PORT_UINT(c[1]) & 7u, oz = PORT_UINT(c[2]) & 7u;
    if (ox != 7u && oy != 7u && oz != 7u) { /* the whole cell in one block: two of every three cells */
        const uint32_t w = GRID_CHUNK_AT(g, e, local);
        if (w < lowest)
            return 0;
        if (w < GRID_TILE_MARKERS) {
            for (int k = 0; k < 8; k++)
                v[k] = w == GRID_TILE_POSITIVE ? GRID(g).background : -GRID(g).background;
            PORT_DEREF(tiles) = 0xFFu;
            return 1;
        }
        const uint32_t n = 64u * ox + 8u * oy + oz;
        for (int k = 0; k < 8; k++)
            v[k] =
                leaf_value(g, type, w, n + 64u * PORT_UINT(k & 1) + 8u * PORT_UINT(k >> 1 & 1) + PORT_UINT(k >> 2 & 1));
        if (with_tiles != 0)
            PORT_DEREF(tiles) = 0u;
        return 1;
    }
    /* Per axis the two voxel layers are offsets o and o + 1 of one block,
     * or, when o = 7, offset 7 and offset 0 of the next block. */
    const uint32_t o[3] = {ox, oy, oz};
    PORT_CONST uint32_t per_offset[3] = {64u, 8u, 1u},
                        per_local[3] = {1u, GRID_CHUNK_SIDE, GRID_CHUNK_SIDE * GRID_CHUNK_SIDE};
    uint32_t next[3][2], offset[3][2], from_tiles = 0u;
    for (int k = 0; k < 3; k++) {
        next[k][0] = 0u;
        next[k][1] = o[k] == 7u ? per_local[k] : 0u;
        offset[k][0] = o[k] * per_offset[k];
        offset[k][1] = ((o[k] + 1u) & 7u) * per_offset[k];
    }
    for (int k = 0; k < 8; k++) {
        const int x = k & 1, y = k >> 1 & 1, z = k >> 2 & 1;
        const uint32_t w = GRID_CHUNK_AT(g, e, local + next[0][x] + next[1][y] + next[2][z]);
        if (w < lowest)
            return 0;
        from_tiles |= PORT_UINT(w < GRID_TILE_MARKERS) << k;
        v[k] = entry_value(g, type, w, offset[0][x] + offset[1][y] + offset[2][z]);
    }
    if (with_tiles != 0)
        PORT_DEREF(tiles) = from_tiles;
    return 1;
}

/* The eight values of the cell whose lowest corner is i0, through the
 * directory where it holds them, else through the read accessor (tiles and
 * background included). Returns 1 when they all came from leaves. */
PORT_INLINE int cell_values(GRID_REF g, pnanovdb_grid_type_t type, PNANOVDB_INOUT(pnanovdb_readaccessor_t) acc,
                            pnanovdb_coord_t i0, PORT_ARRAY_OUT float v[8])
{
    uint32_t tiles;
    if (has_directory(type) && GRID_HAS_DIRECTORY(g) && cell_from_leaves(g, type, i0, v, 1, PORT_REF(tiles)) != 0)
        return PORT_INT(tiles == 0u);
    int leaves = 1;
    PORT_NO_UNROLL for (int k = 0; k < 8; k++)
    {
        uint32_t level;
        v[k] = read_value(g, type, acc, grid_coord(i0.x + (k & 1), i0.y + (k >> 1 & 1), i0.z + (k >> 2 & 1)),
                          PORT_REF(level));
        leaves &= PORT_INT(level == 0u);
    }
    return leaves;
}

/* The four differences of cell values v along index axis k, each edge's
 * far end less its near end, in double (exact for the floats of a band):
 * e[P + 2 Q] for the edge at P, Q in {0, 1} on the other two axes, in
 * order. Along axis k the interpolant's derivative is their bilinear
 * blend over P and Q. */
PORT_INLINE void cell_edges(const float v[8], int k, PORT_ARRAY_OUT double e[4])
{
    PORT_CONST int stride[3] = {1, 2, 4}; /* v's index step along x, y and z */
    const int p = k == 0 ? 1 : 0, r = k == 2 ? 1 : 2;
    for (int i = 0; i < 4; i++) {
        const int near = (i & 1) * stride[p] + (i >> 1) * stride[r];
        e[i] = PORT_DOUBLE(v[near + stride[k]]) - PORT_DOUBLE(v[near]);
    }
}

/* Whether index-space gradient d is too flat to give a normal: below a
 * millionth of the band's half-width per voxel (off the surface, in a
 * tile or the background). */
PORT_INLINE bool gradient_is_flat(GRID_REF g, const float d[3])
{
    return !(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 1e-12f * GRID(g).background * GRID(g).background);
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
PORT_INLINE void cell_gradient_along(const float v[8], const double u0[3], const double du[3],
                                     PORT_ARRAY_OUT double q[3][3])
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
PORT_INLINE sdft_vec3 world_normal(GRID_REF g, const float d[3])
{
    return sdft_normalize(sdft_v3(GRID(g).w2i[0] * d[0] + GRID(g).w2i[3] * d[1] + GRID(g).w2i[6] * d[2],
                                  GRID(g).w2i[1] * d[0] + GRID(g).w2i[4] * d[1] + GRID(g).w2i[7] * d[2],
                                  GRID(g).w2i[2] * d[0] + GRID(g).w2i[5] * d[1] + GRID(g).w2i[8] * d[2]));
}

PORT_INLINE float trilerp(const float v[8], float tx, float ty, float tz)
{
    float x00 = lerp(v[0], v[1], tx), x10 = lerp(v[2], v[3], tx);
    float x01 = lerp(v[4], v[5], tx), x11 = lerp(v[6], v[7], tx);
    return lerp(lerp(x00, x10, ty), lerp(x01, x11, ty), tz);
}

#endif
