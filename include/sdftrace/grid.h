/* sdftrace — discrete signed distance fields: NanoVDB grids, in plain C.
 *
 * An `sdft_grid` is one flat, relocatable NanoVDB buffer (a Float, Double,
 * Fp4, Fp8, Fp16 or FpN grid) plus what the sampler needs from its header.
 * It is immutable once made and shared by every thread; each thread samples
 * it through its own NanoVDB read accessor kept in its `sdft_scratch`.
 *
 * sdft_grid_field() turns a grid into an `sdft_field`: trilinear sampling in
 * index space through the grid's transform, normals from the grid's
 * gradient, and outside the narrow band a safe lower bound on the distance
 * (see src/grid/grid_bound.c), so every tracing variant and the renderer
 * take a grid exactly as they take a procedural SDF. Distances are in the
 * grid's world units.
 *
 * One call opens a grid, sdft_grid_open, with an sdft_grid_options that
 * says where from: a `.nvdb` file (here, in C, never through C++) or a
 * NanoVDB buffer in memory, copied, borrowed or adopted. The OpenVDB
 * component's sdft_vdb_open (sdftrace/vdb.h) takes the same options and
 * opens `.vdb` files too. sdft_grid_free releases a grid, however it was
 * opened. Errors follow sdftrace/error.h: an sdft_error and one line in
 * msg; nothing here prints.
 *
 * Choosing a grid (every loader, `.vdb` and `.nvdb` alike): with a `name`,
 * the first grid of that name (SDFT_ENOTFOUND if there is none,
 * SDFT_ENOTSCALAR if it does not hold scalars); with name NULL, the first
 * scalar level set, else the first scalar grid (SDFT_ENOTFOUND for a file
 * with no grid, SDFT_ENOTSCALAR when none is scalar). Scalar: float,
 * double (read as float) and NanoVDB's quantized Fp4, Fp8, Fp16 and FpN. */
#ifndef SDFTRACE_GRID_H
#define SDFTRACE_GRID_H

#include <stddef.h>
#include <stdint.h>

#include "field.h"
#include "sdftrace/config.h"
#include "sdftrace/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sdft_grid sdft_grid;

/* How a grid in memory is taken (sdft_grid_options.memory). */
typedef enum sdft_grid_memory {
    /* The chosen grid's bytes are copied and validated (sizes, node
     * offsets), so a corrupt buffer is an error, never a crash; `data`
     * stays the caller's and may be freed at once. */
    SDFT_GRID_COPY = 0,
    /* Read in place (validated the same way), for a renderer that already
     * holds its NanoVDB grids in memory: the buffer must stay unchanged and
     * alive until sdft_grid_free, which does not free it. The chosen grid
     * must start 32-byte aligned, as NanoVDB lays grids out (SDFT_EINVAL
     * otherwise). The grid still owns what it builds at load (the far
     * bound, the leaf directory). */
    SDFT_GRID_BORROW = 1,
    /* As BORROW, but the grid takes the buffer over: it calls
     * release(data) once, when the grid is freed, or before returning when
     * it refuses the buffer. For a loader that fills a buffer for the grid
     * alone (the OpenVDB component's streamed `.vdb` loading does), without
     * a copy. */
    SDFT_GRID_ADOPT = 2
} sdft_grid_memory;

/* Writes leaf `index` of a deferred grid (the index-th node of the tree's
 * leaf array) whole into `leaf`, its place in the grid's buffer: header,
 * masks and values. 0 on success; non-zero when the values could not be
 * read, after writing the header and masks and NaN values. */
typedef int (*sdft_leaf_fill_fn)(void *user, uint64_t index, void *leaf);

/* Whether a grid's leaves are read only when something first reads them
 * (sdft_grid_options.defer). */
typedef enum sdft_defer {
    SDFT_DEFER_NONE = 0, /* every leaf at load */
    /* Defer where it changes nothing but the time and the memory: a level
     * set whose far bound has cells narrower than a leaf (an active box up
     * to about 1024^3) reads a leaf's active states for it, so such a grid
     * is filled whole at load; wider cells see a leaf as one block, read or
     * not, and the grid is deferred. */
    SDFT_DEFER_WHERE_EXACT = 1,
    /* Always defer: a looser far bound on small level sets (an unread leaf
     * counts as occupied), for the quickest first image. */
    SDFT_DEFER_ALWAYS = 2
} sdft_defer;

/* How a `.vdb` file's grid is stored as NanoVDB (sdft_grid_options.quant,
 * sdft_vdb_open). */
