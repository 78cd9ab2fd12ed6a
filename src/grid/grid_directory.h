/* sdftrace — reading the leaf directory (grid_leaves.c builds it, its
 * layout is grid_internal.h's grid_leaves): which grids have one, and the
 * chunk that holds a voxel's block. Shared by the directory's builder and
 * its readers (grid_cell.h, the far bound, the hull), below both, so that
 * neither includes the other. Internal header. */
#ifndef SDFTRACE_GRID_DIRECTORY_H
#define SDFTRACE_GRID_DIRECTORY_H

#include "grid_internal.h"

/* Whether grids of `type` have a leaf directory (grid_leaves.c). */
static inline int has_directory(pnanovdb_grid_type_t type)
{
    return type == PNANOVDB_GRID_TYPE_FLOAT || type == PNANOVDB_GRID_TYPE_FP16 || type == PNANOVDB_GRID_TYPE_FP8 ||
           type == PNANOVDB_GRID_TYPE_FP4;
}

/* The directory's chunk holding voxel c's block, with *local that block's
 * entry in it; NULL when c lies outside the regions or in one without a
 * chunk (grid_leaves.c builds them). */
GRID_INLINE const uint32_t *directory_chunk(const grid_leaves *d, const int32_t c[3], uint32_t *local)
{
    uint32_t r[3];
    for (int k = 0; k < 3; k++) {
        r[k] = (uint32_t)((c[k] >> 6) - d->r0[k]);
        if (r[k] >= (uint32_t)d->nr[k]) /* below r0 wraps above nr */
            return NULL;
    }
    const uint32_t chunk = d->top[((size_t)r[2] * (size_t)d->nr[1] + r[1]) * (size_t)d->nr[0] + r[0]];
    if (!chunk)
        return NULL;
    *local = ((uint32_t)c[0] >> 3 & 7u) + GRID_CHUNK_SIDE * ((uint32_t)c[1] >> 3 & 7u) +
             GRID_CHUNK_SIDE * GRID_CHUNK_SIDE * ((uint32_t)c[2] >> 3 & 7u);
    return d->chunk + (size_t)(chunk - 1u) * GRID_CHUNK_ENTRIES;
}

#endif
