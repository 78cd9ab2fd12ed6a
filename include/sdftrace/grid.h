/* sdftrace — discrete signed distance fields: NanoVDB grids.
 *
 * An `sdft_grid` is one flat, relocatable NanoVDB buffer (a Float, Fp4, Fp8,
 * Fp16 or FpN grid) plus what the sampler needs from its header. It is
 * immutable once made and shared by every thread; each thread samples it
 * through its own NanoVDB read accessor kept in its `sdft_scratch`.
 *
 * sdft_grid_field() turns a grid into an `sdft_field`: trilinear sampling in
 * index space through the grid's transform, normals from the grid's
 * gradient, and outside the narrow band a safe lower bound on the distance
 * derived from the tree itself (see src/grid/grid_sample.c), so every tracing
 * variant and the renderer take a grid exactly as they take a procedural SDF.
 *
 * Errors come back as a non-zero code plus one line in `msg` (msg_len bytes,
 * may be NULL); nothing here prints. `.vdb` files are read by the C++ seam
 * (src/vdb/vdb.h), which hands its NanoVDB buffer to sdft_grid_from_buffer. */
#ifndef SDFTRACE_GRID_H
#define SDFTRACE_GRID_H

#include <stddef.h>
#include <stdint.h>

#include "field.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sdft_grid sdft_grid;

typedef enum sdft_grid_error {
    SDFT_GRID_OK = 0,
    SDFT_GRID_EIO,        /* file missing or unreadable */
    SDFT_GRID_EFORMAT,    /* not a NanoVDB file/buffer, corrupt or truncated */
    SDFT_GRID_ENOTSCALAR, /* the chosen grid does not hold scalar floats */
    SDFT_GRID_ENOTFOUND,  /* no grid of that name, or no scalar grid at all */
    SDFT_GRID_EEMPTY,     /* the grid has no active voxels */
    SDFT_GRID_ENOMEM
} sdft_grid_error;

/* Loads one grid of a `.nvdb` file (uncompressed, as NanoVDB writes by
 * default). `name` NULL picks the first scalar level set, else the first
 * scalar grid. On success *out owns a copy of the grid; free it with
 * sdft_grid_free. */
int sdft_grid_load_nvdb(const char *path, const char *name, sdft_grid **out, char *msg, unsigned msg_len);

/* Makes a grid from `size` bytes holding one or more NanoVDB grids back to
 * back (a GridHandle's buffer); selection as above. The bytes are copied and
 * validated (sizes, node offsets), so a corrupt buffer is an error, never a
 * crash. `data` stays the caller's. */
int sdft_grid_from_buffer(const void *data, size_t size, const char *name, sdft_grid **out, char *msg,
                          unsigned msg_len);

void sdft_grid_free(sdft_grid *g);

/* The field of a grid: ctx is the grid itself, which must outlive it.
 * bounds: the world box of the active voxels' cells; feature_size: the
 * smallest voxel edge. Beyond the leaves it answers with the far bound. */
sdft_field sdft_grid_field(const sdft_grid *g);

/* What a grid's field answers where the tree holds no voxels (level sets):
 *   FAR   the default: the distance to the nearest leaf, from a coarse
 *         distance transform built at load (src/grid/grid_bound.c), plus
 *         what the band guarantees; continuous, no tree walk;
 *   TREE  the distance to the boundary of the tile holding the point plus
 *         the band (src/grid/grid_sample.c): a step ends at every tile edge;
 *   NONE  trilinear everywhere, so +-background beyond the band.
 * TREE and NONE are kept to measure what the bounds save. */
typedef enum sdft_grid_bound { SDFT_GRID_BOUND_FAR, SDFT_GRID_BOUND_TREE, SDFT_GRID_BOUND_NONE } sdft_grid_bound;
sdft_field sdft_grid_field_with(const sdft_grid *g, sdft_grid_bound bound);

/* sdft_grid_field_with(g, SDFT_GRID_BOUND_NONE). */
sdft_field sdft_grid_field_without_bound(const sdft_grid *g);

/* Queries. Strings are owned by the grid. */
const char *sdft_grid_name(const sdft_grid *g);
const char *sdft_grid_type_name(const sdft_grid *g);  /* "float", "fp16", "fp8", "fp4", "fpN" */
const char *sdft_grid_class_name(const sdft_grid *g); /* "level set", "fog volume", "unknown", ... */
int sdft_grid_is_level_set(const sdft_grid *g);
sdft_vec3 sdft_grid_voxel_size(const sdft_grid *g);   /* world units per voxel along x, y, z */
float sdft_grid_background(const sdft_grid *g);       /* world units; a level set's band half-width */
uint64_t sdft_grid_active_voxels(const sdft_grid *g);
/* Active voxels' index box (inclusive) and the world box of their cells. */
void sdft_grid_index_bounds(const sdft_grid *g, int32_t lo[3], int32_t hi[3]);
sdft_aabb sdft_grid_world_bounds(const sdft_grid *g);
/* The grid's bytes (one NanoVDB grid, 32-byte aligned), e.g. for a GPU. */
const void *sdft_grid_data(const sdft_grid *g, size_t *size);

/* The stored value of voxel (i, j, k) (background outside the tree) and its
 * active state; for tests and tools. */
float sdft_grid_voxel(const sdft_grid *g, int32_t i, int32_t j, int32_t k, int *active);

/* What the field with `bound` does at world point p, spelled out: the far
 * bound (*level 5), else the trilinear value where the tree holds voxels
 * (*level 0), else the tree bound of the tile or empty root region (*level
 * 1..4: lower tile, upper tile, root tile, background). World units.
 * sdft_grid_sample is the default field's (SDFT_GRID_BOUND_FAR). */
float sdft_grid_sample_with(const sdft_grid *g, sdft_grid_bound bound, sdft_scratch *s, sdft_vec3 p, int *level);
float sdft_grid_sample(const sdft_grid *g, sdft_scratch *s, sdft_vec3 p, int *level);

#ifdef __cplusplus
}
#endif
#endif