typedef enum sdft_quant {
    SDFT_QUANT_NONE = 0, /* float */
    SDFT_QUANT_FP16,
    SDFT_QUANT_FP8,
    SDFT_QUANT_FP4,
    SDFT_QUANT_FPN /* variable bit rate, NanoVDB's AbsDiff oracle */
} sdft_quant;

/* A long operation's progress: `done` in [0, 1], never decreasing. Return
 * 0 to go on, non-zero to stop (the operation then fails with
 * SDFT_ECANCELED). Called from the operation's worker threads, one call at
 * a time, about once per percent. */
typedef int (*sdft_progress_fn)(void *user, float done);

/* How to open a grid. It will grow: make one with
 * sdft_grid_options_defaults() and set the fields you change. Defaults in
 * brackets. */
typedef struct sdft_grid_options {
    const char *path; /* a `.nvdb` file (uncompressed, as NanoVDB writes by default), or with
                       * sdft_vdb_open a `.vdb` file; NULL: the buffer below [NULL] */
    const char *name; /* the grid to take, chosen as above; NULL: the first scalar level set [NULL] */
    /* A buffer in memory, with path NULL: `size` bytes holding one or more NanoVDB grids back to
     * back (a GridHandle's buffer). */
    const void *data;
    size_t size;
    sdft_grid_memory memory;     /* how data is taken [SDFT_GRID_COPY] */
    void (*release)(void *data); /* SDFT_GRID_ADOPT: called once with data (required there) [NULL] */
    /* Deferred leaves, for a loader that has laid a grid out but not yet filled its leaves (the
     * OpenVDB component's deferred `.vdb` loading): with SDFT_GRID_ADOPT and defer, every node above
     * the leaves must be in place, the leaves' bytes need not be. The grid calls fill(fill_user, i,
     * leaf) the first time anything reads leaf i, from the thread that reads it, at most once per
     * leaf and possibly for several leaves at once, and fill_release(fill_user) (if not NULL, with
     * SDFT_GRID_ADOPT) when it is freed or refuses the buffer. Float and Fp16 grids. Until filled, a leaf counts as
     * occupied for the far bound: still a bound, a looser one. A fill that fails at load is an
     * error (SDFT_EIO); a leaf whose fill failed later reads as NaN, where rays see no surface
     * (sdft_grid_leaf_counts counts them). sdft_grid_data fills every leaf first. [NULL] */
    sdft_leaf_fill_fn fill;
    void *fill_user;
    void (*fill_release)(void *user);
    /* With fill, whether a small level set is filled at load (sdft_defer above). With sdft_vdb_open,
     * lay a `.vdb` grid out and read each leaf's values from the file only when something first
     * reads that leaf (OpenVDB's delayed loading, as vdb_render does): a renderer's first image
     * sooner, and memory for the leaves it reaches; the file must stay unchanged while the grid
     * lives; float and Fp16, streamed. [SDFT_DEFER_NONE] */
    sdft_defer defer;
    /* `.vdb` files (sdft_vdb_open) only: */
    sdft_quant quant;          /* how the NanoVDB copy stores leaf values [SDFT_QUANT_NONE: float] */
    int stream;                /* 1: float and Fp16 copies streamed leaf by leaf; 0: NanoVDB's own
                                * converter with the whole OpenVDB grid in memory (the reference the
                                * tests hold the stream to) [1] */
    sdft_progress_fn progress; /* NULL: no progress reports [NULL] */
    void *progress_user;       /* handed to progress */
    /* A buffer's loader may say what reading it into memory took, in wall ms, for
     * sdft_grid_load_phases to report with the grid's own phases: all of it, and the part that ran
     * on one thread before the first parallel phase. [0, 0] */
    double read_ms, read_serial_ms;
} sdft_grid_options;

/* No path, no buffer (set one), the first level set, copied, every leaf at
 * load; for `.vdb` files float leaves, streamed, no progress reports. */
SDFT_API sdft_grid_options sdft_grid_options_defaults(void);

/* Opens the grid o says into *out, which owns it: free it with
 * sdft_grid_free. On failure *out is NULL (and, with SDFT_GRID_ADOPT of a
 * buffer, release(data) and fill_release(fill_user) have been called). A `.vdb` path is
 * SDFT_EFORMAT here: it needs the OpenVDB component's sdft_vdb_open, which
 * takes the same options. SDFT_EINVAL (NULL o or out; neither path nor
 * data, or size 0; an unknown memory or defer; ADOPT without release;
 * fill without ADOPT and defer, or defer without fill; a borrowed grid not
 * 32-byte aligned; deferred leaves on a grid neither float nor Fp16),
 * SDFT_EIO, SDFT_EFORMAT, SDFT_ENOTFOUND, SDFT_ENOTSCALAR, SDFT_EEMPTY,
 * SDFT_ENOMEM. */
