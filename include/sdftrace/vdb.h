/* sdftrace — the OpenVDB component (libsdftrace_vdb; CMake target
 * sdftrace::vdb, pkg-config sdftrace_vdb): `.vdb` files in, fields baked
 * out to OpenVDB or NanoVDB level sets. A C API over a C++17 seam: every
 * OpenVDB exception is caught inside and reported as an sdft_error with one
 * line in msg (sdftrace/error.h); nothing here prints. Grids come out as
 * the core library's sdft_grid (sdftrace/grid.h), freed with
 * sdft_grid_free. */
#ifndef SDFTRACE_VDB_H
#define SDFTRACE_VDB_H

#include <stddef.h>
#include <stdint.h>

#include "field.h"
#include "grid.h"
#include "sdftrace/config.h"
#include "sdftrace/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Opens the grid o says, as sdft_grid_open does, and `.vdb` files too: a
 * scalar grid of the file, chosen as sdftrace/grid.h says (doubles become
 * floats), into *out, which owns it (sdft_grid_free). Float and Fp16
 * copies are streamed leaf by leaf from OpenVDB's delayed loading into the
 * NanoVDB buffer (o->stream), so that the OpenVDB tree and the NanoVDB
 * grid are never in memory together; Fp8, Fp4 and FpN go through
 * NanoVDB's own converter. The result is the grid NanoVDB's converter
 * makes, voxel for voxel. A path is taken by its extension: `.vdb` here,
 * `.nvdb` through sdft_grid_open, any other SDFT_EFORMAT; with no path,
 * the buffer, through sdft_grid_open. On failure *out is NULL. Errors as
 * sdft_grid_open's, and for a `.vdb` file SDFT_EINVAL (an unknown quant or
 * defer; defer with stream 0 or another quant than float or Fp16),
 * SDFT_ECANCELED (the progress callback said stop), SDFT_EINTERNAL. */
SDFT_API sdft_error sdft_vdb_open(const sdft_grid_options *o, sdft_grid **out, char *msg, size_t msg_len);

/* The world box of the active voxels' cells of a `.vdb` file's grid (chosen
 * as sdft_vdb_open chooses), from its metadata and transform alone, without
 * reading the tree: what sdft_grid_world_bounds gives once loaded. Errors as
 * sdft_vdb_open's. */
SDFT_API sdft_error sdft_vdb_bounds(const char *path, const char *name, sdft_aabb *box, char *msg, size_t msg_len);

/* How to bake. It will grow: make one with sdft_bake_defaults() and set the
 * fields you change, never with an aggregate initializer alone. */
typedef struct sdft_bake_params {
    int res;                   /* voxels along the box's longest edge, 1..SDFT_BAKE_MAX_RES */
    float band;                /* narrow-band half-width in voxels, (0, 1000]; also the background */
    int full;                  /* 1: store every voxel of the box (dense), no band */
    int fp16;                  /* 1: Fp16 leaves in .nvdb (and in the returned grid), half floats in .vdb */
    const char *grid_name;     /* NULL: "sdf"; the caller's string, read during the call */
    sdft_progress_fn progress; /* NULL: no progress reports */
    void *progress_user;       /* handed to progress */
    int threads;               /* worker threads, 0: TBB's default */
    int materials;             /* 1: the field's materials too (f->material, and a path): the grids
                                * NAME.material_ids and NAME.material_table after the surface in the file
                                * (sdftrace/grid.h, sdft_grid_set_materials); grid_out carries none */
} sdft_bake_params;

#define SDFT_BAKE_MAX_RES 1024

typedef struct sdft_bake_stats {
    double ms;            /* wall time of sampling + building the tree */
    uint64_t evaluations; /* field evaluations, node centres included */
    uint64_t leaves;      /* leaf nodes kept */
    uint64_t active_voxels;
    int dims[3];      /* grid size in voxels */
    float voxel_size; /* world units */
} sdft_bake_stats;

/* res 256, band 3, narrow band, float, grid "sdf", no progress, all threads,
 * no materials. */
SDFT_API sdft_bake_params sdft_bake_defaults(void);

/* Samples f at the voxel centres of a grid of cubic voxels over f->bounds
 * (res voxels on the longest edge) into an OpenVDB level set (class
 * GRID_LEVEL_SET, background = band * voxel size, inside tiles negative).
 * Narrow band: descends the tree and skips every node whose centre distance
 * exceeds its half-diagonal plus the band. Writes `path` (.vdb or .nvdb) when
 * not NULL, whole or not at all (a temporary file beside it, renamed; the
 * mode the umask gives), and returns the NanoVDB grid in *grid_out (the
 * caller's, sdft_grid_free) when grid_out is not NULL. stats may be NULL.
 * SDFT_EINVAL (NULL f or p, a field without distance or with an empty or
 * infinite box, res or band out of range, another extension; materials
 * without f->material or without a path, or with more than
 * SDFT_GRID_MAX_MATERIALS distinct ones), SDFT_EEMPTY
 * (no voxel within the band), SDFT_EIO, SDFT_ECANCELED, SDFT_ENOMEM,
 * SDFT_EINTERNAL. f is evaluated from several threads, each with its own
 * scratch. */
SDFT_API sdft_error sdft_bake(const sdft_field *f, const sdft_bake_params *p, const char *path, sdft_grid **grid_out,
                              sdft_bake_stats *stats, char *msg, size_t msg_len);

#ifdef __cplusplus
}
#endif
#endif
