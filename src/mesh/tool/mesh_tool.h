/* sdftrace — what mesh2sdf needs of the mesh component beyond
 * sdftrace/mesh.h: its output files reserved before the work and written
 * together at its end, a conversion's box planned before the health line
 * is printed, the rows of each kind a draw of samples makes (for the
 * sidecar), and grids' signs checked against the exact winding number
 * (--check-sign reads .vdb files, in a child process). Internal: a static
 * library beside libsdftrace_mesh (sdftrace_mesh_tool), never installed or
 * exported; C, with the errors of sdftrace/error.h. */
#ifndef SDFT_MESH_TOOL_H
#define SDFT_MESH_TOOL_H

#include <stddef.h>
#include <stdint.h>

#include "sdftrace/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Files written together, whole or not at all, and reserved before the
 * work that fills them: mesh_files_reserve creates a temporary file beside
 * each destination now (so that a missing or read-only folder fails before
 * minutes of converting), mesh_files_write_grid writes each and renames
 * all of them into place (src/common/atomic_file.h); freeing the set
 * before that removes the temporary files. Destinations that are devices
 * or pipes (/dev/null) are written in place. New files get the mode the
 * umask gives. */
typedef struct mesh_files mesh_files;

typedef struct mesh_file {
    const char *path;
    sdft_mesh_format format; /* an .npy file brings its sidecar JSON (mesh_sidecar_path) */
} mesh_file;

/* Reserves `count` destinations into *out (mesh_files_free); the paths are
 * copied. SDFT_EINVAL (a NULL argument or path, count 0, an unknown
 * format), SDFT_EIO (a folder missing or read-only, a destination that is
 * a folder), SDFT_ENOMEM. On failure *out is NULL and nothing is left
 * behind. */
sdft_error mesh_files_reserve(const mesh_file *files, size_t count, mesh_files **out, char *msg, size_t msg_len);

/* Writes g into every reserved file in its format (fp16 1: NanoVDB Fp16
 * leaves), then renames all of them into place. Once: a set is spent after
 * the call, whatever it returns. SDFT_EINVAL (a NULL argument, a spent
 * set, a dense array over SDFT_MESH_MAX_DENSE_VOXELS), SDFT_EIO (a write
 * or a rename failed: the reason in msg), SDFT_ENOMEM, SDFT_EINTERNAL; on
 * failure no destination was replaced by a partial file and no temporary
 * file is left. */
sdft_error mesh_files_write_grid(mesh_files *f, const sdft_mesh_grid *g, int fp16, char *msg, size_t msg_len);

/* Removes what was reserved and not written; NULL is fine. */
void mesh_files_free(mesh_files *f);

/* The sidecar JSON's path of an `.npy` file: a trailing `.npy` replaced by
 * `.json`, else `.json` appended. Written into out as snprintf does (out
 * may be NULL with out_len 0); returns the path's length. */
size_t mesh_sidecar_path(const char *npy_path, char *out, size_t out_len);

/* The box sdft_mesh_to_grid would convert m into with p, through the same
 * checks, without building anything. SDFT_EINVAL (as sdft_mesh_to_grid),
 * SDFT_ENOMEM (the conversion would not fit this machine's memory: the
 * estimate in msg). */
sdft_error mesh_grid_plan(const sdft_mesh *m, const sdft_mesh_grid_params *p, sdft_mesh_grid_box *box, char *msg,
                          size_t msg_len);

/* How many of p->count rows sdft_mesh_samples draws of each kind:
 * *uniform = round(share * count) (a share outside [0, 1] taken as the
 * nearer end, NaN as 0), the rest near, the first sigma's ceil(near / 2)
 * and the second's floor(near / 2). Any output may be NULL. */
void mesh_sample_counts(const sdft_mesh_sample_params *p, size_t *near_first, size_t *near_second, size_t *uniform);

/* How often a grid's sign disagrees with the mesh's exact winding number. */
typedef struct mesh_sign_counts {
    uint64_t clear;     /* points whose exact winding number is clearly in (> 0.75) or out (< 0.25), a voxel
                         * or more from the surface */
    uint64_t wrong;     /* of them, where the grid's nearest voxel has the other sign */
    uint64_t wrong_far; /* of them, 3 or more voxels from the surface */
} mesh_sign_counts;

/* Draws `points` points uniformly (a fixed seed) in the mesh's box grown
 * by 5% a side and computes each one's winding number exactly (over every
 * triangle, of the mesh as it is: load it without orienting to check
 * against the file's own faces); then, for each of the `count` `.vdb` files
 * in grid_paths, compares those signs with its first float grid's nearest
 * voxel (active or not, < 0 inside) into out[i]. Every grid is read (each
 * first in a child process: a corrupt file fails, never crashes) before
 * any point is drawn. SDFT_EINVAL (a NULL argument, count 0, points outside
 * 1..SDFT_MESH_MAX_SAMPLES), SDFT_EIO (a file missing or not readable),
 * SDFT_EFORMAT (a corrupt file, no float grid), SDFT_ENOMEM (the points do
 * not fit this machine). */
sdft_error mesh_sign_check(const sdft_mesh *m, const char *const *grid_paths, size_t count, size_t points,
                           mesh_sign_counts *out, char *msg, size_t msg_len);

#ifdef __cplusplus
}
#endif

#endif
