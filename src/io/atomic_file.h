/* sdftrace io — a temporary file beside the target, renamed into place on
 * success. Internal to src/io. */
#ifndef SDFTRACE_ATOMIC_FILE_H
#define SDFTRACE_ATOMIC_FILE_H

#include <stdio.h>

typedef struct atomic_file {
    char final_path[4096];
    char tmp_path[4112];
    int fd; /* open descriptor of tmp_path, or -1 */
} atomic_file;

/* Creates an empty, unique temporary file in path's folder. 0 or -1 (msg). */
int atomic_begin(atomic_file *af, const char *path, char *msg, unsigned msg_len);
/* Renames the finished temporary file onto the target. 0 or -1 (msg);
 * on failure the temporary file is removed. */
int atomic_commit(atomic_file *af, char *msg, unsigned msg_len);
/* Removes the temporary file (after a failed write). */
void atomic_abort(atomic_file *af);

#endif
