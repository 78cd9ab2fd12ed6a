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

/* How the NanoVDB copy of a float grid stores its leaf values. */
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

/* How a `.vdb` file is loaded. It will grow: make one with
 * sdft_vdb_options_defaults() and set the fields you change. */
typedef struct sdft_vdb_options {
    sdft_quant quant;          /* how the NanoVDB copy stores leaf values [SDFT_QUANT_NONE: float] */
    sdft_progress_fn progress; /* NULL: no progress reports [NULL] */
    void *progress_user;       /* handed to progress */
    int stream;                /* 1: float and Fp16 copies streamed leaf by leaf [1]; 0: NanoVDB's own
                                * converter with the whole OpenVDB grid in memory (the reference the
                                * tests hold the stream to) */
    int defer;                 /* 1: lay the grid out and read each leaf's values from the file only when
                                * something first reads that leaf (OpenVDB's delayed loading, as
                                * vdb_render does): a renderer's first image sooner, and memory for the
                                * leaves it reaches, where that changes nothing else (a level set up to
                                * about 1024^3 still loads whole: SDFT_DEFER_WHERE_EXACT in grid.h);
                                * 2: always (SDFT_DEFER_ALWAYS). The file must stay unchanged while the
                                * grid lives. Float and Fp16 (SDFT_EINVAL for other quant or stream 0) [0] */
} sdft_vdb_options;

/* Float leaves, no progress, streamed. */
SDFT_API sdft_vdb_options sdft_vdb_options_defaults(void);

/* Loads a scalar grid of a `.vdb` file, chosen as sdftrace/grid.h says
 * (doubles become floats), into *out, which owns it (sdft_grid_free).
 * Float and Fp16 copies are streamed leaf by leaf from OpenVDB's delayed
 * loading into the NanoVDB buffer, so that the OpenVDB tree and the NanoVDB
 * grid are never in memory together; Fp8, Fp4 and FpN go through NanoVDB's
 * own converter. The result is the grid NanoVDB's converter makes, voxel
 * for voxel. On failure *out is NULL. SDFT_EINVAL (NULL path, out or o,
 * unknown quant), SDFT_EIO, SDFT_EFORMAT, SDFT_ENOTFOUND, SDFT_ENOTSCALAR,
 * SDFT_EEMPTY, SDFT_ECANCELED (the progress callback said stop),
 * SDFT_ENOMEM, SDFT_EINTERNAL. */
SDFT_API sdft_error sdft_vdb_open(const char *path, const char *name, const sdft_vdb_options *o, sdft_grid **out,
                                  char *msg, size_t msg_len);

/* sdft_vdb_open with `quant` and the other defaults. */
SDFT_API sdft_error sdft_vdb_load(const char *path, const char *name, sdft_quant quant, sdft_grid **out, char *msg,
                                  size_t msg_len);

/* The world box of the active voxels' cells of a `.vdb` file's grid (chosen
 * as sdft_vdb_open chooses), from its metadata and transform alone, without
 * reading the tree: what sdft_grid_world_bounds gives once loaded. Errors as
 * sdft_vdb_open's. */
SDFT_API sdft_error sdft_vdb_bounds(const char *path, const char *name, sdft_aabb *box, char *msg, size_t msg_len);

/* A grid file by its extension: `.vdb` through sdft_vdb_load (float
 * leaves), `.nvdb` through sdft_grid_load_nvdb (plain C, no OpenVDB); any
 * other extension is SDFT_EFORMAT. Otherwise as those two. */
SDFT_API sdft_error sdft_grid_open(const char *path, const char *name, sdft_grid **out, char *msg, size_t msg_len);

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

/* res 256, band 3, narrow band, float, grid "sdf", no progress, all threads. */
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
 * infinite box, res or band out of range, another extension), SDFT_EEMPTY
 * (no voxel within the band), SDFT_EIO, SDFT_ECANCELED, SDFT_ENOMEM,
 * SDFT_EINTERNAL. f is evaluated from several threads, each with its own
 * scratch. */
SDFT_API sdft_error sdft_bake(const sdft_field *f, const sdft_bake_params *p, const char *path, sdft_grid **grid_out,
                              sdft_bake_stats *stats, char *msg, size_t msg_len);

#ifdef __cplusplus
}
#endif
#endif
