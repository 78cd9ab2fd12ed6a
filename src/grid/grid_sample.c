/* sdftrace — a NanoVDB grid as a field: trilinear sampling in index space
 * through the grid's transform, one read accessor per thread (kept in the
 * caller's sdft_scratch) and, for float grids, the leaf directory that
 * finds a point's leaf in one load (grid_leaves.c); normals from the grid's
 * gradient; and beyond the narrow band a lower bound on the distance taken
 * from the tree itself.
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
#include <math.h>

#include "grid_cell.h"

static void grid_scratch_init(const void *ctx, sdft_scratch *s)
{
    const sdft_grid *g = ctx;
    pnanovdb_readaccessor_init(accessor(s), g->root);
}

/* The bound of the comment above for the node of `level` holding voxel c,
 * whose value is v; world units. */
static inline float tree_bound(const sdft_grid *g, const float x[3], pnanovdb_coord_t c, uint32_t level, float v)
{
    static const int log2_dim[5] = {0, 3, 7, 12, 12};
    const int32_t dim = 1 << log2_dim[level];
    const int32_t cc[3] = {c.x, c.y, c.z};
    float depth = INFINITY, out2 = 0.0f;
    for (int k = 0; k < 3; k++) {
        float lo = (float)(cc[k] & ~(dim - 1)), hi = lo + (float)(dim - 1);
        float inside = sdft_minf(x[k] - lo, hi - x[k]);
        depth = sdft_minf(depth, inside);
        if (inside < 0.0f)
            out2 += inside * inside;
    }
    float h = depth >= 0.0f ? g->sigma_min * depth : -g->sigma_max * sqrtf(out2);
    return fabsf(v) - g->sigma_max * 0.8660254f + h;
}

/* The trilinear value at index point x when the leaf directory knows all
 * eight corners of x's cell (`tiles` 0: in leaves only; 1: tiles of
 * +-background too), else 0. *near: the value of the voxel nearest x and
 * whether it lies in a tile (2 | sign bit), or 0 in a leaf; NULL: not
 * wanted. */
GRID_INLINE int sample_leaves(const sdft_grid *g, pnanovdb_grid_type_t type, const float x[3], int tiles, float *value,
                              pnanovdb_coord_t *near_voxel, float *near_value, int *near_tile)
{
    if (!has_directory(type) || !g->leaves.top || !(fabsf(x[0]) < 1e9f && fabsf(x[1]) < 1e9f && fabsf(x[2]) < 1e9f))
        return 0;
    const pnanovdb_coord_t i0 = {ifloor(x[0]), ifloor(x[1]), ifloor(x[2])};
    const float tx = x[0] - (float)i0.x, ty = x[1] - (float)i0.y, tz = x[2] - (float)i0.z;
    float v[8];
    uint32_t from_tiles = 0u;
    if (!cell_from_leaves(g, type, i0, v, tiles ? &from_tiles : NULL))
        return 0;
    *value = trilerp(v, tx, ty, tz);
    if (near_tile) { /* the voxel nearest x: the corner on x's side of each midpoint */
        const int near = (tx >= 0.5f) | (ty >= 0.5f) << 1 | (tz >= 0.5f) << 2;
        *near_voxel = (pnanovdb_coord_t){i0.x + (near & 1), i0.y + (near >> 1 & 1), i0.z + (near >> 2 & 1)};
        *near_value = v[near];
        *near_tile = (int)(from_tiles >> near & 1u);
    }
    return 1;
}

/* The field at index point x through the read accessor: trilinear in
 * leaves, the tree bound in tiles (if `bound`). `type` as for read_value.
 * For float grids the leaf directory serves most points, so this path is
 * kept out of line, out of the hot loop's way. */
