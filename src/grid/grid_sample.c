/* sdftrace — a NanoVDB grid as a field: the library's side of the
 * sampler in src/portable/grid_sample.h (trilinear sampling through the
 * leaf directory and the read accessor, the tree bound and the far bound,
 * the normal), specialised per grid type, transform shape and bound; one
 * read accessor per thread, kept in the caller's sdft_scratch; and the
 * prefetch hints. */
#include <math.h>

#include "grid_sample.h"

static void grid_scratch_init(const void *ctx, sdft_scratch *s)
{
    const sdft_grid *g = ctx;
    pnanovdb_readaccessor_init(accessor(s), g->root);
}

/* Starts loading what sample_at() at index point x will read: the leaf
 * directory's entry for x's cell and, in a leaf, the cell's four rows of
 * two voxels (z is the fastest axis, so each row is one or two adjacent
 * values); beside no leaf, the far bound's corners. Plain loads of the
 * directory (small, mostly cached) and prefetches of the rest, so that a
 * caller's scattered points wait for their memory together (the field's
 * prefetch hint; the tracer does not use it, field.h). Reads nothing it
 * cannot bound: x's block is checked as in cell_from_leaves. */
PORT_INLINE void prefetch_index(const sdft_grid *g, pnanovdb_grid_type_t type, const float x[3])
{
    if (!has_directory(type) || !g->leaves.top || !(fabsf(x[0]) < 1e9f && fabsf(x[1]) < 1e9f && fabsf(x[2]) < 1e9f))
        return;
    const int32_t c[3] = {ifloor(x[0]), ifloor(x[1]), ifloor(x[2])};
    uint32_t local;
    const uint32_t *e;
    const uint32_t w = directory_chunk(g, c, &local, &e) ? e[local] : 0u;
    if (w < GRID_TILE_MARKERS) { /* no leaf known here: the far bound will be read */
        const grid_far *f = &g->far;
        float t[3], out2;
        const uint16_t *corner;
        if (!far_cell_corner(g, x, t, &out2, &corner))
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

/* One distance function per (float grid, Fp16 grid or any, diagonal
 * transform or not, bound), each with its configuration folded in. */
#define GRID_DISTANCE(name, type, diagonal, bound)                                                                     \
    static float name(const void *ctx, sdft_scratch *s, sdft_vec3 p)                                                   \
    {                                                                                                                  \
        const sdft_grid *g = ctx;                                                                                      \
        return grid_distance(g, type, diagonal, accessor(s), p, bound);                                                \
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

static sdft_vec3 normal_float(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    return normal_of(ctx, PNANOVDB_GRID_TYPE_FLOAT, accessor(s), p);
}

static sdft_vec3 normal_fp16(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    return normal_of(ctx, PNANOVDB_GRID_TYPE_FP16, accessor(s), p);
}

static sdft_vec3 normal_any(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    const sdft_grid *g = ctx;
    return normal_of(g, g->type, accessor(s), p);
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
    int at_level;
    const float v = sample_at(g, g->type, accessor(s), x, &at_level, bound);
    if (level)
        *level = at_level;
    return v;
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