SDFT_API sdft_error sdft_grid_open(const sdft_grid_options *o, sdft_grid **out, char *msg, size_t msg_len);

/* Whether a grid whose active voxels span the index box [lo, hi]
 * (inclusive), a level set or not, with `background`, is deferred under
 * `how`: the rule of sdft_defer, for a loader that lays a grid out and
 * asks before it reads the leaves. 1 or 0. */
SDFT_API int sdft_grid_defers(sdft_defer how, int level_set, float background, const int32_t lo[3],
                              const int32_t hi[3]);

/* What opening a grid took, phase by phase, in wall milliseconds: the
 * work before its first ray. A loader outside this library (a `.vdb` read
 * through OpenVDB) times its own part. */
typedef struct sdft_grid_phases {
    double read_ms;      /* the grid read into memory: a `.nvdb` file's bytes, a `.vdb` file's grid converted; 0 for a
                          * buffer (or what its loader says: sdft_grid_options.read_ms) */
    double serial_ms;    /* the part of read_ms on one thread before the first parallel phase */
    double check_ms;     /* the tree's nodes checked against the buffer */
    double fill_ms;      /* a deferred grid's leaves filled at load (sdft_grid_defers said no) */
    double directory_ms; /* the leaf directory built */
    double tables_ms;    /* the tables the grid stores (sdft_grid_export) found and checked */
    double far_ms;       /* the far bound built (level sets), where the grid does not store it */
    double hull_ms;      /* the hull built (level sets loaded whole), where the grid does not store it */
    int far_stored;      /* 1: the far bound came from the grid's stored tables */
    int hull_stored;     /* 1: the hull did */
} sdft_grid_phases;

/* The phases of g's opening into *phases. */
SDFT_API void sdft_grid_load_phases(const sdft_grid *g, sdft_grid_phases *phases);

/* The grid's NanoVDB bytes with its acceleration tables (the far bound's
 * corners and the hull) stored after them, as NanoVDB blind data that
 * NanoVDB's tools pass through: a grid opened from those bytes (a `.nvdb`
 * file written from them) checks and takes the tables instead of building
 * them, the same field to the bit. The grid's checksum becomes "none" (a
 * writer may set one). A grid that already holds blind data is given as
 * it is. *data: malloc'ed, the caller frees it; *size bytes. A deferred
 * grid's leaves are filled first. SDFT_EINVAL (NULL argument),
 * SDFT_ENOMEM. */
SDFT_API sdft_error sdft_grid_export(const sdft_grid *g, void **data, size_t *size, char *msg, size_t msg_len);

/* A deferred grid's leaves: how many there are, how many are filled so far,
 * and how many of those failed; for a grid loaded whole, all filled and 0
 * failed. */
SDFT_API void sdft_grid_leaf_counts(const sdft_grid *g, uint64_t *leaves, uint64_t *filled, uint64_t *failed);

/* Frees the grid and what it owns (not a borrowed buffer); NULL is fine.
 * Every field of the grid must be out of use. */
SDFT_API void sdft_grid_free(sdft_grid *g);

/* What a grid's field answers where the tree holds no voxels (level sets):
 *   FAR   the default: the distance to the nearest leaf, from a coarse
 *         distance transform built at load (src/grid/grid_bound.c), plus
 *         what the band guarantees; continuous, no tree walk;
 *   TREE  the distance to the boundary of the tile holding the point plus
 *         the band (src/grid/grid_sample.c): a step ends at every tile edge;
 *   NONE  trilinear everywhere, so +-background beyond the band.
 * TREE and NONE are kept to measure what the bounds save. */
typedef enum sdft_grid_bound { SDFT_GRID_BOUND_FAR, SDFT_GRID_BOUND_TREE, SDFT_GRID_BOUND_NONE } sdft_grid_bound;

/* The field of a grid, answering with `bound` beyond the leaves: ctx is
 * the grid itself, which must outlive it, and so is its accel (the exact
 * root, prefetch hints and, on a grid loaded whole, the hull). bounds: the
 * world box of the active voxels' cells; feature_size: the smallest voxel
 * edge. Each thread's scratch must be sdft_scratch_init'ed for it (one
 * scratch serves every field of the same grid). g NULL or an unknown bound
 * gives sdft_field_defaults(), which sdft_trace and sdft_render refuse. */
