/* sdftrace common — write beside, flush, rename: POSIX rename() within one
 * folder replaces the target atomically, so readers see the old file or the
 * whole new one, and after fsync a crash cannot leave a renamed but empty
 * file. */
#define _POSIX_C_SOURCE 200809L
#define _DEFAULT_SOURCE /* flock */
#include "atomic_file.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
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
    /* The writer's lock, held while this process lives (atomic_file_sweep).
     * A file system without locks writes all the same. */
    (void)flock(af->fd, LOCK_EX | LOCK_NB);
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

/* Whether `entry` is ".<inner>.tmp-XXXXXX" (mkstemp's six letters and
 * digits) with <inner> `name`, or ending in one of `suffixes`. */
static int sweepable(const char *entry, const char *name, const char *const *suffixes)
{
    const size_t n = strlen(entry), tail = strlen(".tmp-XXXXXX");
    if (entry[0] != '.' || n < 1 + tail + 1 || strncmp(entry + n - tail, ".tmp-", 5) != 0)
        return 0;
    for (size_t i = n - 6; i < n; i++)
        if (!((entry[i] >= 'a' && entry[i] <= 'z') || (entry[i] >= 'A' && entry[i] <= 'Z') ||
              (entry[i] >= '0' && entry[i] <= '9')))
            return 0;
    const char *inner = entry + 1;
    const size_t inner_len = n - 1 - tail;
    if (name)
        return strlen(name) == inner_len && strncmp(inner, name, inner_len) == 0;
    for (; suffixes && *suffixes; suffixes++) {
        const size_t k = strlen(*suffixes);
        if (k < inner_len && strncmp(inner + inner_len - k, *suffixes, k) == 0)
            return 1;
    }
    return 0;
}

int atomic_file_sweep(const char *dir, const char *name, const char *const *suffixes)
{
    const char *folder = dir && *dir ? dir : ".";
    DIR *d = opendir(folder);
    if (!d)
        return 0;
    int removed = 0;
    const time_t now = time(NULL);
    char path[4096];
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        if (!sweepable(e->d_name, name, suffixes))
            continue;
        if ((size_t)snprintf(path, sizeof path, "%s/%s", folder, e->d_name) >= sizeof path)
            continue;
        /* Opened without following a link, and only a regular file: the
         * lock test needs a descriptor of the file itself. */
        const int fd = open(path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
        if (fd < 0)
            continue;
        struct stat st;
        if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && now - st.st_mtime >= 1 && flock(fd, LOCK_EX | LOCK_NB) == 0) {
            /* Still the same file under that name (not replaced meanwhile). */
            struct stat now_st;
            if (lstat(path, &now_st) == 0 && now_st.st_ino == st.st_ino && now_st.st_dev == st.st_dev &&
                unlink(path) == 0)
                removed++;
        }
        close(fd);
    }
    closedir(d);
    return removed;
}