GRID_COLD float sample_tree(const sdft_grid *g, pnanovdb_grid_type_t type, pnanovdb_readaccessor_t *acc,
                            const float x[3], int *level_out, int bound)
{
    if (!(fabsf(x[0]) < 1e9f && fabsf(x[1]) < 1e9f && fabsf(x[2]) < 1e9f)) { /* NaN or absurdly far: background */
        if (level_out)
            *level_out = 4;
        return g->background;
    }
    const pnanovdb_coord_t i0 = {ifloor(x[0]), ifloor(x[1]), ifloor(x[2])};
    const float tx = x[0] - (float)i0.x, ty = x[1] - (float)i0.y, tz = x[2] - (float)i0.z;
    /* The voxel nearest x is the cell corner on x's side of each midpoint. */
    const int near = (tx >= 0.5f) | (ty >= 0.5f) << 1 | (tz >= 0.5f) << 2;
    const pnanovdb_coord_t c = {i0.x + (near & 1), i0.y + (near >> 1 & 1), i0.z + (near >> 2 & 1)};
    uint32_t level;
    float v[8];
    v[near] = read_value(g, type, acc, c, &level);
    if (level > 0 && bound) {
        float b = tree_bound(g, x, c, level, v[near]);
        if (b > 0.5f * g->sigma_min) {
            if (level_out)
                *level_out = (int)level;
            return copysignf(b, v[near]);
        }
    }
    if (type == PNANOVDB_GRID_TYPE_FLOAT && level == 0 && (i0.x & 7) != 7 && (i0.y & 7) != 7 && (i0.z & 7) != 7) {
        /* The whole cell lies in the leaf the accessor just found: read the
         * eight floats from its table (x strides 64, y 8, z 1). */
        pnanovdb_address_t t = pnanovdb_leaf_get_table_address(PNANOVDB_GRID_TYPE_FLOAT, g->buf, acc->leaf,
                                                               pnanovdb_leaf_coord_to_offset(&i0));
        for (int k = 0; k < 8; k++)
            v[k] = pnanovdb_read_float(
                g->buf, pnanovdb_address_offset(t, 4u * (64u * (k & 1) + 8u * (k >> 1 & 1) + (k >> 2 & 1))));
    } else {
        for (int k = 0; k < 8; k++) {
            if (k == near)
                continue;
            uint32_t lk;
            v[k] = read_value(g, type, acc,
                              (pnanovdb_coord_t){i0.x + (k & 1), i0.y + (k >> 1 & 1), i0.z + (k >> 2 & 1)}, &lk);
        }
    }
    if (level_out)
        *level_out = 0;
    return trilerp(v, tx, ty, tz);
}

/* The field at index point x without the far bound: through the leaf
 * directory where it serves (the same values, fewer loads), else the
 * accessor. */
GRID_INLINE float sample_index(const sdft_grid *g, pnanovdb_grid_type_t type, pnanovdb_readaccessor_t *acc,
                               const float x[3], int *level, int bound)
{
    float v;
    if (sample_leaves(g, type, x, !bound, &v, NULL, NULL, NULL)) {
        if (level)
            *level = 0;
        return v;
    }
    return sample_tree(g, type, acc, x, level, bound);
}

/* The far bound's cell of index point x, taken to the nearest point xc of
 * the cells' box: its lowest corner in the table (x fastest, rows of
 * n[0] + 1), x's weights t in it, and |x - xc|^2 in cells^2 (*out2); NULL
 * without a far bound, or for x NaN or absurdly far. */
static inline const uint16_t *far_cell_corner(const grid_far *f, const float x[3], float t[3], float *out2)
{
    if (!f->corner)
        return NULL;
    int c[3];
    *out2 = 0.0f;
    for (int k = 0; k < 3; k++) {
        const float u = (x[k] - f->origin[k]) * f->inv_cell;
        if (!(fabsf(u) < 1e9f)) /* NaN or absurdly far */
            return NULL;
        const float uc = sdft_minf(sdft_maxf(u, 0.0f), (float)f->n[k]);
        *out2 += (u - uc) * (u - uc);
        c[k] = (int)uc - ((int)uc == f->n[k]);
        t[k] = uc - (float)c[k];
    }
    const size_t sx = (size_t)f->n[0] + 1, sy = sx * ((size_t)f->n[1] + 1);
    return f->corner + (size_t)c[2] * sy + (size_t)c[1] * sx + (size_t)c[0];
}

/* The far bound of grid_bound.c at index point x (world units, signed), or
 * 0 where it does not apply: x in an occupied cell, or NaN. One cell read,
 * eight corner reads, one square root, no tree walk. A point outside the
 * cells (a ray entering the box, rounded) is taken to the nearest point xc
 * of their box: everything out there rounds to inactive voxels, so the sign
 * is xc's cell's, and e(x) >= max(e(xc) - |x - xc|, |x - xc|) as U lies in
 * the box. */
