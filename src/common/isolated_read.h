/* sdftrace — running a dependency's reader on an untrusted file in a child
 * process: a crash, a loop or an allocation past the limits kills the
 * child, and the caller gets one line saying so instead of dying.
 *
 * The child is forked: it shares the caller's state as it was, runs one
 * function that writes its answer (any bytes) to a pipe, and exits with
 * _exit (no atexit handler, no stdio flush). Its stdout and stderr go to
 * /dev/null (a dependency's assertion would add lines to the caller's
 * one-line error). Its address space is limited (below), except under
 * AddressSanitizer,
 * which reserves its shadow as address space and checks allocation sizes
 * itself. No thread
 * pool survives fork(): the function must not wait on TBB's or OpenMP's
 * workers. Internal; C and C++. */
#ifndef SDFTRACE_COMMON_ISOLATED_READ_H
#define SDFTRACE_COMMON_ISOLATED_READ_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The child's work: writes its answer to fd; returns 0 when it did. */
typedef int (*isolated_fn)(void *ctx, int fd);

/* Seconds of processor time a child may take to read `path`, all its
 * threads together: 10 s, plus 1 s per 8 MiB of file (an honest serial read
 * is several times faster than that); the environment variable
 * SDFT_READ_TIME_LIMIT (seconds) replaces it, so that fuzzing does not wait
 * 10 s on every input that loops. Processor time, not wall: a reader that
 * loops spends it, a reader that waits its turn on a loaded machine does
 * not. A child that spends no processor time at all for as many seconds
 * of wall time (one that waits on nothing that will come) is stopped too,
 * and any child after ISOLATED_WALL_FACTOR times as many. */
double isolated_time_limit(const char *path);
#define ISOLATED_WALL_FACTOR 30

/* Runs fn(ctx, fd), which reads `path`, in a child for at most
 * isolated_time_limit(path) seconds of processor time and with at most 256 MiB plus 64 bytes
 * per byte of the file (or the machine's memory, if less) more address
 * space than it inherits: a reader may unpack, but a length field cannot
 * make it take the machine's memory. 0: the child exited 0; *answer
 * (malloc'ed, the caller frees it) holds what it wrote, *size bytes. -1: it
 * crashed, was killed, exited otherwise or ran out of time, or could not
 * start; `why` says which ("signal 11 (Segmentation fault)", "ran past
 * 12 s of processor time") in a few words. */
int isolated_read(const char *path, isolated_fn fn, void *ctx, char **answer, size_t *size, char *why, size_t why_len);

/* What a caller of isolated_read_with adds to isolated_read's defaults. */
typedef struct isolated_extra {
    /* Address space the child may take beyond what the file allows (its
     * threads' stacks and malloc arenas, a shared mapping it fills), bytes. */
    double bytes;
    /* Called about every 20 ms in the caller's thread while the child runs
     * (a progress report from memory the child shares); non-zero stops the
     * child: it is killed and the call returns -2. NULL: not called. */
    int (*watch)(void *watch_ctx);
    void *watch_ctx;
} isolated_extra;

/* isolated_read with `extra` (NULL: none); -2 when watch stopped it. */
int isolated_read_with(const char *path, isolated_fn fn, void *ctx, const isolated_extra *extra, char **answer,
                       size_t *size, char *why, size_t why_len);

/* write(2) of all n bytes, through EINTR; 0 on success. For fn. */
int isolated_write_all(int fd, const void *data, size_t n);

#ifdef __cplusplus
}
#endif

#endif
