/* sdftrace common — reading a NumPy .npy array strictly, beside npy_write.h:
 * nothing in the file is trusted (it may be truncated, hostile or another
 * array), and every flaw is one line naming the file. mesh2sdf's --query
 * points and the benches read theirs through it. Internal header (C and
 * C++). */
#ifndef SDFTRACE_COMMON_NPY_READ_H
#define SDFTRACE_COMMON_NPY_READ_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Reads an (N, columns) float32 or float64 array, C or Fortran order,
 * little-endian, format version 1.0, 2.0 or 3.0, N >= 1, into *values (N
 * rows of doubles, row by row; malloc'd, the caller frees it) and *rows.
 * Checks the magic, the header's length, its dict (exactly the keys
 * 'descr', 'fortran_order' and 'shape', once each), the data's length
 * against the file's size before allocating, and that every value is
 * finite. 0, or -1 with one line naming `path` in msg ("points PATH: ...")
 * and *values NULL. */
int npy_read_rows(const char *path, size_t columns, double **values, size_t *rows, char *msg, size_t msg_len);

#ifdef __cplusplus
}
#endif
#endif