static inline float far_bound(const sdft_grid *g, const float x[3])
{
    const grid_far *f = &g->far;
    float t[3], out2;
    const uint16_t *d = far_cell_corner(f, x, t, &out2);
    if (!d)
        return 0.0f;
    const size_t sx = (size_t)f->n[0] + 1, sy = sx * ((size_t)f->n[1] + 1);
    const unsigned code = d[0] >> FAR_DISTANCE_BITS;
    if (code == 0)
        return 0.0f;
#define D(i) (float)(d[i] & ((1u << FAR_DISTANCE_BITS) - 1u))
    const float d00 = lerp(D(0), D(1), t[0]), d10 = lerp(D(sx), D(sx + 1), t[0]);
    const float d01 = lerp(D(sy), D(sy + 1), t[0]), d11 = lerp(D(sy + sx), D(sy + sx + 1), t[0]);
#undef D
    const float S = (float)f->cell;
    float e = (1.0f / FAR_DISTANCE_SCALE) * lerp(lerp(d00, d10, t[1]), lerp(d01, d11, t[1]), t[2]) -
              S * sqrtf(t[0] * (1.0f - t[0]) + t[1] * (1.0f - t[1]) + t[2] * (1.0f - t[2]));
    if (out2 > 0.0f) {
        const float out = S * sqrtf(out2);
        e = sdft_maxf(e - out, out);
    }
    const float b = g->sigma_min * sdft_maxf(e, 0.0f) + f->bonus;
    return code == FAR_EMPTY_POSITIVE ? b : -b;
}

/* Starts loading what sample() at index point x will read: the leaf
 * directory's entry for x's cell and, in a leaf, the cell's four rows of
 * two voxels (z is the fastest axis, so each row is one or two adjacent
 * values); beside no leaf, the far bound's corners. Plain loads of the
 * directory (small, mostly cached) and prefetches of the rest, so that a
 * caller's scattered points wait for their memory together (the field's
 * prefetch hint; the tracer does not use it, field.h). Reads nothing it
 * cannot bound: x's block is checked as in cell_from_leaves. */
GRID_INLINE void prefetch_index(const sdft_grid *g, pnanovdb_grid_type_t type, const float x[3])
{
    const grid_leaves *d = &g->leaves;
    if (!has_directory(type) || !d->top || !(fabsf(x[0]) < 1e9f && fabsf(x[1]) < 1e9f && fabsf(x[2]) < 1e9f))
        return;
    const int32_t c[3] = {ifloor(x[0]), ifloor(x[1]), ifloor(x[2])};
    uint32_t local;
    const uint32_t *e = directory_chunk(d, c, &local);
    const uint32_t w = e ? e[local] : 0u;
    if (w < GRID_TILE_MARKERS) { /* no leaf known here: the far bound will be read */
        const grid_far *f = &g->far;
        float t[3], out2;
        const uint16_t *corner = far_cell_corner(f, x, t, &out2);
        if (!corner)
            return;
        const size_t sx = (size_t)f->n[0] + 1, sy = sx * ((size_t)f->n[1] + 1);
        __builtin_prefetch(corner), __builtin_prefetch(corner + sx);
        __builtin_prefetch(corner + sy), __builtin_prefetch(corner + sy + sx);
        return;
    }
    /* values per word: 1 (float), 2 (Fp16), 4 (Fp8), 8 (Fp4) */
    const unsigned shift = type == PNANOVDB_GRID_TYPE_FLOAT  ? 0u
                           : type == PNANOVDB_GRID_TYPE_FP16 ? 1u
                           : type == PNANOVDB_GRID_TYPE_FP8  ? 2u
                                                             : 3u;
    const uint32_t n = 64u * ((uint32_t)c[0] & 7u) + 8u * ((uint32_t)c[1] & 7u) + ((uint32_t)c[2] & 7u);
    const uint32_t *v = g->words + w;
    __builtin_prefetch(v + (n >> shift)), __builtin_prefetch(v + ((n + 8u) >> shift));
    if ((c[0] & 7) != 7)
        __builtin_prefetch(v + ((n + 64u) >> shift)), __builtin_prefetch(v + ((n + 72u) >> shift));
}

