/* sdftrace — a grid on the device: the NanoVDB buffer as it is, the leaf
 * directory's two tables, the far bound's corner words and the hull's
 * boxes and slabs, each a buffer the shader reads by its device address,
 * and the grid_shape (gpu_frame.h) that names them with the scalars the
 * portable sampler reads. The tables are the ones the library built at
 * load, so the shader samples the field sdft_grid_field(g, FAR) is. */
#include <stdlib.h>
#include <string.h>

#include "fail.h"
#include "gpu_grid.h"

/* 32-bit byte offsets (PNanoVDB's GLSL addressing) reach this far. */
#define GPU_MOST_GRID ((uint64_t)4 << 30)

/* The tables' bytes, all uploaded: the grid's, the directory's, the far
 * bound's, the hull's. */
typedef struct grid_tables {
    const void *data[6];
    size_t bytes[6];
} grid_tables;

enum { TABLE_WORDS, TABLE_TOP, TABLE_CHUNK, TABLE_FAR, TABLE_HULL, TABLE_SLABS, TABLES };

static grid_tables tables_of(const sdft_grid *g)
{
    grid_tables t = {0};
    size_t size;
    t.data[TABLE_WORDS] = sdft_grid_data(g, &size); /* a deferred grid's leaves are read here */
    t.bytes[TABLE_WORDS] = size;
    const grid_leaves *d = &g->leaves;
    if (d->top) {
        t.data[TABLE_TOP] = d->top;
        t.bytes[TABLE_TOP] = (size_t)d->nr[0] * (size_t)d->nr[1] * (size_t)d->nr[2] * sizeof *d->top;
        t.data[TABLE_CHUNK] = d->chunk;
        t.bytes[TABLE_CHUNK] = d->chunks * GRID_CHUNK_ENTRIES * sizeof *d->chunk;
    }
    const grid_far *f = &g->far;
    if (f->corner) {
        t.data[TABLE_FAR] = f->corner;
        t.bytes[TABLE_FAR] = ((size_t)f->n[0] + 1) * ((size_t)f->n[1] + 1) * ((size_t)f->n[2] + 1) * sizeof *f->corner;
    }
    if (g->hull_count) {
        t.data[TABLE_HULL] = g->hull;
        t.bytes[TABLE_HULL] = g->hull_count * sizeof *g->hull;
        if (g->hull_slab) {
            t.data[TABLE_SLABS] = g->hull_slab;
            t.bytes[TABLE_SLABS] = g->hull_count * sizeof *g->hull_slab;
        }
    }
    return t;
}

/* Whether the grid fits the device: its addressing, the device's memory. */
static sdft_error check_fits(const sdft_gpu *gpu, const sdft_grid *g, const grid_tables *t, char *msg, size_t msg_len)
{
    if (g->type != PNANOVDB_GRID_TYPE_FLOAT)
        return fail_with(msg, msg_len, SDFT_ENOTSCALAR,
                         "grid '%s' is %s: the GPU renders float grids (load a .vdb without --fp16)", g->name,
                         sdft_grid_type_name(g));
    if (t->bytes[TABLE_WORDS] > GPU_MOST_GRID)
        return fail_with(msg, msg_len, SDFT_ENOMEM,
                         "grid '%s' is %.2f GiB: too big for the GPU, whose shader addresses grids up to 4 GiB",
                         g->name, (double)t->bytes[TABLE_WORDS] / 1073741824.0);
    uint64_t total = 0;
    for (int k = 0; k < TABLES; k++)
        total += t->bytes[k];
    if (total > gpu->device_memory)
        return fail_with(msg, msg_len, SDFT_ENOMEM,
                         "grid '%s' and its tables (%.1f MiB) are too big for %s (%.1f MiB of device memory to use)",
                         g->name, (double)total / 1048576.0, gpu->name, (double)gpu->device_memory / 1048576.0);
    return SDFT_OK;
}

/* The shape the portable sampler reads (grid_layout.h), from g. */
static grid_shape shape_of(const sdft_grid *g, const gpu_buffer *b)
{
    grid_shape s;
    memset(&s, 0, sizeof s);
    s.buf = b[TABLE_WORDS].address;
    s.top = b[TABLE_TOP].address;
    s.chunk = b[TABLE_CHUNK].address;
    s.far_corner = b[TABLE_FAR].address;
    s.root = (uint32_t)g->root.address.byte_offset;
    memcpy(s.w2i, g->w2i, sizeof s.w2i);
    memcpy(s.w2i_t, g->w2i_t, sizeof s.w2i_t);
    s.diagonal = g->diagonal;
    s.sigma_min = g->sigma_min, s.sigma_max = g->sigma_max, s.background = g->background;
    s.has_directory = g->leaves.top != NULL;
    s.has_far = g->far.corner != NULL;
    for (int k = 0; k < 3; k++) {
        s.leaves.r0[k] = g->leaves.r0[k], s.leaves.nr[k] = g->leaves.nr[k];
        s.far.n[k] = g->far.n[k], s.far.origin[k] = g->far.origin[k];
    }
    s.far.cell = g->far.cell, s.far.inv_cell = g->far.inv_cell, s.far.bonus = g->far.bonus;
    return s;
}

sdft_error sdft_gpu_grid_create(sdft_gpu *gpu, const sdft_grid *g, sdft_gpu_grid **out, char *msg, size_t msg_len)
{
    if (!out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_gpu_grid_create: no place for the grid (out is NULL)");
    *out = NULL;
    if (!gpu || !g)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_gpu_grid_create: no %s (NULL)", gpu ? "grid" : "device");
    if (g->type != PNANOVDB_GRID_TYPE_FLOAT) /* before reading a deferred grid's leaves */
        return check_fits(gpu, g, &(grid_tables){0}, msg, msg_len);
    const grid_tables t = tables_of(g);
    sdft_error rc = check_fits(gpu, g, &t, msg, msg_len);
    if (rc)
        return rc;
    sdft_gpu_grid *gg = calloc(1, sizeof *gg);
    if (!gg)
        return fail_with(msg, msg_len, SDFT_ENOMEM, "out of memory for a grid on the device");
    gg->gpu = gpu, gg->grid = g;
    gg->field = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    for (int k = 0; k < TABLES && !rc; k++)
        rc = gpu_buffer_upload(gpu, t.data[k], t.bytes[k], &gg->tables[k], msg, msg_len);
    if (rc) {
        sdft_gpu_grid_release(gg);
        return rc;
    }
    gg->shape = shape_of(g, gg->tables);
    gg->hull = gg->tables[TABLE_HULL].address;
    gg->slabs = t.bytes[TABLE_SLABS] ? gg->tables[TABLE_SLABS].address : 0;
    *out = gg;
    return SDFT_OK;
}

void sdft_gpu_grid_release(sdft_gpu_grid *gg)
{
    if (!gg)
        return;
    for (int k = 0; k < GPU_GRID_TABLES; k++)
        if (gg->tables[k].buffer)
            gpu_buffer_free(gg->gpu, &gg->tables[k]);
    free(gg);
}
