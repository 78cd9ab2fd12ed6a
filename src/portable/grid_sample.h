/* sdftrace — a NanoVDB grid's field at a point: trilinear sampling in
 * index space through the grid's transform, through a read accessor (one
 * per thread) and, for float grids, the leaf directory that finds a
 * point's leaf in one load (grid_leaves.c); normals from the grid's
 * gradient; and beyond the narrow band a lower bound on the distance taken
 * from the tree itself (below) or from the far bound's table
 * (grid_bound.c). Portable (portable.h, grid_layout.h): the library's grid
 * field (grid_sample.c) and the shader sample the same code.
 *
 * THE TREE BOUND. An OpenVDB/NanoVDB level set stores distances only in a
 * narrow band; a tile (an 8^3, 128^3 or 4096^3 block the tree keeps as one
 * value) and the region outside every root tile hold one value v, which for a
 * level set is +-background. The level-set convention, which our bake
 * guarantees (src/vdb/bake.cpp), is that each voxel centre c covered by such
 * a value has a true distance |s(c)| >= |v| (background is the band's
 * half-width: every voxel nearer the surface than that is stored in a leaf).
 * Let B be the box spanned by those centres, [a, a + D - 1]^3 in index space,
 * and x any point, in index units.
 *   1. Every point y of B is within sqrt(3)/2 index units of a centre of B
 *      (round each coordinate), so |s(y)| >= |v| - s_max sqrt(3)/2 where
 *      s_max bounds the world length of a unit index step (the transform's
 *      largest singular value). The surface therefore avoids the set
 *      B (+) {world ball of radius r0 = |v| - s_max sqrt(3)/2}.
 *   2. If x lies in B at index depth h >= 0 from B's faces, the index ball of
 *      radius h around x lies in B, and its image contains the world ball of
 *      radius s_min h (s_min: the smallest singular value). So the surface is
 *      at least s_min h + r0 away from x.
 *   3. If x lies outside B at index distance e, its nearest point y of B is
 *      at most s_max e away in world units, so |s(x)| >= r0 - s_max e.
 * Hence |s(x)| >= |v| - s_max sqrt(3)/2 + (h >= 0 ? s_min h : s_max h), with
 * h the signed depth of x in B, and the sign of v gives the side. We look up
 * the node holding the voxel nearest x, so e <= sqrt(3)/2 and the bound is at
 * least |v| - s_max sqrt(3) (1.27 voxels for the default 3-voxel band); when
 * a thin band makes it smaller than half a voxel we fall back to trilinear.
 * s_min and s_max are exact for a uniform scale and conservative otherwise
 * (grid_load.c). The bound grows with the depth inside the node, so one
 * step crosses most of an empty 128^3 tile instead of 3 voxels at a time.
 *
 * Inside leaves the field is the trilinear interpolant of the stored values
 * (inactive voxels hold +-background): the discrete SDF the papers trace. */
#ifndef SDFTRACE_GRID_SAMPLE_H
#define SDFTRACE_GRID_SAMPLE_H

#include "grid_cell.h"

#if defined(SDFT_GLSL)
/* sdftrace/grid.h's sdft_grid_bound. */
#define SDFT_GRID_BOUND_FAR 0
#define SDFT_GRID_BOUND_TREE 1
#define SDFT_GRID_BOUND_NONE 2
#endif

/* The bound of the comment above for the node of `level` holding voxel c,
 * whose value is v; world units. */
PORT_INLINE float tree_bound(GRID_REF g, const float x[3], pnanovdb_coord_t c, uint32_t level, float v)
{
    PORT_CONST int log2_dim[5] = {0, 3, 7, 12, 12};
    const int32_t dim = 1 << log2_dim[level];
    const int32_t cc[3] = {c.x, c.y, c.z};
    float depth = INFINITY, out2 = 0.0f;
    for (int k = 0; k < 3; k++) {
        float lo = PORT_FLOAT(cc[k] & ~(dim - 1)), hi = lo + PORT_FLOAT(dim - 1);
        float inside = sdft_minf(x[k] - lo, hi - x[k]);
        depth = sdft_minf(depth, inside);
        if (inside < 0.0f)
            out2 += inside * inside;
    }
    float h = depth >= 0.0f ? GRID(g).sigma_min * depth : -GRID(g).sigma_max * sqrtf(out2);
    return fabsf(v) - GRID(g).sigma_max * 0.8660254f + h;
}

