/* sdftrace — what the grid loader and the grid sampler share: the grid
 * object itself. Internal header; C only, through PNanoVDB.h. */
#ifndef SDFTRACE_GRID_INTERNAL_H
#define SDFTRACE_GRID_INTERNAL_H

#define PNANOVDB_C
#include <nanovdb/PNanoVDB.h>

#include "sdftrace/grid.h"

/* One NanoVDB grid plus the numbers the sampler reads on every call,
 * decoded once from the grid's header. Immutable after loading. */
struct sdft_grid {
    uint32_t *words;              /* the grid's bytes, 32-byte aligned, owned */
    size_t size;                  /* bytes */
    pnanovdb_buf_t buf;
    pnanovdb_grid_handle_t grid;  /* at address 0 */
    pnanovdb_root_handle_t root;
    pnanovdb_grid_type_t type;    /* FLOAT, DOUBLE, FP4, FP8, FP16, FPN */
    uint32_t grid_class;
    float w2i[9], w2i_t[3];       /* index = w2i * world + w2i_t */
    float i2w[9], i2w_t[3];       /* world = i2w * index + i2w_t */
    float sigma_min, sigma_max;   /* world length of a unit index step: bounds on i2w's singular values */
    float background;             /* world units */
    sdft_vec3 voxel_size;
    int32_t ilo[3], ihi[3];       /* active voxels' index box, inclusive */
    sdft_aabb bounds;             /* world box of those voxels' cells */
    char name[256];
};

/* Decodes and checks a grid already copied into g->words / g->size. */
int grid_init(sdft_grid *g, char *msg, unsigned msg_len);

/* Printf into msg (if any); returns code. */
int grid_fail(char *msg, unsigned msg_len, int code, const char *fmt, ...);

#endif
