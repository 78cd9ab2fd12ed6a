/* sdftrace — the C++ seam to OpenVDB, seen from C: `.vdb` files in (through
 * NanoVDB's own converter) and fields baked out to level sets. Everything
 * here catches OpenVDB's exceptions and reports a code (sdft_grid_error) plus
 * one line in msg; nothing prints except the bake's progress, and that only
 * when asked to and stderr is a terminal. */
#ifndef SDFTRACE_VDB_H
#define SDFTRACE_VDB_H

#include <stdint.h>

#include "sdftrace/field.h"
#include "sdftrace/grid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How the NanoVDB copy of a float grid stores its leaf values. */
typedef enum sdft_quant {
    SDFT_QUANT_NONE = 0, /* float */
    SDFT_QUANT_FP16,
    SDFT_QUANT_FP8,
    SDFT_QUANT_FP4,
    SDFT_QUANT_FPN       /* variable bit rate, NanoVDB's AbsDiff oracle */
} sdft_quant;

/* How a `.vdb` file is loaded. */
typedef struct sdft_vdb_options {
    sdft_quant quant; /* how the NanoVDB copy stores leaf values [SDFT_QUANT_NONE: float] */
    int progress;     /* 1: a progress line on stderr while loading, when stderr is a terminal [0] */
    int stream;       /* 1: float and Fp16 copies streamed leaf by leaf (vdb_stream.cpp) [1]; 0: through
                       * nanovdb::openToNanoVDB with the whole OpenVDB grid in memory (the reference the
                       * tests hold the stream to) */
} sdft_vdb_options;

sdft_vdb_options sdft_vdb_options_defaults(void);

/* Loads a scalar grid of a `.vdb` file: by name, else the first scalar level
 * set, else the first scalar grid; doubles become floats. Float and Fp16
 * copies are streamed leaf by leaf from OpenVDB's delayed loading into the
 * NanoVDB buffer (vdb_stream.cpp), so the OpenVDB tree and the NanoVDB
 * grid are never in memory together; Fp8, Fp4 and FpN go through
 * nanovdb::openToNanoVDB. *out: free with sdft_grid_free. */
int sdft_vdb_open(const char *path, const char *name, const sdft_vdb_options *o, sdft_grid **out, char *msg,
                  unsigned msg_len);

/* The world box of the active voxels' cells of a `.vdb` file's grid (chosen
 * as sdft_vdb_open chooses), from its metadata and transform alone, without
 * reading the tree: what sdft_grid_world_bounds gives once loaded (OpenVDB
 * writes the active index box as the grid's file_bbox_min / file_bbox_max). */
int sdft_vdb_bounds(const char *path, const char *name, sdft_aabb *bounds, char *msg, unsigned msg_len);

/* sdft_vdb_open with `quant` and no progress. */
int sdft_vdb_load(const char *path, const char *name, sdft_quant quant, sdft_grid **out, char *msg, unsigned msg_len);

/* `.vdb` through sdft_vdb_load, `.nvdb` through sdft_grid_load_nvdb, chosen
 * by the file's extension. */
int sdft_grid_open(const char *path, const char *name, sdft_grid **out, char *msg, unsigned msg_len);

typedef struct sdft_bake_params {
    int res;               /* voxels along the box's longest edge, 1..SDFT_BAKE_MAX_RES */
    float band;            /* narrow-band half-width in voxels (> 0); also the background */
    int full;              /* 1: store every voxel of the box (dense), no band */
    int fp16;              /* 1: Fp16 leaves in .nvdb, half floats in .vdb */
    const char *grid_name; /* NULL: "sdf" */
    int progress;          /* 1: progress on stderr when it is a terminal */
    int threads;           /* 0: TBB's default */
} sdft_bake_params;

#define SDFT_BAKE_MAX_RES 1024

typedef struct sdft_bake_stats {
    double ms;                 /* wall time of sampling + building the tree */
    uint64_t evaluations;      /* field evaluations, node centres included */
    uint64_t leaves;           /* leaf nodes kept */
    uint64_t active_voxels;
    int dims[3];               /* grid size in voxels */
    float voxel_size;          /* world units */
} sdft_bake_stats;

/* res 256, band 3, narrow band, float, grid "sdf", no progress. */
sdft_bake_params sdft_bake_defaults(void);

/* Samples f at the voxel centres of a grid of cubic voxels over f->bounds
 * (res voxels on the longest edge) into an OpenVDB level set (class
 * GRID_LEVEL_SET, background = band * voxel size, inside tiles negative).
 * Narrow band: descends the tree and skips every node whose centre distance
 * exceeds its half-diagonal plus the band. Writes `path` (.vdb or .nvdb, via
 * a temporary file renamed into place) when not NULL, and returns the
 * NanoVDB grid in *grid_out when not NULL. */
int sdft_bake(const sdft_field *f, const sdft_bake_params *p, const char *path, sdft_grid **grid_out,
              sdft_bake_stats *stats, char *msg, unsigned msg_len);

#ifdef __cplusplus
}
#endif
#endif
