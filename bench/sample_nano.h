/* sample_bench's C++ side, seen from C. */
#ifndef SDFT_BENCH_SAMPLE_NANO_H
#define SDFT_BENCH_SAMPLE_NANO_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A dense float array over a grid's active index box grown by one voxel,
 * z fastest, holding every voxel's value (tiles and background included). */
typedef struct sb_dense {
    float *v;
    int lo[3], n[3];
    float w2i[9], w2i_t[3];
} sb_dense;

int sb_dense_make(const void *grid_bytes, sb_dense *d);

/* Sum of NanoVDB's own trilinear samples (createSampler<1> over a read
 * accessor) at n world points; chained: each point waits for the last value. */
double sb_nano_sum(const void *grid_bytes, const float *xyz, size_t n, int chained);

#ifdef __cplusplus
}
#endif
#endif