/* The trilinear value at index point x when the leaf directory knows all
 * eight corners of x's cell (`tiles` 0: in leaves only; 1: tiles of
 * +-background too), else 0. With `want_near`, near_voxel and near_value
 * are the voxel nearest x and its value, and near_tile whether it lies in
 * a tile. */
PORT_INLINE int sample_leaves(GRID_REF g, pnanovdb_grid_type_t type, const float x[3], int tiles, PORT_OUT(float) value,
                              int want_near, PORT_OUT(pnanovdb_coord_t) near_voxel, PORT_OUT(float) near_value,
                              PORT_OUT(int) near_tile)
{
    if (!has_directory(type) || !GRID_HAS_DIRECTORY(g) ||
        !(fabsf(x[0]) < 1e9f && fabsf(x[1]) < 1e9f && fabsf(x[2]) < 1e9f))
        return 0;
    const pnanovdb_coord_t i0 = grid_coord(ifloor(x[0]), ifloor(x[1]), ifloor(x[2]));
    const float tx = x[0] - PORT_FLOAT(i0.x), ty = x[1] - PORT_FLOAT(i0.y), tz = x[2] - PORT_FLOAT(i0.z);
    float v[8];
    uint32_t from_tiles = 0u;
    if (cell_from_leaves(g, type, i0, v, tiles, PORT_REF(from_tiles)) == 0)
        return 0;
    PORT_DEREF(value) = trilerp(v, tx, ty, tz);
    if (want_near != 0) { /* the voxel nearest x: the corner on x's side of each midpoint */
        const int near = PORT_INT(tx >= 0.5f) | PORT_INT(ty >= 0.5f) << 1 | PORT_INT(tz >= 0.5f) << 2;
        PORT_DEREF(near_voxel) = grid_coord(i0.x + (near & 1), i0.y + (near >> 1 & 1), i0.z + (near >> 2 & 1));
        PORT_DEREF(near_value) = v[near];
        PORT_DEREF(near_tile) = PORT_INT(from_tiles >> near & 1u);
    }
    return 1;
}

/* The field at index point x through the read accessor: trilinear in
 * leaves, the tree bound in tiles (if `bound`), and the level the value
 * came from in level_out. `type` as for read_value. For float grids the
 * leaf directory serves most points, so this path is kept out of line,
 * out of the hot loop's way. */
PORT_COLD float sample_tree(GRID_REF g, pnanovdb_grid_type_t type, PNANOVDB_INOUT(pnanovdb_readaccessor_t) acc,
                            const float x[3], PORT_OUT(int) level_out, int bound)
{
    if (!(fabsf(x[0]) < 1e9f && fabsf(x[1]) < 1e9f && fabsf(x[2]) < 1e9f)) { /* NaN or absurdly far: background */
        PORT_DEREF(level_out) = 4;
        return GRID(g).background;
    }
    const pnanovdb_coord_t i0 = grid_coord(ifloor(x[0]), ifloor(x[1]), ifloor(x[2]));
    const float tx = x[0] - PORT_FLOAT(i0.x), ty = x[1] - PORT_FLOAT(i0.y), tz = x[2] - PORT_FLOAT(i0.z);
    /* The voxel nearest x is the cell corner on x's side of each midpoint. */
    const int near = PORT_INT(tx >= 0.5f) | PORT_INT(ty >= 0.5f) << 1 | PORT_INT(tz >= 0.5f) << 2;
    const pnanovdb_coord_t c = grid_coord(i0.x + (near & 1), i0.y + (near >> 1 & 1), i0.z + (near >> 2 & 1));
    uint32_t level;
    float v[8];
    v[near] = read_value(g, type, acc, c, PORT_REF(level));
    if (level > 0u && bound != 0) {
        float b = tree_bound(g, x, c, level, v[near]);
        if (b > 0.5f * GRID(g).sigma_min) {
            PORT_DEREF(level_out) = PORT_INT(level);
            return copysignf(b, v[near]);
        }
    }
    if (type == PNANOVDB_GRID_TYPE_FLOAT && level == 0u && (i0.x & 7) != 7 && (i0.y & 7) != 7 && (i0.z & 7) != 7) {
        /* The whole cell lies in the leaf the accessor just found: read the
         * eight floats from its table (x strides 64, y 8, z 1). */
        pnanovdb_address_t t =
            pnanovdb_leaf_get_table_address(PNANOVDB_GRID_TYPE_FLOAT, GRID(g).buf, PNANOVDB_DEREF(acc).leaf,
                                            pnanovdb_leaf_coord_to_offset(PNANOVDB_REF(i0)));
        for (int k = 0; k < 8; k++)
            v[k] = pnanovdb_read_float(
                GRID(g).buf, pnanovdb_address_offset(t, 4u * (64u * PORT_UINT(k & 1) + 8u * PORT_UINT(k >> 1 & 1) +
                                                              PORT_UINT(k >> 2 & 1))));
    } else {
        PORT_NO_UNROLL for (int k = 0; k < 8; k++)
        {
            if (k == near)
                continue;
            uint32_t lk;
            v[k] = read_value(g, type, acc, grid_coord(i0.x + (k & 1), i0.y + (k >> 1 & 1), i0.z + (k >> 2 & 1)),
                              PORT_REF(lk));
        }
    }
    PORT_DEREF(level_out) = 0;
    return trilerp(v, tx, ty, tz);
}

