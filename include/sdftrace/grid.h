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
 * Grids come from `.nvdb` files (here, in C, never through C++), from a
 * NanoVDB buffer in memory, copied or borrowed, or from `.vdb` files
 * through the OpenVDB component (sdftrace/vdb.h). Errors follow
 * sdftrace/error.h: an sdft_error and one line in msg; nothing here prints.
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

/* Loads one grid of a `.nvdb` file (uncompressed, as NanoVDB writes by
 * default), chosen as above. On success *out owns a copy of the grid's
 * bytes: free it with sdft_grid_free. On failure *out is NULL. SDFT_EINVAL
 * (NULL path or out), SDFT_EIO, SDFT_EFORMAT, SDFT_ENOTFOUND,
 * SDFT_ENOTSCALAR, SDFT_EEMPTY, SDFT_ENOMEM. */
SDFT_API sdft_error sdft_grid_load_nvdb(const char *path, const char *name, sdft_grid **out, char *msg, size_t msg_len);

/* Makes a grid from `size` bytes holding one or more NanoVDB grids back to
 * back (a GridHandle's buffer), chosen as above. The chosen grid's bytes are
 * copied and validated (sizes, node offsets), so a corrupt buffer is an
 * error, never a crash; `data` stays the caller's and may be freed at once.
 * Free the grid with sdft_grid_free. Errors as sdft_grid_load_nvdb, less
 * SDFT_EIO. */
SDFT_API sdft_error sdft_grid_from_buffer(const void *data, size_t size, const char *name, sdft_grid **out, char *msg,
                                          size_t msg_len);

/* As sdft_grid_from_buffer, without the copy: the grid reads the caller's
 * bytes in place (validated the same way), for a renderer that already
 * holds its NanoVDB grids in memory. The buffer stays the caller's: it must
 * stay unchanged and alive until sdft_grid_free, which does not free it.
 * The chosen grid must start 32-byte aligned, as NanoVDB lays grids out
 * (SDFT_EINVAL otherwise). The grid still owns what it builds at load (the
 * far bound, the leaf directory). */
SDFT_API sdft_error sdft_grid_borrow_buffer(const void *data, size_t size, const char *name, sdft_grid **out, char *msg,
                                            size_t msg_len);

/* As sdft_grid_borrow_buffer, but the grid takes the buffer over: it calls
 * release(data) once, when the grid is freed, or before returning when it
 * refuses the buffer (any error but a NULL release, SDFT_EINVAL). For a
 * loader that fills a buffer for the grid alone (the OpenVDB component's
 * streamed `.vdb` loading does), without a copy. */
SDFT_API sdft_error sdft_grid_adopt_buffer(void *data, size_t size, const char *name, void (*release)(void *data),
                                           sdft_grid **out, char *msg, size_t msg_len);

/* Writes leaf `index` of a deferred grid (the index-th node of the tree's
 * leaf array) whole into `leaf`, its place in the grid's buffer: header,
 * masks and values. 0 on success; non-zero when the values could not be
 * read, after writing the header and masks and NaN values. */
typedef int (*sdft_leaf_fill_fn)(void *user, uint64_t index, void *leaf);

/* How a deferred grid defers (sdft_grid_adopt_deferred's `how`). */
typedef enum sdft_defer {
    /* Defer where it changes nothing but the time and the memory: a level
     * set whose far bound has cells narrower than a leaf (an active box up
     * to about 1024^3) reads a leaf's active states for it, so such a grid
     * is filled whole at load; wider cells see a leaf as one block, read or
     * not, and the grid is deferred. */
    SDFT_DEFER_WHERE_EXACT = 0,
    /* Always defer: a looser far bound on small level sets (an unread leaf
     * counts as occupied), for the quickest first image. */
    SDFT_DEFER_ALWAYS = 1
} sdft_defer;