/* The field of `bound` at index point x. TREE: the tree bound in tiles
 * (the first version of the grid field); NONE: trilinear everywhere,
 * +-background beyond the band, only to measure what the bounds save.
 * FAR, the default: in a leaf (the voxel nearest x in a leaf, x's cell
 * known to the directory) the trilinear value, read first and alone: near
 * the surface that is all that is read. The far bound is not asked there,
 * even where the value is the background: inside a leaf b rarely beats
 * the background (a 4^3 cell of the leaf must be empty and x more than
 * 2.3 voxels from every occupied one), and reading its table, a cache
 * miss, cost 2-7% of a frame on the bench's grids for 0.00-0.04% fewer
 * evaluations. Elsewhere TREE's field (the tree bound where the nearest
 * voxel lies in a tile: from the directory's tile marker when it has one,
 * without walking the tree), and where the far bound b applies (x in an
 * empty cell), the larger of b and that. Each is a step the tracer may
 * take (b a proven distance bound, the other the field it traces without
 * the far bound), so the larger is too. Beside leaves b can be as small
 * as its band bonus (0.72 voxels) where the field steps a whole band; once
 * b reaches the band it is taken without looking further. */
GRID_INLINE float sample(const sdft_grid *g, pnanovdb_grid_type_t type, pnanovdb_readaccessor_t *acc, const float x[3],
                         int *level, sdft_grid_bound bound)
{
    if (bound != SDFT_GRID_BOUND_FAR) {
        int vlevel;
        const float v = sample_index(g, type, acc, x, &vlevel, bound == SDFT_GRID_BOUND_TREE);
        if (level)
            *level = vlevel;
        return v;
    }
    float v = 0.0f, near_value = 0.0f;
    pnanovdb_coord_t near_voxel;
    int near_tile = 0, vlevel = 0;
    const int known = sample_leaves(g, type, x, 1, &v, &near_voxel, &near_value, &near_tile);
    if (known && near_tile) { /* TREE's field: the tree bound of an 8^3 tile, where it is of use */
        const float tb = tree_bound(g, x, near_voxel, 1, near_value);
        if (tb > 0.5f * g->sigma_min)
            v = copysignf(tb, near_value), vlevel = 1;
    } else if (known) {
        if (level)
            *level = 0;
        return v;
    }
    const float b = far_bound(g, x); /* 0: does not apply */
    if (b != 0.0f && fabsf(b) >= g->background) {
        if (level)
            *level = 5;
        return b;
    }
    if (!known)
        v = sample_tree(g, type, acc, x, &vlevel, 1);
    if (b == 0.0f || (fabsf(v) > fabsf(b) && (v < 0.0f) == (b < 0.0f))) {
        if (level)
            *level = vlevel;
        return v;
    }
    if (level)
        *level = 5;
    return b;
}

/* One distance function per (float grid, Fp16 grid or any, diagonal
 * transform or not, bound), each with its configuration folded in. */
#define GRID_DISTANCE(name, type, diagonal, bound)                                                                     \
    static float name(const void *ctx, sdft_scratch *s, sdft_vec3 p)                                                   \
    {                                                                                                                  \
        const sdft_grid *g = ctx;                                                                                      \
        float x[3];                                                                                                    \
        to_index(g, diagonal, p, x);                                                                                   \
        return sample(g, type, accessor(s), x, NULL, bound);                                                           \
    }
#define F PNANOVDB_GRID_TYPE_FLOAT
#define H PNANOVDB_GRID_TYPE_FP16
GRID_DISTANCE(distance_float_diag_far, F, 1, SDFT_GRID_BOUND_FAR)
GRID_DISTANCE(distance_float_diag_tree, F, 1, SDFT_GRID_BOUND_TREE)
GRID_DISTANCE(distance_float_diag_none, F, 1, SDFT_GRID_BOUND_NONE)
GRID_DISTANCE(distance_float_full_far, F, 0, SDFT_GRID_BOUND_FAR)
GRID_DISTANCE(distance_float_full_tree, F, 0, SDFT_GRID_BOUND_TREE)
GRID_DISTANCE(distance_float_full_none, F, 0, SDFT_GRID_BOUND_NONE)
GRID_DISTANCE(distance_fp16_any_far, H, g->diagonal, SDFT_GRID_BOUND_FAR)
GRID_DISTANCE(distance_fp16_any_tree, H, g->diagonal, SDFT_GRID_BOUND_TREE)
GRID_DISTANCE(distance_fp16_any_none, H, g->diagonal, SDFT_GRID_BOUND_NONE)
GRID_DISTANCE(distance_any_far, g->type, g->diagonal, SDFT_GRID_BOUND_FAR)
GRID_DISTANCE(distance_any_tree, g->type, g->diagonal, SDFT_GRID_BOUND_TREE)
GRID_DISTANCE(distance_any_none, g->type, g->diagonal, SDFT_GRID_BOUND_NONE)
#undef F
#undef H
#undef GRID_DISTANCE