/* The field at index point x without the far bound: through the leaf
 * directory where it serves (the same values, fewer loads), else the
 * accessor. */
PORT_INLINE float sample_index(GRID_REF g, pnanovdb_grid_type_t type, PNANOVDB_INOUT(pnanovdb_readaccessor_t) acc,
                               const float x[3], PORT_OUT(int) level, int bound)
{
    float v;
    pnanovdb_coord_t near_voxel;
    float near_value;
    int near_tile;
    if (sample_leaves(g, type, x, PORT_INT(bound == 0), PORT_REF(v), 0, PORT_REF(near_voxel), PORT_REF(near_value),
                      PORT_REF(near_tile)) != 0) {
        PORT_DEREF(level) = 0;
        return v;
    }
    return sample_tree(g, type, acc, x, level, bound);
}

/* The far bound's cell of index point x, taken to the nearest point xc of
 * the cells' box: 1, with *corner its lowest corner's place in the table
 * (x fastest, rows of n[0] + 1), x's weights t in it, and |x - xc|^2 in
 * cells^2 (*out2); 0 without a far bound, or for x NaN or absurdly far. */
PORT_INLINE int far_cell_corner(GRID_REF g, const float x[3], PORT_ARRAY_OUT float t[3], PORT_OUT(float) out2,
                                PORT_OUT(GRID_FAR_REF) corner)
{
    if (!GRID_HAS_FAR(g))
        return 0;
    int c[3];
    PORT_DEREF(out2) = 0.0f;
    for (int k = 0; k < 3; k++) {
        const float u = (x[k] - GRID(g).far.origin[k]) * GRID(g).far.inv_cell;
        if (!(fabsf(u) < 1e9f)) /* NaN or absurdly far */
            return 0;
        const float uc = sdft_minf(sdft_maxf(u, 0.0f), PORT_FLOAT(GRID(g).far.n[k]));
        PORT_DEREF(out2) += (u - uc) * (u - uc);
        c[k] = PORT_INT(uc) - PORT_INT(PORT_INT(uc) == GRID(g).far.n[k]);
        t[k] = uc - PORT_FLOAT(c[k]);
    }
    const size_t sx = PORT_INDEX(GRID(g).far.n[0]) + 1u, sy = sx * (PORT_INDEX(GRID(g).far.n[1]) + 1u);
    PORT_DEREF(corner) = GRID_FAR_BASE(g, PORT_INDEX(c[2]) * sy + PORT_INDEX(c[1]) * sx + PORT_INDEX(c[0]));
    return 1;
}

/* Corner word i from corner d of the far bound's table: its distance, index
 * units x FAR_DISTANCE_SCALE. */
PORT_INLINE float far_corner_distance(GRID_REF g, GRID_FAR_REF d, size_t i)
{
    PORT_UNUSED(g);
    return PORT_FLOAT(PORT_UINT(GRID_FAR_AT(g, d, i)) & ((1u << FAR_DISTANCE_BITS) - 1u));
}

