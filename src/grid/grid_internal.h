/* sdftrace — what the grid loader and the grid sampler share: the grid
 * object itself. Internal header; C only, through PNanoVDB.h. */
#ifndef SDFTRACE_GRID_INTERNAL_H
#define SDFTRACE_GRID_INTERNAL_H

#include <math.h>

#define PNANOVDB_C
#include <nanovdb/PNanoVDB.h>

#include "fail.h"
#include "grid_layout.h"
#include "sdftrace/grid.h"

/* The far bound (grid_bound.c): cells of `cell`^3 voxels over the active
 * box (4^3, half a leaf's edge, unless the box is too big for the table's
 * cap), each occupied (it holds an active voxel, or inactive values of both
 * signs) or empty with its values' sign; and at the cells' corners the
 * index distance to the occupied ones. Both in one table of 16-bit words,
 * so a lookup reads four cache lines, not five, and a 1024^3 grid's table
 * (32 MiB) mostly stays in cache. */
typedef struct grid_far {
    uint16_t *corner; /* (n[0] + 1) x (n[1] + 1) x (n[2] + 1) corners, x fastest; NULL: no far bound.
                       * Bits 0-13: the index distance x 4, rounded down, saturated (still a bound);
                       * bits 14-15: the cell whose lowest corner this is: FAR_EMPTY_POSITIVE or
                       * FAR_EMPTY_NEGATIVE when empty, 0 when occupied or there is none */
    int32_t c0[3];    /* first cell, in cells */
    int n[3];         /* cells per axis */
    int cell;         /* S: voxels per cell edge, 4 * 2^k */
    float inv_cell;   /* 1 / S */
    float origin[3];  /* index coordinates of corner 0: c0 S - 1/2 */
    float bonus;      /* world units added to smin e(x): the band's guarantee */
    int stored;       /* 1: corner lies in the grid's own bytes (grid_tables.c), not ours to free */
} grid_far;

/* FAR_DISTANCE_BITS, FAR_EMPTY_POSITIVE, FAR_EMPTY_NEGATIVE and
 * FAR_DISTANCE_SCALE: grid_layout.h. */

/* The leaf directory (grid_leaves.c): for each region of 8^3 blocks of
 * the active box, a chunk of 9^3 entries (the region's blocks and its
 * one-block apron on the + sides), each the word offset in the grid's
 * buffer of that block's leaf value table; where it has no leaf,
 * GRID_TILE_POSITIVE / GRID_TILE_NEGATIVE for a tile of value +background
 * / -background, else 0. Float, Fp16, Fp8 and Fp4 grids; top NULL: none
 * (the accessor serves). */
/* GRID_CHUNK_SIDE, GRID_CHUNK_ENTRIES and the markers GRID_TILE_POSITIVE,
 * GRID_TILE_NEGATIVE (below GRID_TILE_MARKERS, under any value table's
 * word): grid_layout.h. */
typedef struct grid_leaves {
    uint32_t *top;   /* nr[0] x nr[1] x nr[2] regions, x fastest: chunk index + 1, 0 none */
    uint32_t *chunk; /* chunks x GRID_CHUNK_ENTRIES, x fastest */
    int32_t r0[3];   /* first region, in regions (index >> 6) */
    int nr[3];       /* regions per axis */
    size_t chunks;
} grid_leaves;

/* A deferred grid's leaves (grid_deferred.c): filled by `fill` on first
 * read. state: per leaf, LEAF_EMPTY, LEAF_FILLING or LEAF_READY (atomic);
 * NULL for a grid loaded whole. Leaf i lies at byte first + i * stride. */
enum { LEAF_EMPTY = 0, LEAF_FILLING = 1, LEAF_READY = 2 };
typedef struct grid_deferred {
    uint8_t *state;
    sdft_leaf_fill_fn fill;
    void *user;
    void (*release_user)(void *user);
    uint64_t first, stride, count;
    uint64_t filled, failed; /* atomic counts */
    sdft_defer how;
} grid_deferred;

/* The index of the deferred leaf at byte `at`, or d->count when `at` is not
 * the start of one of them (below first wraps above count). */
static inline uint64_t deferred_leaf_index(const grid_deferred *d, uint64_t at)
{
    const uint64_t i = (at - d->first) / d->stride;
    return i < d->count && at == d->first + i * d->stride ? i : d->count;
}

/* One NanoVDB grid plus the numbers the sampler reads on every call,
 * decoded once from the grid's header. Immutable after loading. */
