/* sdftrace common — a path's file name without its folder and its last
 * extension: the default name of a converted grid (libsdftrace_mesh) and of
 * a batch's outputs (mesh2sdf). Internal header (C and C++). */
#ifndef SDFTRACE_COMMON_PATH_STEM_H
#define SDFTRACE_COMMON_PATH_STEM_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* "dir/spot.obj" -> "spot", "a.b.ply" -> "a.b"; a name that only begins
 * with a dot (".obj") or has none ("mesh") is kept whole. Sets *start to
 * where the stem begins in path; returns its length. */
size_t path_stem(const char *path, const char **start);

#ifdef __cplusplus
}
#endif
#endif
