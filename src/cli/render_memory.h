/* sdftrace render — the image's peak memory, checked against what the
 * machine allows before anything is allocated. */
#ifndef SDFT_CLI_RENDER_MEMORY_H
#define SDFT_CLI_RENDER_MEMORY_H

#include <stddef.h>

/* Bytes a width x height render needs at its peak (resident set). */
double render_peak_bytes(int width, int height);

/* 0 when that fits src/common/memory_limit.h's limit; -1 with one line in
 * msg ("needs ~5.1 GiB for a 16384x16384 image; ...") otherwise. */
int render_memory_check(int width, int height, char *msg, size_t len);

#endif