/* As sdft_grid_adopt_buffer, for a loader that has laid a grid out but not
 * yet filled its leaves (the OpenVDB component's deferred `.vdb` loading):
 * every node above the leaves must be in place; the leaves' bytes need not
 * be. The grid calls fill(user, i, leaf) the first time anything reads
 * leaf i, from the thread that reads it, at most once per leaf and possibly
 * for several leaves at once, and release_user(user) (if not NULL) when it
 * is freed or refuses the buffer. Float and Fp16 grids (SDFT_EINVAL for
 * others, a NULL fill or an unknown `how`). `how` says whether a small
 * level set is filled at load (sdft_defer above); until filled, a leaf
 * counts as occupied for the far bound: still a bound, a looser one. A fill
 * that fails at load is an error (SDFT_EIO). A leaf whose fill failed reads as
 * NaN, where rays see no surface; sdft_grid_leaf_counts counts them.
 * sdft_grid_data fills every leaf first. */
SDFT_API sdft_error sdft_grid_adopt_deferred(void *data, size_t size, const char *name, void (*release)(void *data),
                                             sdft_leaf_fill_fn fill, void *user, void (*release_user)(void *user),
                                             sdft_defer how, sdft_grid **out, char *msg, size_t msg_len);

/* A deferred grid's leaves: how many there are, how many are filled so far,
 * and how many of those failed; for a grid loaded whole, all filled and 0
 * failed. */
SDFT_API void sdft_grid_leaf_counts(const sdft_grid *g, uint64_t *leaves, uint64_t *filled, uint64_t *failed);

/* Frees the grid and what it owns (not a borrowed buffer); NULL is fine.
 * Every field of the grid must be out of use. */
SDFT_API void sdft_grid_free(sdft_grid *g);

/* The field of a grid: ctx is the grid itself, which must outlive it.
 * bounds: the world box of the active voxels' cells; feature_size: the
 * smallest voxel edge. Beyond the leaves it answers with the far bound.
 * Each thread's scratch must be sdft_scratch_init'ed for it (one scratch
 * serves every field of the same grid). g NULL gives an all-zero field,
 * which sdft_trace and sdft_render refuse. */
SDFT_API sdft_field sdft_grid_field(const sdft_grid *g);

/* What a grid's field answers where the tree holds no voxels (level sets):
 *   FAR   the default: the distance to the nearest leaf, from a coarse
 *         distance transform built at load (src/grid/grid_bound.c), plus
 *         what the band guarantees; continuous, no tree walk;
 *   TREE  the distance to the boundary of the tile holding the point plus
 *         the band (src/grid/grid_sample.c): a step ends at every tile edge;
 *   NONE  trilinear everywhere, so +-background beyond the band.
 * TREE and NONE are kept to measure what the bounds save. */
typedef enum sdft_grid_bound { SDFT_GRID_BOUND_FAR, SDFT_GRID_BOUND_TREE, SDFT_GRID_BOUND_NONE } sdft_grid_bound;
/* An unknown bound, like g NULL, gives an all-zero field. */
SDFT_API sdft_field sdft_grid_field_with(const sdft_grid *g, sdft_grid_bound bound);

/* sdft_grid_field_with(g, SDFT_GRID_BOUND_NONE). */
SDFT_API sdft_field sdft_grid_field_without_bound(const sdft_grid *g);

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

/* What the field with `bound` does at world point p, spelled out: the far
 * bound (*level 5), else the trilinear value where the tree holds voxels
 * (*level 0), else the tree bound of the tile or empty root region (*level
 * 1..4: lower tile, upper tile, root tile, background). World units.
 * sdft_grid_sample is the default field's (SDFT_GRID_BOUND_FAR). s must have
 * been prepared for a field of g (sdft_scratch_init): otherwise the answer
 * is NaN with *level -1, never a read through another grid's accessor.
 * level may be NULL. */
SDFT_API float sdft_grid_sample_with(const sdft_grid *g, sdft_grid_bound bound, sdft_scratch *s, sdft_vec3 p,
                                     int *level);
SDFT_API float sdft_grid_sample(const sdft_grid *g, sdft_scratch *s, sdft_vec3 p, int *level);

#ifdef __cplusplus
}
#endif
#endif
