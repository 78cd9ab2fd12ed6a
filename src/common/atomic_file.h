/* sdftrace common — writing a file whole or not at all: a temporary file
 * beside the target, written, flushed to disk (fsync) and renamed onto the
 * target, with the mode a plain fopen would give it (0666 less the umask);
 * and several files together, all or none (atomic_files_*). The one
 * implementation for every output of sdftrace render and bake,
 * libsdftrace_vdb, libsdftrace_mesh and mesh2sdf. Internal header (C and
 * C++). */
#ifndef SDFTRACE_COMMON_ATOMIC_FILE_H
#define SDFTRACE_COMMON_ATOMIC_FILE_H

#include <stddef.h>

#include "sdftrace/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct atomic_file {
    char path[4096];     /* the target */
    char tmp_path[4112]; /* "<folder>/.<name>.tmp-XXXXXX", beside it; "" when none */
    int fd;              /* open descriptor of tmp_path, or -1 */
    int direct;          /* 1: the target is a device or a pipe (/dev/null, a FIFO), written in place */
} atomic_file;

/* Creates the empty temporary file beside `path` (mode from the umask), so
 * that a missing folder, a folder in the target's place or a read-only
 * folder fails here, before any work. The writer holds a lock on it
 * (flock) until it is renamed or removed, or the process ends: that is how
 * atomic_file_sweep tells a live writer's file from a killed one's. A target that exists and is neither
 * a regular file nor a folder (/dev/null, a named pipe) is opened and
 * written in place: renaming onto it would replace the device with a file. Write to af->tmp_path (by name, or
 * through af->fd). SDFT_OK; SDFT_EINVAL (empty or too long a path); SDFT_EIO
 * with the reason. On failure nothing is left behind. */
sdft_error atomic_file_begin(atomic_file *af, const char *path, char *msg, size_t msg_len);

/* Flushes the temporary file to disk, closes it and renames it onto the
 * target (then flushes the folder). SDFT_OK, or SDFT_EIO with the reason,
 * and then the temporary file is removed. */
sdft_error atomic_file_commit(atomic_file *af, char *msg, size_t msg_len);

/* Removes the temporary file (after a failed write); safe to call twice. */
void atomic_file_abort(atomic_file *af);

/* Several files written together, all or none: atomic_files_begin
 * reserves each target as atomic_file_begin does (on a failure, none is
 * left), the caller writes each tmp_path (or fd), and atomic_files_commit
 * flushes every one to disk before it renames any, so that a write that
 * fails (a full disk) replaces no target; what is not renamed is removed.
 * The files are the caller's array of `count`. */
sdft_error atomic_files_begin(atomic_file *files, const char *const *paths, size_t count, char *msg, size_t msg_len);

/* Flushes every file, then renames each onto its target. SDFT_OK, or
 * SDFT_EIO with the reason: then no file was renamed if a flush failed,
 * and every temporary file is removed. */
sdft_error atomic_files_commit(atomic_file *files, size_t count, char *msg, size_t msg_len);

/* Removes every temporary file (after a failed write); safe to call twice. */
void atomic_files_abort(atomic_file *files, size_t count);

/* Whether a file could be created at path: creates and removes a temporary
 * file beside it, touching nothing at path itself. SDFT_OK or as begin. */
sdft_error atomic_file_check_writable(const char *path, char *msg, size_t msg_len);

/* Removes the temporary files a killed writer left in folder `dir` (NULL
 * or "": the current one): files named ".<name>.tmp-XXXXXX", as
 * atomic_file_begin names them, where <name> is `name` or (name NULL) ends
 * in one of the `suffixes` (NULL-terminated; NULL: none), that no process
 * holds the writer's lock on and that are a second old or more (older than
 * the moment between a temporary file's creation and its lock). Files of
 * writers still running (another run into the same folder, a batch's other
 * shards) are kept; so are those of a file system that takes no locks.
 * Returns how many it removed. */
int atomic_file_sweep(const char *dir, const char *name, const char *const *suffixes);

/* The mode a new file gets from the process's umask: 0666 & ~umask. */
unsigned atomic_file_mode(void);

#ifdef __cplusplus
}
#endif
#endif