struct sdft_grid {
    uint32_t *words;         /* the grid's bytes, 64-byte aligned when owned */
    int owned;               /* 1: words is ours to free; 0: borrowed or adopted (SDFT_GRID_BORROW, _ADOPT) */
    void (*release)(void *); /* adopted (SDFT_GRID_ADOPT): release(release_data) when freed */
    void *release_data;
    size_t size; /* bytes */
    pnanovdb_buf_t buf;
    pnanovdb_grid_handle_t grid; /* at address 0 */
    pnanovdb_root_handle_t root;
    pnanovdb_grid_type_t type; /* FLOAT, DOUBLE, FP4, FP8, FP16, FPN */
    uint32_t grid_class;
    float w2i[9], w2i_t[3];     /* index = w2i * world + w2i_t */
    float i2w[9], i2w_t[3];     /* world = i2w * index + i2w_t */
    int diagonal;               /* w2i's off-diagonal entries are all 0: index = w2i[4k] world + w2i_t */
    float sigma_min, sigma_max; /* world length of a unit index step: bounds on i2w's singular values */
    float background;           /* world units */
    sdft_vec3 voxel_size;
    int32_t ilo[3], ihi[3];   /* active voxels' index box, inclusive */
    sdft_aabb bounds;         /* world box of those voxels' cells */
    grid_far far;             /* the far bound; built at load for level sets */
    grid_leaves leaves;       /* the leaf directory; built at load for float grids */
    grid_deferred deferred;   /* leaves filled on first read; state NULL: all there */
    sdft_aabb *hull;          /* the hull (grid_hull.c): world boxes of the leaves' cells; NULL: none */
    sdft_slab *hull_slab;     /* with each box, a world slab that holds its cells too */
    sdft_aabb *hull_gradient; /* with each box, world bounds on its cells' gradients */
    size_t hull_count;
    int hull_stored;         /* 1: the hull's arrays lie in the grid's own bytes (grid_tables.c) */
    sdft_field_accel accel;  /* what its fields point to (grid_accel_init) */
    sdft_grid_phases phases; /* what loading it took (sdft_grid_load_phases) */
    /* Its surface's materials (sdft_grid_set_materials, grid_material.c): the grid of indices
     * into the table; NULL: none. */
    const sdft_grid *material_ids;
    sdft_material *material_table;
    size_t material_count;
    char name[256];
};

/* The world point of index point x under g's transform. */
static inline sdft_vec3 grid_index_to_world(const sdft_grid *g, const float x[3])
{
    const float *m = g->i2w;
    return sdft_v3(m[0] * x[0] + m[1] * x[1] + m[2] * x[2] + g->i2w_t[0],
                   m[3] * x[0] + m[4] * x[1] + m[5] * x[2] + g->i2w_t[1],
                   m[6] * x[0] + m[7] * x[1] + m[8] * x[2] + g->i2w_t[2]);
}

/* The world box that holds the index box [lo, hi] under g's transform:
 * its eight corners' hull. */
static inline sdft_aabb grid_world_box(const sdft_grid *g, const float lo[3], const float hi[3])
{
    sdft_vec3 wlo = sdft_v3(INFINITY, INFINITY, INFINITY), whi = sdft_scale(wlo, -1.0f);
    for (int c = 0; c < 8; c++) {
        const float x[3] = {(c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1], (c & 4) ? hi[2] : lo[2]};
        const sdft_vec3 w = grid_index_to_world(g, x);
        wlo = sdft_min_v(wlo, w), whi = sdft_max_v(whi, w);
    }
    return (sdft_aabb){wlo, whi};
}

/* Decodes and checks a grid already copied into g->words / g->size. */
sdft_error grid_init(sdft_grid *g, char *msg, size_t msg_len);

/* Builds / frees g->far (grid_bound.c). Needs g fully decoded, its
 * directory included. SDFT_OK or SDFT_ENOMEM. */
sdft_error grid_far_build(sdft_grid *g);
/* Lays far's cells and constants over g (no table), as grid_far_build
 * would; 1 when g gets a far bound (a level set, background > 0). */
int grid_far_plan(const sdft_grid *g, grid_far *far);
int grid_far_cell(const int32_t lo[3],
                  const int32_t hi[3]); /* the S grid_far_build picks for a box: voxels per cell edge */
sdft_error grid_far_build_cells(sdft_grid *g, size_t most_cells); /* cells of 4 * 2^k voxels, at most most_cells */
void grid_far_free(sdft_grid *g);

/* Builds / frees g->leaves (grid_leaves.c). Needs g fully decoded. SDFT_OK
 * (also when the grid gets no directory) or SDFT_ENOMEM. */
sdft_error grid_leaves_build(sdft_grid *g);
/* Enters a deferred leaf, just filled, into the directory: block b (index >> 3), value table at `word`. */
void grid_leaves_publish(const sdft_grid *g, const int32_t b[3], uint32_t word);
/* Calls visit(ctx, block (index >> 3), byte offset, value table word) for each leaf the tree reaches,
 * without reading the leaves (grid_leaves.c). */