typedef float (*grid_distance_fn)(const void *ctx, sdft_scratch *s, sdft_vec3 p);

#define GRID_PREFETCH(name, type, diagonal)                                                                            \
    static void name(const void *ctx, sdft_vec3 p)                                                                     \
    {                                                                                                                  \
        const sdft_grid *g = ctx;                                                                                      \
        float x[3];                                                                                                    \
        to_index(g, diagonal, p, x);                                                                                   \
        prefetch_index(g, type, x);                                                                                    \
    }
GRID_PREFETCH(prefetch_float_diag, PNANOVDB_GRID_TYPE_FLOAT, 1)
GRID_PREFETCH(prefetch_float_full, PNANOVDB_GRID_TYPE_FLOAT, 0)
GRID_PREFETCH(prefetch_fp16_any, PNANOVDB_GRID_TYPE_FP16, g->diagonal)
GRID_PREFETCH(prefetch_any, g->type, g->diagonal)
#undef GRID_PREFETCH

/* [kind][bound]: kind 0 float+diagonal, 1 float, 2 Fp16, 3 any other. */
static const grid_distance_fn grid_distances[4][3] = {
    {distance_float_diag_far, distance_float_diag_tree, distance_float_diag_none},
    {distance_float_full_far, distance_float_full_tree, distance_float_full_none},
    {distance_fp16_any_far, distance_fp16_any_tree, distance_fp16_any_none},
    {distance_any_far, distance_any_tree, distance_any_none},
};

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
GRID_INLINE sdft_vec3 normal_of(const sdft_grid *g, pnanovdb_grid_type_t type, sdft_scratch *s, sdft_vec3 p)
{
    pnanovdb_readaccessor_t *acc = accessor(s);
    float x[3], d[3] = {0, 0, 0};
    to_index(g, g->diagonal, p, x);
    if (fabsf(x[0]) < 1e9f && fabsf(x[1]) < 1e9f && fabsf(x[2]) < 1e9f) {
        const pnanovdb_coord_t i0 = {ifloor(x[0]), ifloor(x[1]), ifloor(x[2])};
        const float tx = x[0] - (float)i0.x, ty = x[1] - (float)i0.y, tz = x[2] - (float)i0.z;
        float v[8];
        double q[3][3];
        cell_values(g, type, acc, i0, v);
        cell_gradient_along(v, (const double[3]){tx, ty, tz}, (const double[3]){0.0, 0.0, 0.0}, q);
        d[0] = (float)q[0][0], d[1] = (float)q[0][1], d[2] = (float)q[0][2];
    }
    if (gradient_is_flat(g, d)) {
        static const float k[4][3] = {{1, -1, -1}, {-1, -1, 1}, {-1, 1, -1}, {1, 1, 1}};
        d[0] = d[1] = d[2] = 0.0f;
        for (int i = 0; i < 4; i++) {
            const float at[3] = {x[0] + k[i][0], x[1] + k[i][1], x[2] + k[i][2]};
            const float f = sample_index(g, type, acc, at, NULL, 0);
            d[0] += k[i][0] * f, d[1] += k[i][1] * f, d[2] += k[i][2] * f;
        }
    }
    return world_normal(g, d);
}

static sdft_vec3 normal_float(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    return normal_of(ctx, PNANOVDB_GRID_TYPE_FLOAT, s, p);
}

static sdft_vec3 normal_fp16(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    return normal_of(ctx, PNANOVDB_GRID_TYPE_FP16, s, p);
}

static sdft_vec3 normal_any(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    const sdft_grid *g = ctx;
    return normal_of(g, g->type, s, p);
}

