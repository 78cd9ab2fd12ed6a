/* sdftrace — whether a `.vdb` file holds the bytes its header says it
 * does, checked before OpenVDB reads it. Internal; C and C++. */
#ifndef SDFTRACE_VDB_EXTENT_H
#define SDFTRACE_VDB_EXTENT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* 0: `path`'s header, file metadata and grid descriptors lie within the
 * file and every grid ends by the file's end (or the file predates the
 * layout checked here, or has no grid offsets, or is not a regular file
 * that can be opened: nothing to check, and the reader reports what it
 * meets). -1: it is not a .vdb file, or is truncated or corrupt where it
 * is walked; `why` says so in a few words ("grid 'sdf' runs to byte
 * 42038 of 600: a truncated file?"). */
int vdb_check_extent(const char *path, char *why, size_t why_len);

#ifdef __cplusplus
}
#endif

#endif