/* The far bound of grid_bound.c at index point x (world units, signed), or
 * 0 where it does not apply: x in an occupied cell, or NaN. One cell read,
 * eight corner reads, one square root, no tree walk. A point outside the
 * cells (a ray entering the box, rounded) is taken to the nearest point xc
 * of their box: everything out there rounds to inactive voxels, so the sign
 * is xc's cell's, and e(x) >= max(e(xc) - |x - xc|, |x - xc|) as U lies in
 * the box. */
PORT_INLINE float far_bound(GRID_REF g, const float x[3])
{
    float t[3], out2;
    GRID_FAR_REF d;
    if (far_cell_corner(g, x, t, PORT_REF(out2), PORT_REF(d)) == 0)
        return 0.0f;
    const size_t sx = PORT_INDEX(GRID(g).far.n[0]) + 1u, sy = sx * (PORT_INDEX(GRID(g).far.n[1]) + 1u);
    const uint32_t code = PORT_UINT(GRID_FAR_AT(g, d, 0u)) >> FAR_DISTANCE_BITS;
    if (code == 0u)
        return 0.0f;
    const float d00 = lerp(far_corner_distance(g, d, 0u), far_corner_distance(g, d, 1u), t[0]);
    const float d10 = lerp(far_corner_distance(g, d, sx), far_corner_distance(g, d, sx + 1u), t[0]);
    const float d01 = lerp(far_corner_distance(g, d, sy), far_corner_distance(g, d, sy + 1u), t[0]);
    const float d11 = lerp(far_corner_distance(g, d, sy + sx), far_corner_distance(g, d, sy + sx + 1u), t[0]);
    const float S = PORT_FLOAT(GRID(g).far.cell);
    float e = (1.0f / FAR_DISTANCE_SCALE) * lerp(lerp(d00, d10, t[1]), lerp(d01, d11, t[1]), t[2]) -
              S * sqrtf(t[0] * (1.0f - t[0]) + t[1] * (1.0f - t[1]) + t[2] * (1.0f - t[2]));
    if (out2 > 0.0f) {
        const float away = S * sqrtf(out2);
        e = sdft_maxf(e - away, away);
    }
    const float b = GRID(g).sigma_min * sdft_maxf(e, 0.0f) + GRID(g).far.bonus;
    return code == FAR_EMPTY_POSITIVE ? b : -b;
}

/* The field of `bound` at index point x, and the level it came from
 * (sdft_grid_sample's). TREE: the tree bound in tiles (the first version of
 * the grid field); NONE: trilinear everywhere, +-background beyond the
 * band, only to measure what the bounds save. FAR, the default: in a leaf
 * (the voxel nearest x in a leaf, x's cell known to the directory) the
 * trilinear value, read first and alone: near the surface that is all that
 * is read. The far bound is not asked there, even where the value is the
 * background: inside a leaf b rarely beats the background (a 4^3 cell of
 * the leaf must be empty and x more than 2.3 voxels from every occupied
 * one), and reading its table, a cache miss, cost 2-7% of a frame on the
 * bench's grids for 0.00-0.04% fewer evaluations. Elsewhere TREE's field
 * (the tree bound where the nearest voxel lies in a tile: from the
 * directory's tile marker when it has one, without walking the tree), and
 * where the far bound b applies (x in an empty cell), the larger of b and
 * that. Each is a step the tracer may take (b a proven distance bound, the
 * other the field it traces without the far bound), so the larger is too.
 * Beside leaves b can be as small as its band bonus (0.72 voxels) where
 * the field steps a whole band; once b reaches the band it is taken
 * without looking further. */