typedef void (*leaf_visit)(void *ctx, const int32_t b[3], uint64_t at, uint32_t word);
void grid_each_leaf(const sdft_grid *g, leaf_visit visit, void *ctx);

/* Deferred leaves (grid_deferred.c). init: after decoding, before the directory; free: with the grid. */
sdft_error grid_deferred_init(sdft_grid *g);
void grid_deferred_free(sdft_grid *g);
/* Fills the leaf at byte `at` that holds voxel ijk, unless filled (cold; grid_leaf_ready asks). */
void grid_leaf_fill(const sdft_grid *g, uint64_t at, pnanovdb_coord_t ijk);
/* Fills every leaf not yet filled (sdft_grid_data). */
void grid_fill_all(const sdft_grid *g);
/* At load, before the directory: fills every leaf and makes g a grid loaded
 * whole (its loader's user is still released with it). The leaves whose
 * fill failed. */
uint64_t grid_deferred_fill_now(sdft_grid *g);
void grid_leaves_free(sdft_grid *g);
size_t grid_leaves_bytes(const sdft_grid *g); /* its tables' size */

/* The exact last-cell root (grid_root.c): the grid's sdft_field_accel.root,
 * specialised for g's type; and its core, the first root in [0, len] of the
 * trilinear interpolant of cell values v (v[k] at corner (k & 1, k >> 1 & 1,
 * k >> 2 & 1)) along u0 + s du in cell-local coordinates: 1 and *s, or 0. */
typedef int (*grid_root_fn)(const void *ctx, sdft_scratch *s, sdft_vec3 org, sdft_vec3 dir, float t0, float t1,
                            float *t, sdft_vec3 *normal, uint32_t *reads);
grid_root_fn grid_root_for(const sdft_grid *g);
int grid_cell_root(const float v[8], const double u0[3], const double du[3], double len, double *s);

/* Builds / frees g->hull (grid_hull.c). Needs g fully decoded. SDFT_OK
 * (also when the grid gets none) or SDFT_ENOMEM. */
sdft_error grid_hull_build(sdft_grid *g);
void grid_hull_free(sdft_grid *g);
int grid_hull_wanted(const sdft_grid *g);    /* whether g gets a hull */
uint64_t grid_hull_most(const sdft_grid *g); /* the most boxes it can have: a leaf's and the face patches' */

/* Takes the far bound and the hull from the tables stored in g's own bytes
 * (grid_tables.c), each where it holds every check; what it does not take
 * is left as it was (NULL), to be built. */
void grid_tables_take(sdft_grid *g);
/* Sets the hashes in the header of the tables that the grid buffer `bytes`
 * (size bytes) stores, for what it holds now (sdft_grid_export; a test's
 * forged tables). Nothing when it stores none. */
void grid_tables_seal(void *bytes, size_t size);

/* Fills g->accel, which every field of g points to: its exact root,
 * prefetch hints and hull (grid_sample.c). Last at load, after the hull. */
void grid_accel_init(sdft_grid *g);

/* The material at world point p of a grid with materials (grid_material.c):
 * its fields' sdft_field.material, ctx the grid. */
sdft_material grid_material(const void *ctx, sdft_vec3 p);

/* Memory for a big table (grid_memory.c): 64-byte aligned; free() releases
 * it. */
void *grid_table_alloc(size_t bytes);

_Static_assert(sizeof(pnanovdb_readaccessor_t) <= SDFT_SCRATCH_BYTES, "a read accessor must fit a thread's scratch");

/* A thread's read accessor, kept in its scratch. */
static inline pnanovdb_readaccessor_t *accessor(sdft_scratch *s) { return (pnanovdb_readaccessor_t *)(void *)s->bytes; }

/* A deferred grid's leaf at byte `at`, holding voxel ijk, filled if it is
 * not yet (grid_deferred.c); nothing for a grid loaded whole, or for an
 * address that is not one of its leaves (a corrupt child offset is then
 * read as it stands, as in any grid, never filled out of place). */
static inline __attribute__((always_inline)) void grid_leaf_ready(const sdft_grid *g, uint64_t at, pnanovdb_coord_t ijk)
{
    const grid_deferred *d = &g->deferred;
    if (!d->state)
        return;
    const uint64_t i = deferred_leaf_index(d, at);
    if (i < d->count && __atomic_load_n(&d->state[i], __ATOMIC_ACQUIRE) != LEAF_READY)
        grid_leaf_fill(g, at, ijk);
}

#endif
