/* sdftrace common — the header of a NumPy .npy file (format 1.0) of
 * little-endian float32: the one writer of it, for the converter's dense
 * grids (libsdftrace_mesh) and mesh2sdf's point files. Internal header (C
 * and C++). */
#ifndef SDFTRACE_COMMON_NPY_WRITE_H
#define SDFTRACE_COMMON_NPY_WRITE_H

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Writes the magic, the version, the header's length and the header: a
 * Python dict literal with `shape` (a tuple literal, "(n, 4)" or "(n,)"),
 * padded with spaces to a multiple of 64 bytes and ended by a newline. The
 * array's bytes follow it, C order. 0, or -1 when a write failed. */
int npy_write_header(FILE *f, const char *shape);

#ifdef __cplusplus
}
#endif
#endif
