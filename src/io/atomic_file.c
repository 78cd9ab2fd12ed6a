/* sdftrace io — write beside, then rename: POSIX rename() within one folder
 * replaces the target atomically, so readers see the old file or the whole
 * new one. */
#define _POSIX_C_SOURCE 200809L
#include "atomic_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "image_io.h"

int atomic_begin(atomic_file *af, const char *path, char *msg, unsigned msg_len)
{
    af->fd = -1;
    af->tmp_path[0] = '\0';
    if (!path || !*path) {
        snprintf(msg, msg_len, "empty output path");
        return -1;
    }
    if (strlen(path) >= sizeof af->final_path) {
        snprintf(msg, msg_len, "output path too long");
        return -1;
    }
    strcpy(af->final_path, path);
    /* "<dir>/.<name>.tmpXXXXXX": same folder, so the rename stays atomic. */
    const char *slash = strrchr(path, '/');
    int dir_len = slash ? (int)(slash - path + 1) : 0;
    snprintf(af->tmp_path, sizeof af->tmp_path, "%.*s.%s.tmpXXXXXX", dir_len, path, path + dir_len);
    af->fd = mkstemp(af->tmp_path);
    if (af->fd < 0) {
        snprintf(msg, msg_len, "cannot write %s: %s", path, strerror(errno));
        af->tmp_path[0] = '\0';
        return -1;
    }
    /* mkstemp makes 0600; give the file the mode a plain fopen would. */
    mode_t mask = umask(022);
    umask(mask);
    fchmod(af->fd, 0666 & ~mask);
    return 0;
}

int atomic_commit(atomic_file *af, char *msg, unsigned msg_len)
{
    int rc = 0;
    if (af->fd >= 0) {
        if (fsync(af->fd) != 0 && errno != EINVAL && errno != EROFS)
            rc = -1;
        if (close(af->fd) != 0)
            rc = -1;
        af->fd = -1;
    }
    if (rc == 0 && rename(af->tmp_path, af->final_path) != 0)
        rc = -1;
    if (rc != 0) {
        snprintf(msg, msg_len, "cannot write %s: %s", af->final_path, strerror(errno));
        unlink(af->tmp_path);
    }
    af->tmp_path[0] = '\0';
    return rc;
}

void atomic_abort(atomic_file *af)
{
    if (af->fd >= 0)
        close(af->fd);
    af->fd = -1;
    if (af->tmp_path[0])
        unlink(af->tmp_path);
    af->tmp_path[0] = '\0';
}

int sdft_check_writable(const char *path, char *msg, unsigned msg_len)
{
    atomic_file af;
    if (atomic_begin(&af, path, msg, msg_len))
        return -1;
    atomic_abort(&af);
    return 0;
}
