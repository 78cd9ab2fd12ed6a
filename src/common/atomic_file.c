/* sdftrace common — write beside, flush, rename: POSIX rename() within one
 * folder replaces the target atomically, so readers see the old file or the
 * whole new one, and after fsync a crash cannot leave a renamed but empty
 * file. */
#define _POSIX_C_SOURCE 200809L
#include "atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fail.h"

unsigned atomic_file_mode(void)
{
    /* Linux shows the umask in /proc/self/status: read it there, since
     * umask() can only be read by setting it, a race with other threads. */
    unsigned mask = 0777u + 1u;
    FILE *f = fopen("/proc/self/status", "r");
    if (f) {
        char line[256];
        while (fgets(line, sizeof line, f))
            if (sscanf(line, "Umask: %o", &mask) == 1)
                break;
        fclose(f);
    }
    if (mask > 0777u) {
        const mode_t old = umask(022);
        umask(old);
        mask = (unsigned)old;
    }
    return 0666u & ~mask;
}

sdft_error atomic_file_begin(atomic_file *af, const char *path, char *msg, size_t msg_len)
{
    af->fd = -1;
    af->direct = 0;
    af->path[0] = af->tmp_path[0] = '\0';
    if (!path || !*path)
        return fail_with(msg, msg_len, SDFT_EINVAL, "empty output path");
    if (strlen(path) >= sizeof af->path)
        return fail_with(msg, msg_len, SDFT_EINVAL, "output path too long: %.64s...", path);
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
        return fail_with(msg, msg_len, SDFT_EIO, "cannot write %s: it is a folder", path);
    strcpy(af->path, path);
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        af->fd = open(path, O_WRONLY | O_CLOEXEC);
        if (af->fd < 0)
            return fail_with(msg, msg_len, SDFT_EIO, "cannot write %s: %s", path, strerror(errno));
        strcpy(af->tmp_path, path);
        af->direct = 1;
        return SDFT_OK;
    }
    /* "<folder>/.<name>.tmp-XXXXXX": same folder, so the rename stays atomic. */
    const char *slash = strrchr(path, '/');
    const int dir_len = slash ? (int)(slash - path + 1) : 0;
    snprintf(af->tmp_path, sizeof af->tmp_path, "%.*s.%s.tmp-XXXXXX", dir_len, path, path + dir_len);
    af->fd = mkstemp(af->tmp_path);
    if (af->fd < 0) {
        const int err = errno;
        af->tmp_path[0] = '\0';
        return fail_with(msg, msg_len, SDFT_EIO, "cannot write %s: %s", path, strerror(err));
    }
    /* mkstemp makes 0600; give the file the mode a plain fopen would. */
    if (fchmod(af->fd, (mode_t)atomic_file_mode()) != 0) {
        const int err = errno;
        atomic_file_abort(af);
        return fail_with(msg, msg_len, SDFT_EIO, "cannot write %s: %s", path, strerror(err));
    }
    return SDFT_OK;
}

/* Flushes the folder holding `path`, so that the rename itself survives a
 * crash. Best effort: some file systems refuse fsync on a folder. */
static void sync_folder(const char *path)
{
    char dir[4096];
    const char *slash = strrchr(path, '/');
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path + 1) : 1, slash ? path : ".");
    const int fd = open(dir, O_RDONLY | O_DIRECTORY);
    if (fd >= 0) {
        (void)fsync(fd);
        close(fd);
    }
}

/* The temporary file flushed to disk and closed (a device or pipe: closed):
 * 0, or the errno of the failure. */
static int flush(atomic_file *af)
{
    int err = 0;
    if (af->fd >= 0) {
        if (!af->direct && fsync(af->fd) != 0 && errno != EINVAL && errno != EROFS)
            err = errno;
        if (close(af->fd) != 0 && !err)
            err = errno;
        af->fd = -1;
    }
    return err;
}

/* The flushed temporary file renamed onto the target (a device or pipe:
 * nothing to do): 0, or the errno of the failure. */
static int place(atomic_file *af)
{
    int err = 0;
    if (!af->direct && af->tmp_path[0]) {
        if (rename(af->tmp_path, af->path) != 0)
            err = errno;
        else
            sync_folder(af->path);
    }
    if (!err)
        af->tmp_path[0] = '\0';
    return err;
}

sdft_error atomic_file_commit(atomic_file *af, char *msg, size_t msg_len)
{
    return atomic_files_commit(af, 1, msg, msg_len);
}

sdft_error atomic_files_begin(atomic_file *files, const char *const *paths, size_t count, char *msg, size_t msg_len)
{
    for (size_t i = 0; i < count; i++) {
        const sdft_error rc = atomic_file_begin(&files[i], paths[i], msg, msg_len);
        if (rc != SDFT_OK) {
            atomic_files_abort(files, i);
            return rc;
        }
    }
    return SDFT_OK;
}

sdft_error atomic_files_commit(atomic_file *files, size_t count, char *msg, size_t msg_len)
{
    int err = 0;
    size_t failed = 0;
    for (size_t i = 0; i < count; i++) {
        const int e = flush(&files[i]);
        if (e && !err)
            err = e, failed = i;
    }
    for (size_t i = 0; i < count && !err; i++) {
        err = place(&files[i]);
        failed = i;
    }
    if (!err)
        return SDFT_OK;
    atomic_files_abort(files, count);
    return fail_with(msg, msg_len, SDFT_EIO, "cannot write %s: %s", files[failed].path, strerror(err));
}

void atomic_files_abort(atomic_file *files, size_t count)
{
    for (size_t i = 0; i < count; i++)
        atomic_file_abort(&files[i]);
}

void atomic_file_abort(atomic_file *af)
{
    if (af->fd >= 0)
        close(af->fd);
    af->fd = -1;
    if (af->tmp_path[0] && !af->direct)
        unlink(af->tmp_path);
    af->tmp_path[0] = '\0';
}

sdft_error atomic_file_check_writable(const char *path, char *msg, size_t msg_len)
{
    atomic_file af;
    const sdft_error rc = atomic_file_begin(&af, path, msg, msg_len);
    if (rc == SDFT_OK)
        atomic_file_abort(&af);
    return rc;
}
