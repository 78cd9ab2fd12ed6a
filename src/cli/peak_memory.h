/* sdftrace — the peak memory of a render and of a dense bake, checked
 * against what the machine allows before anything is allocated. */
#ifndef SDFT_CLI_PEAK_MEMORY_H
#define SDFT_CLI_PEAK_MEMORY_H

#include <stddef.h>

#include "sdftrace/field.h"

/* Bytes a width x height render needs at its peak (resident set). */
double render_peak_bytes(int width, int height);

/* 0 when that fits src/common/memory_limit.h's limit; -1 with one line in
 * msg ("needs ~5.1 GiB for a 16384x16384 image; ...") otherwise. */
int render_memory_check(int width, int height, char *msg, size_t len);

/* 0 when a --full bake of field f at res voxels along its longest edge
 * (into a .nvdb file: nvdb) fits; -1 with one line in msg otherwise. A
 * narrow band's memory follows the surface, which only the bake finds;
 * res <= 1024 bounds it. */
int bake_memory_check(const sdft_field *f, int res, int nvdb, char *msg, size_t len);

#endif