PORT_INLINE float sample_at(GRID_REF g, pnanovdb_grid_type_t type, PNANOVDB_INOUT(pnanovdb_readaccessor_t) acc,
                            const float x[3], PORT_OUT(int) level, int bound)
{
    if (bound != SDFT_GRID_BOUND_FAR)
        return sample_index(g, type, acc, x, level, PORT_INT(bound == SDFT_GRID_BOUND_TREE));
    float v = 0.0f, near_value = 0.0f;
    pnanovdb_coord_t near_voxel;
    int near_tile = 0, vlevel = 0;
    const int known =
        sample_leaves(g, type, x, 1, PORT_REF(v), 1, PORT_REF(near_voxel), PORT_REF(near_value), PORT_REF(near_tile));
    if (known != 0 && near_tile != 0) { /* TREE's field: the tree bound of an 8^3 tile, where it is of use */
        const float tb = tree_bound(g, x, near_voxel, 1u, near_value);
        if (tb > 0.5f * GRID(g).sigma_min) {
            v = copysignf(tb, near_value);
            vlevel = 1;
        }
    } else if (known != 0) {
        PORT_DEREF(level) = 0;
        return v;
    }
    const float b = far_bound(g, x); /* 0: does not apply */
    if (b != 0.0f && fabsf(b) >= GRID(g).background) {
        PORT_DEREF(level) = 5;
        return b;
    }
    if (known == 0)
        v = sample_tree(g, type, acc, x, PORT_REF(vlevel), 1);
    if (b == 0.0f || (fabsf(v) > fabsf(b) && (v < 0.0f) == (b < 0.0f))) {
        PORT_DEREF(level) = vlevel;
        return v;
    }
    PORT_DEREF(level) = 5;
    return b;
}

/* The field of `bound` at world point p: the grid's distance. */
PORT_INLINE float grid_distance(GRID_REF g, pnanovdb_grid_type_t type, int diagonal,
                                PNANOVDB_INOUT(pnanovdb_readaccessor_t) acc, sdft_vec3 p, int bound)
{
    float x[3];
    int level;
    to_index(g, diagonal, p, x);
    return sample_at(g, type, acc, x, PORT_REF(level), bound);
}

/* The normal at world point p: the gradient of the trilinear interpolant
 * the tracer traces, in the cell holding p, the eight values a hit's last
 * cell already read (so cached); taken to world space by the inverse
 * transform's transpose. At a hit that is the exact normal of the traced
 * surface, and vdb_render's too (OpenVDB's BoxStencil gradient). Where the
 * interpolant is flat in that cell (p off the surface, in a tile or the
 * background) it falls back to tetrahedral differences one voxel out:
 * four samples at x + k_i, k_i alternate corners (+-1, +-1, +-1) of the
 * voxel cube around x, whose outer products sum to 4 I, so sum f(x + k_i)
 * k_i is 4 times the gradient of a linear field. */
PORT_INLINE sdft_vec3 normal_of(GRID_REF g, pnanovdb_grid_type_t type, PNANOVDB_INOUT(pnanovdb_readaccessor_t) acc,
                                sdft_vec3 p)
{
    float x[3], d[3] = {0.0f, 0.0f, 0.0f};
    to_index(g, PORT_INT(GRID(g).diagonal), p, x);
    if (fabsf(x[0]) < 1e9f && fabsf(x[1]) < 1e9f && fabsf(x[2]) < 1e9f) {
        const pnanovdb_coord_t i0 = grid_coord(ifloor(x[0]), ifloor(x[1]), ifloor(x[2]));
        const float tx = x[0] - PORT_FLOAT(i0.x), ty = x[1] - PORT_FLOAT(i0.y), tz = x[2] - PORT_FLOAT(i0.z);
        float v[8];
        double q[3][3];
        const double u0[3] = {tx, ty, tz}, none[3] = {0.0, 0.0, 0.0};
        cell_values(g, type, acc, i0, v);
        cell_gradient_along(v, u0, none, q);
        d[0] = PORT_FLOAT(q[0][0]);
        d[1] = PORT_FLOAT(q[0][1]);
        d[2] = PORT_FLOAT(q[0][2]);
    }
    if (gradient_is_flat(g, d)) {
        PORT_CONST float k[4][3] = {
            {1.0f, -1.0f, -1.0f}, {-1.0f, -1.0f, 1.0f}, {-1.0f, 1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}};
        d[0] = 0.0f;
        d[1] = 0.0f;
        d[2] = 0.0f;
        PORT_NO_UNROLL for (int i = 0; i < 4; i++)
        {
            const float at[3] = {x[0] + k[i][0], x[1] + k[i][1], x[2] + k[i][2]};
            int level;
            const float f = sample_index(g, type, acc, at, PORT_REF(level), 0);
            d[0] += k[i][0] * f;
            d[1] += k[i][1] * f;
            d[2] += k[i][2] * f;
        }
    }
    return world_normal(g, d);
}

#endif
