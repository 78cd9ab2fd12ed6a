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

#include "grid_internal.h"

_Static_assert(sizeof(pnanovdb_readaccessor_t) <= SDFT_SCRATCH_BYTES, "a read accessor must fit a thread's scratch");

static inline pnanovdb_readaccessor_t *accessor(sdft_scratch *s) { return (pnanovdb_readaccessor_t *)(void *)s->bytes; }

/* The hot path is written once and instantiated per grid type, transform
 * shape and bound (the GRID_DISTANCE table below), so the loop a ray runs
 * never branches on configuration; these helpers must inline to fold. */
#if defined(__GNUC__)
#define GRID_INLINE static inline __attribute__((always_inline))
#define GRID_COLD static __attribute__((noinline))
#else
#define GRID_INLINE static inline
#define GRID_COLD static
#endif

static void grid_scratch_init(const void *ctx, sdft_scratch *s)
{
    const sdft_grid *g = ctx;
    pnanovdb_readaccessor_init(accessor(s), g->root);
}

/* The stored value at voxel ijk and the tree level it came from
 * (0 leaf, 1 lower-node tile, 2 upper-node tile, 3 root tile, 4 background).
 * `type` is g->type, or a constant where the caller is specialised. */
GRID_INLINE float read_value(const sdft_grid *g, pnanovdb_grid_type_t type, pnanovdb_readaccessor_t *acc,
                             pnanovdb_coord_t ijk, uint32_t *level)
{
    pnanovdb_address_t a = pnanovdb_readaccessor_get_value_address_and_level(type, g->buf, acc, &ijk, level);
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

static inline float lerp(float a, float b, float t) { return a + (b - a) * t; }

static inline float word_float(const sdft_grid *g, uint32_t w)
{
    return pnanovdb_read_float(g->buf, (pnanovdb_address_t){4u * w});
}

/* The eight values of the cell whose lowest corner is i0 (v[k]: corner
 * i0 + (k & 1, k >> 1 & 1, k >> 2 & 1)), read through the leaf directory
 * (grid_leaves.c); 0 when a corner lies in no leaf (the accessor's path
 * then). Per axis the cell's two voxel layers are the same block at
 * offsets o and o + 1, or, when o = 7, two blocks at offsets 7 and 0; a
 * value sits at 64, 8 and 1 words per x, y and z offset in its leaf. */
GRID_INLINE int cell_from_leaves(const sdft_grid *g, pnanovdb_coord_t i0, float v[8])
{
    const grid_leaves *d = &g->leaves;
    const int32_t c[3] = {i0.x, i0.y, i0.z};
    const size_t stride[3] = {1, (size_t)d->n[0], (size_t)d->n[0] * (size_t)d->n[1]};
    static const uint32_t per_offset[3] = {64u, 8u, 1u};
    size_t block[3][2];
    uint32_t offset[3][2];
    for (int k = 0; k < 3; k++) {
        const uint32_t b = (uint32_t)((c[k] >> 3) - d->b0[k]), o = (uint32_t)(c[k] & 7);
        const uint32_t b1 = b + (o == 7u);
        if (b >= (uint32_t)d->n[k] || b1 >= (uint32_t)d->n[k]) /* below b0 wraps above n */
            return 0;
        block[k][0] = b * stride[k], block[k][1] = b1 * stride[k];
        offset[k][0] = o * per_offset[k], offset[k][1] = ((o + 1u) & 7u) * per_offset[k];
    }
    for (int k = 0; k < 8; k++) {
        const int x = k & 1, y = k >> 1 & 1, z = k >> 2 & 1;
        const uint32_t w = d->word[block[0][x] + block[1][y] + block[2][z]];
        if (!w)
            return 0;
        v[k] = word_float(g, w + offset[0][x] + offset[1][y] + offset[2][z]);
    }
    return 1;
}

static inline float trilerp(const float v[8], float tx, float ty, float tz)
{
    float x00 = lerp(v[0], v[1], tx), x10 = lerp(v[2], v[3], tx);
    float x01 = lerp(v[4], v[5], tx), x11 = lerp(v[6], v[7], tx);
    return lerp(lerp(x00, x10, ty), lerp(x01, x11, ty), tz);
}

/* The trilinear value at index point x when the leaf directory holds all
 * eight corners of x's cell (float grids); 0 if not. */
GRID_INLINE int sample_leaves(const sdft_grid *g, const float x[3], float *value)
{
    if (!g->leaves.word || !(fabsf(x[0]) < 1e9f && fabsf(x[1]) < 1e9f && fabsf(x[2]) < 1e9f))
        return 0;
    const pnanovdb_coord_t i0 = {ifloor(x[0]), ifloor(x[1]), ifloor(x[2])};
    float v[8];
    if (!cell_from_leaves(g, i0, v))
        return 0;
    *value = trilerp(v, x[0] - (float)i0.x, x[1] - (float)i0.y, x[2] - (float)i0.z);
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
    if (type == PNANOVDB_GRID_TYPE_FLOAT && sample_leaves(g, x, &v)) {
        if (level)
            *level = 0;
        return v;
    }
    return sample_tree(g, type, acc, x, level, bound);
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
    if (!f->corner)
        return 0.0f;
    float t[3], out2 = 0.0f;
    int c[3];
    for (int k = 0; k < 3; k++) {
        const float u = (x[k] - f->origin[k]) * f->inv_cell;
        if (!(fabsf(u) < 1e9f)) /* NaN or absurdly far */
            return 0.0f;
        const float uc = sdft_minf(sdft_maxf(u, 0.0f), (float)f->n[k]);
        out2 += (u - uc) * (u - uc);
        c[k] = (int)uc - ((int)uc == f->n[k]);
        t[k] = uc - (float)c[k];
    }
    const size_t sx = (size_t)f->n[0] + 1, sy = sx * ((size_t)f->n[1] + 1);
    const uint16_t *d = f->corner + (size_t)c[2] * sy + (size_t)c[1] * sx + (size_t)c[0];
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

/* The field of `bound` at index point x. TREE: the tree bound in tiles
 * (the first version of the grid field); NONE: trilinear everywhere,
 * +-background beyond the band, only to measure what the bounds save.
 * FAR, the default: where the far bound b applies (x in an empty cell),
 * the larger of b and TREE's field, else TREE's field (the trilinear value
 * in leaves). Each is a step the tracer may take (b a proven distance
 * bound, the other the field it traces without the far bound), so the
 * larger is too. Beside leaves b can be as small as its band bonus (0.72
 * voxels) where the field steps a whole band; once b reaches the band it
 * is taken without looking further. The far bound is read first: away
 * from the surface it is all that is read. */
GRID_INLINE float sample(const sdft_grid *g, pnanovdb_grid_type_t type, pnanovdb_readaccessor_t *acc, const float x[3],
                         int *level, sdft_grid_bound bound)
{
    const float b = bound == SDFT_GRID_BOUND_FAR ? far_bound(g, x) : 0.0f; /* 0: does not apply */
    if (b != 0.0f && fabsf(b) >= g->background) {
        if (level)
            *level = 5;
        return b;
    }
    int vlevel;
    const float v = sample_index(g, type, acc, x, &vlevel, bound != SDFT_GRID_BOUND_NONE);
    if (b == 0.0f || (fabsf(v) > fabsf(b) && (v < 0.0f) == (b < 0.0f))) {
        if (level)
            *level = vlevel;
        return v;
    }
    if (level)
        *level = 5;
    return b;
}

/* One distance function per (float grid or any, diagonal transform or not,
 * bound), each with its configuration folded in. */
#define GRID_DISTANCE(name, type, diagonal, bound)                                                                     \
    static float name(const void *ctx, sdft_scratch *s, sdft_vec3 p)                                                   \
    {                                                                                                                  \
        const sdft_grid *g = ctx;                                                                                      \
        float x[3];                                                                                                    \
        to_index(g, diagonal, p, x);                                                                                   \
        return sample(g, type, accessor(s), x, NULL, bound);                                                           \
    }
#define F PNANOVDB_GRID_TYPE_FLOAT
GRID_DISTANCE(distance_float_diag_far, F, 1, SDFT_GRID_BOUND_FAR)
GRID_DISTANCE(distance_float_diag_tree, F, 1, SDFT_GRID_BOUND_TREE)
GRID_DISTANCE(distance_float_diag_none, F, 1, SDFT_GRID_BOUND_NONE)
GRID_DISTANCE(distance_float_full_far, F, 0, SDFT_GRID_BOUND_FAR)
GRID_DISTANCE(distance_float_full_tree, F, 0, SDFT_GRID_BOUND_TREE)
GRID_DISTANCE(distance_float_full_none, F, 0, SDFT_GRID_BOUND_NONE)
GRID_DISTANCE(distance_any_far, g->type, g->diagonal, SDFT_GRID_BOUND_FAR)
GRID_DISTANCE(distance_any_tree, g->type, g->diagonal, SDFT_GRID_BOUND_TREE)
GRID_DISTANCE(distance_any_none, g->type, g->diagonal, SDFT_GRID_BOUND_NONE)
#undef F
#undef GRID_DISTANCE

typedef float (*grid_distance_fn)(const void *ctx, sdft_scratch *s, sdft_vec3 p);

/* [float, diagonal][bound]: index 0 float+diagonal, 1 float, 2 any other. */
static const grid_distance_fn grid_distances[3][3] = {
    {distance_float_diag_far, distance_float_diag_tree, distance_float_diag_none},
    {distance_float_full_far, distance_float_full_tree, distance_float_full_none},
    {distance_any_far, distance_any_tree, distance_any_none},
};

/* The gradient by tetrahedral differences in index space: four samples at
 * x + k_i, k_i the alternate corners (+-1, +-1, +-1) of the voxel cube
 * around x, whose outer products sum to 4 I, so sum f(x + k_i) k_i is 4
 * times the gradient of a linear field, exactly (central differences take
 * six samples for the same); taken to world space by the inverse
 * transform's transpose. */
GRID_INLINE sdft_vec3 normal_of(const sdft_grid *g, pnanovdb_grid_type_t type, sdft_scratch *s, sdft_vec3 p)
{
    static const float k[4][3] = {{1, -1, -1}, {-1, -1, 1}, {-1, 1, -1}, {1, 1, 1}};
    pnanovdb_readaccessor_t *acc = accessor(s);
    float x[3], d[3] = {0, 0, 0};
    to_index(g, g->diagonal, p, x);
    for (int i = 0; i < 4; i++) {
        const float at[3] = {x[0] + k[i][0], x[1] + k[i][1], x[2] + k[i][2]};
        const float f = sample_index(g, type, acc, at, NULL, 1);
        d[0] += k[i][0] * f, d[1] += k[i][1] * f, d[2] += k[i][2] * f;
    }
    const float *m = g->w2i;
    sdft_vec3 n = sdft_v3(m[0] * d[0] + m[3] * d[1] + m[6] * d[2], m[1] * d[0] + m[4] * d[1] + m[7] * d[2],
                          m[2] * d[0] + m[5] * d[1] + m[8] * d[2]);
    return sdft_normalize(n);
}

static sdft_vec3 normal_float(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    return normal_of(ctx, PNANOVDB_GRID_TYPE_FLOAT, s, p);
}

static sdft_vec3 normal_any(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    const sdft_grid *g = ctx;
    return normal_of(g, g->type, s, p);
}

static inline int is_float(const sdft_grid *g) { return g->type == PNANOVDB_GRID_TYPE_FLOAT; }

sdft_field sdft_grid_field_with(const sdft_grid *g, sdft_grid_bound bound)
{
    if (!g || (unsigned)bound > SDFT_GRID_BOUND_NONE)
        return (sdft_field){0};
    sdft_vec3 vs = g->voxel_size;
    const int kind = !is_float(g) ? 2 : g->diagonal ? 0 : 1;
    const int b = bound == SDFT_GRID_BOUND_TREE ? 1 : bound == SDFT_GRID_BOUND_NONE ? 2 : 0;
    return (sdft_field){
        .distance = grid_distances[kind][b],
        .normal = is_float(g) ? normal_float : normal_any,
        .scratch_init = grid_scratch_init,
        .ctx = g,
        .bounds = g->bounds,
        .feature_size = sdft_minf(vs.x, sdft_minf(vs.y, vs.z)),
    };
}

sdft_field sdft_grid_field(const sdft_grid *g) { return sdft_grid_field_with(g, SDFT_GRID_BOUND_FAR); }

sdft_field sdft_grid_field_without_bound(const sdft_grid *g) { return sdft_grid_field_with(g, SDFT_GRID_BOUND_NONE); }

float sdft_grid_sample_with(const sdft_grid *g, sdft_grid_bound bound, sdft_scratch *s, sdft_vec3 p, int *level)
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

float sdft_grid_sample(const sdft_grid *g, sdft_scratch *s, sdft_vec3 p, int *level)
{
    return sdft_grid_sample_with(g, SDFT_GRID_BOUND_FAR, s, p, level);
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