typedef sdft_vec3 (*grid_normal_fn)(const void *ctx, sdft_scratch *s, sdft_vec3 p);

static inline int is_float(const sdft_grid *g) { return g->type == PNANOVDB_GRID_TYPE_FLOAT; }

/* The exact root (grid_root.c) takes over once a ray is this many voxels
 * from the surface: the cells it walks are then about as many as the steps
 * it saves at a head-on hit, and far fewer at a grazing one. */
#define GRID_ROOT_REACH 1.0f

/* The grid's kind for the specialised callbacks: float with a diagonal
 * transform, float, fp16, any other. */
static int grid_kind(const sdft_grid *g)
{
    return is_float(g) ? (g->diagonal ? 0 : 1) : g->type == PNANOVDB_GRID_TYPE_FP16 ? 2 : 3;
}

void grid_accel_init(sdft_grid *g)
{
    static void (*const prefetches[4])(const void *, sdft_vec3) = {prefetch_float_diag, prefetch_float_full,
                                                                   prefetch_fp16_any, prefetch_any};
    g->accel = sdft_field_accel_defaults();
    g->accel.ctx = g;
    g->accel.root = grid_root_for(g);
    g->accel.root_reach = GRID_ROOT_REACH * g->sigma_min;
    g->accel.prefetch = prefetches[grid_kind(g)];
    g->accel.hull = g->hull;
    g->accel.hull_count = g->hull_count;
    g->accel.hull_slabs = g->hull_slab;
    g->accel.hull_gradients = g->hull_gradient;
}

sdft_field sdft_grid_field(const sdft_grid *g, sdft_grid_bound bound)
{
    sdft_field f = sdft_field_defaults();
    if (!g || (unsigned)bound > SDFT_GRID_BOUND_NONE)
        return f;
    sdft_vec3 vs = g->voxel_size;
    const int kind = grid_kind(g);
    static const grid_normal_fn normals[4] = {normal_float, normal_float, normal_fp16, normal_any};
    const int b = bound == SDFT_GRID_BOUND_TREE ? 1 : bound == SDFT_GRID_BOUND_NONE ? 2 : 0;
    f.distance = grid_distances[kind][b];
    f.normal = normals[kind];
    f.scratch_init = grid_scratch_init;
    f.ctx = g;
    f.bounds = g->bounds;
    f.feature_size = sdft_minf(vs.x, sdft_minf(vs.y, vs.z));
    f.accel = &g->accel;
    f.material = g->material_ids ? grid_material : NULL;
    return f;
}

float sdft_grid_sample(const sdft_grid *g, sdft_grid_bound bound, sdft_scratch *s, sdft_vec3 p, int *level)
{
    if (!g || !s || s->owner.ctx != g || s->owner.init != grid_scratch_init) {
        if (level)
            *level = -1;
        return NAN;
    }
    float x[3];
    to_index(g, g->diagonal, p, x);
    if (bound != SDFT_GRID_BOUND_FAR && bound != SDFT_GRID_BOUND_TREE)
        bound = SDFT_GRID_BOUND_NONE;
    return sample(g, g->type, accessor(s), x, level, bound);
}

float sdft_grid_voxel(const sdft_grid *g, int32_t i, int32_t j, int32_t k, int *active)
{
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(&acc, g->root);
    pnanovdb_coord_t ijk = {i, j, k};
    uint32_t level;
    float v = read_value(g, g->type, &acc, ijk, &level);
    if (active) {
        switch (level) {
        case 0:
            *active = pnanovdb_leaf_get_value_mask(g->buf, acc.leaf, pnanovdb_leaf_coord_to_offset(&ijk));
            break;
        case 1:
            *active = pnanovdb_lower_get_value_mask(g->buf, acc.lower, pnanovdb_lower_coord_to_offset(&ijk));
            break;
        case 2:
            *active = pnanovdb_upper_get_value_mask(g->buf, acc.upper, pnanovdb_upper_coord_to_offset(&ijk));
            break;
        case 3: {
            pnanovdb_root_tile_handle_t t = pnanovdb_root_find_tile(g->type, g->buf, g->root, &ijk);
            *active = (int)pnanovdb_root_tile_get_state(g->buf, t);
            break;
        }
        default:
            *active = 0;
        }
    }
    return v;
}