SDFT_API sdft_field sdft_grid_field(const sdft_grid *g, sdft_grid_bound bound);

/* Queries; g must not be NULL. Strings are owned by the grid and live as
 * long as it does. */
SDFT_API const char *sdft_grid_name(const sdft_grid *g);
SDFT_API const char *sdft_grid_type_name(const sdft_grid *g);  /* "float", "double", "fp16", "fp8", "fp4", "fpN" */
SDFT_API const char *sdft_grid_class_name(const sdft_grid *g); /* "level set", "fog volume", "unknown", ... */
SDFT_API int sdft_grid_is_level_set(const sdft_grid *g);
SDFT_API sdft_vec3 sdft_grid_voxel_size(const sdft_grid *g); /* world units per voxel along x, y, z */
SDFT_API float sdft_grid_background(const sdft_grid *g);     /* world units; a level set's band half-width */
SDFT_API uint64_t sdft_grid_active_voxels(const sdft_grid *g);
/* Active voxels' index box (inclusive) and the world box of their cells. */
SDFT_API void sdft_grid_index_bounds(const sdft_grid *g, int32_t lo[3], int32_t hi[3]);
SDFT_API sdft_aabb sdft_grid_world_bounds(const sdft_grid *g);
/* The grid's bytes (one NanoVDB grid, 32-byte aligned), e.g. for a GPU:
 * owned by the grid (or, borrowed, by whoever lent them); *size in bytes.
 * A deferred grid fills all its leaves first. */
SDFT_API const void *sdft_grid_data(const sdft_grid *g, size_t *size);
/* The grid's size in bytes, as sdft_grid_data gives it, without filling a
 * deferred grid's leaves (their pages are not resident until filled). */
SDFT_API size_t sdft_grid_size(const sdft_grid *g);

/* The stored value of voxel (i, j, k) (background outside the tree) and its
 * active state (active may be NULL); for tests and tools. */
SDFT_API float sdft_grid_voxel(const sdft_grid *g, int32_t i, int32_t j, int32_t k, int *active);

/* Materials on a grid's surface, for shading (sdft_field.material). The
 * convention `sdftrace bake --materials` writes, in the surface's own file:
 *   NAME.material_ids    a float grid of material indices k (0, 1, ...),
 *                        active over the band around the surface;
 *   NAME.material_table  a float grid whose voxels (k, 0..4, 0), all active,
 *                        hold material k: red, green, blue, reflectance,
 *                        index of refraction (sdft_material's members).
 * Open them as any grid (by name) and hand them over below. */
#define SDFT_GRID_MAX_MATERIALS 4096

/* Gives g's fields a material: at world point p, table[k] for the k the
 * voxel of `ids` nearest p holds (its own transform places it; where that
 * voxel is inactive, the nearest active one of its 26 neighbours; an index
 * outside the table is clamped into it). The table (count entries, at most
 * SDFT_GRID_MAX_MATERIALS) is copied; ids is borrowed and must outlive
 * every field of g. A step of making g, before any field of it is made or
 * used: fields made afterwards (sdft_grid_field) carry the materials. ids
 * NULL takes them away. SDFT_EINVAL (g NULL; a NULL or empty table, too
 * long; a colour or reflectance outside [0, 1], an index of refraction
 * neither 0 nor >= 1), SDFT_ENOMEM. */
SDFT_API sdft_error sdft_grid_set_materials(sdft_grid *g, const sdft_grid *ids, const sdft_material *table,
                                            size_t count, char *msg, size_t msg_len);

/* Reads a material table grid (above) into table[0..most): *count entries,
 * from voxel row k = 0 on, up to the first inactive one. SDFT_EINVAL (a
 * NULL argument; more than `most` entries), SDFT_EFORMAT (no entry, an
 * entry missing a component or out of range). */
SDFT_API sdft_error sdft_grid_material_table(const sdft_grid *t, sdft_material *table, size_t most, size_t *count,
                                             char *msg, size_t msg_len);

/* What the field with `bound` does at world point p, spelled out: the far
 * bound (*level 5), else the trilinear value where the tree holds voxels
 * (*level 0), else the tree bound of the tile or empty root region (*level
 * 1..4: lower tile, upper tile, root tile, background). World units. s
 * must have been prepared for a field of g (sdft_scratch_init): otherwise
 * the answer is NaN with *level -1, never a read through another grid's
 * accessor. level may be NULL. */
SDFT_API float sdft_grid_sample(const sdft_grid *g, sdft_grid_bound bound, sdft_scratch *s, sdft_vec3 p, int *level);

#ifdef __cplusplus
}
#endif
#endif
