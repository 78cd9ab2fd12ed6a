/* sdftrace fuzzing — reading a grid a harness opened across its index box,
 * so that a deferred grid fills the leaves the reads fall in and an
 * accepted grid is read everywhere. */
#ifndef SDFT_FUZZ_READ_GRID_H
#define SDFT_FUZZ_READ_GRID_H

#include <stdint.h>

#include "sdftrace/grid.h"

/* Reads voxels on a 17^3 lattice over the grid's index box. */
static inline void fuzz_read_voxels(const sdft_grid *g)
{
    int32_t lo[3], hi[3];
    sdft_grid_index_bounds(g, lo, hi);
    int64_t step[3];
    for (int k = 0; k < 3; k++)
        step[k] = hi[k] >= lo[k] ? ((int64_t)hi[k] - lo[k]) / 16 + 1 : 1;
    volatile float sink = 0;
    for (int64_t i = lo[0]; i <= hi[0]; i += step[0])
        for (int64_t j = lo[1]; j <= hi[1]; j += step[1])
            for (int64_t k = lo[2]; k <= hi[2]; k += step[2])
                sink += sdft_grid_voxel(g, (int32_t)i, (int32_t)j, (int32_t)k, NULL);
    (void)sink;
}

#endif
