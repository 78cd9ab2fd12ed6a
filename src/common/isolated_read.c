/* sdftrace — a dependency's reader in a child process (isolated_read.h). */
#define _GNU_SOURCE /* pipe2, strsignal */
#include "isolated_read.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "memory_limit.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SDFT_UNDER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define SDFT_UNDER_ASAN 1
#endif
#if defined(SDFT_UNDER_ASAN)
#include <sanitizer/common_interface_defs.h>
#endif

static double file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (double)st.st_size : 0.0;
}

double isolated_time_limit(const char *path)
{
    const char *env = getenv("SDFT_READ_TIME_LIMIT");
    double forced;
    if (env && sscanf(env, "%lf", &forced) == 1 && forced > 0)
        return forced;
    return 10.0 + file_size(path) / (double)(8u << 20);
}

int isolated_write_all(int fd, const void *data, size_t n)
{
    const char *p = data;
    while (n) {
        const ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        p += w, n -= (size_t)w;
    }
    return 0;
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

#if !defined(SDFT_UNDER_ASAN)
/* The process's address space now, in bytes (/proc/self/statm's first
 * field); 0 where it cannot be read. */
static uint64_t address_space_bytes(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long long pages = 0;
    if (f) {
        if (fscanf(f, "%llu", &pages) != 1)
            pages = 0;
        fclose(f);
    }
    return (uint64_t)pages * (uint64_t)sysconf(_SC_PAGESIZE);
}
#endif

/* The child: quiet, limited (the file's allowance plus `extra` bytes), fn, _exit. */
static void run_child(const char *path, int fd, isolated_fn fn, void *ctx, double extra)
{
    /* A crash here ends the child with its signal, for the parent to
     * report: the caller's crash handlers (a crash reporter's, libFuzzer's
     * that save the input as a crash of their own) must not run. */
    static const int fatal[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGTRAP, SIGSYS};
    for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; i++)
        signal(fatal[i], SIG_DFL);
    /* Ctrl-C and kill end the reader as they would have ended the caller
     * (whose handlers may only set a flag the reader never looks at). */
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0)
        dup2(null, STDOUT_FILENO), dup2(null, STDERR_FILENO), close(null);
#if defined(SDFT_UNDER_ASAN)
    (void)path, (void)extra;
    /* The child's death is the parent's to report: a sanitizer's death
     * callback (libFuzzer's writes the input as a crash of its own) must
     * not run here. */
    __sanitizer_set_death_callback(NULL);
#else
    /* The mappings it inherits, plus what the file may unpack to. */
    struct rlimit as;
    const double unpacked = 256.0 * 1024 * 1024 + 64.0 * file_size(path) + extra,
                 machine = (double)memory_machine_bytes();
    const uint64_t limit = address_space_bytes() + (uint64_t)(unpacked < machine ? unpacked : machine);
    if (getrlimit(RLIMIT_AS, &as) == 0 && (as.rlim_cur == RLIM_INFINITY || limit < (uint64_t)as.rlim_cur)) {
        as.rlim_cur = (rlim_t)limit;
        setrlimit(RLIMIT_AS, &as);
    }
#endif
    /* exit_group directly: sanitizers intercept _exit to check for leaks,
     * which in a forked copy of a large process takes longer than the read. */
    syscall(SYS_exit_group, fn(ctx, fd) == 0 ? 0 : 1);
    _exit(1);
}

/* The processor time child `pid` has spent, all its threads, in seconds;
 * -1 where it cannot be read. */
static double child_cpu_s(clockid_t clock)
{
    struct timespec t;
    if (clock_gettime(clock, &t) != 0)
        return -1.0;
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Why collect stopped a child before its end. */
typedef enum { RAN_PAST_PROCESSOR, RAN_PAST_WALL, STALLED } stop_reason;

/* Appends what the child writes to *buf until it closes the pipe (1) or
 * is stopped (0, *stopped says why): its processor time passes `limit`,
 * it spends none for `limit` seconds of wall time in a row, or the wall
 * time passes ISOLATED_WALL_FACTOR limit. -1 when memory runs out, -2 when
 * the watch (NULL: none) says stop. The child's clock is looked at every
 * 50 ms at most; where it cannot be read, `limit` is wall time. */
static int collect(int fd, pid_t pid, double limit, const isolated_extra *x, char **buf, size_t *size,
                   stop_reason *stopped)
{
    size_t cap = 0;
    const int watching = x && x->watch;
    double start = now_s(), deadline = start + ISOLATED_WALL_FACTOR * limit, last = start;
    clockid_t clock;
    const int timed = clock_getcpuclockid(pid, &clock) == 0;
    double spent = 0.0, working_at = start; /* the child's processor time, and when it last grew */
    for (;;) {
        const double now = now_s();
        if (now - last > 1.0) /* this process was stopped (^Z) or starved itself: that time is not the child's */
            start += now - last, deadline += now - last, working_at += now - last;
        last = now;
        const double left = deadline - now;
        const double cpu = timed ? child_cpu_s(clock) : -1.0;
        if (cpu > spent)
            spent = cpu, working_at = now;
        *stopped = !timed || spent > limit ? RAN_PAST_PROCESSOR : left <= 0 ? RAN_PAST_WALL : STALLED;
        if (timed ? spent > limit || left <= 0 || now - working_at > limit : now - start > limit)
            return 0;
        if (watching && x->watch(x->watch_ctx))
            return -2;
        struct pollfd p = {fd, POLLIN, 0};
        const int wait_ms = (int)(left * 1000) + 1, most = watching ? 20 : 50;
        const int r = poll(&p, 1, wait_ms > most ? most : wait_ms);
        if (r < 0 && errno == EINTR)
            continue;
        if (r == 0)
            continue; /* the limits, or the next watch, decide */
        if (*size + 65536 > cap) {
            cap = 2 * (*size + 65536);
            char *grown = realloc(*buf, cap);
            if (!grown)
                return -1;
            *buf = grown;
        }
        const ssize_t n = read(fd, *buf + *size, cap - *size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return 1;
        *size += (size_t)n;
    }
}

/* Waits for the child; 0 when it exited 0, else why in a few words. */
static int reap(pid_t pid, char *why, size_t why_len)
{
    int status = 0;
    pid_t w;
    while ((w = waitpid(pid, &status, 0)) < 0 && errno == EINTR) {
    }
    if (w != pid) { /* SIGCHLD ignored by the application: reaped already, status unknown */
        snprintf(why, why_len, "ended without a status");
        return 0;
    }
    if (WIFSIGNALED(status)) {
        snprintf(why, why_len, "signal %d (%s)", WTERMSIG(status), strsignal(WTERMSIG(status)));
        return -1;
    }
    snprintf(why, why_len, "exit status %d", WEXITSTATUS(status));
    return WEXITSTATUS(status) == 0 ? 0 : -1;
}

int isolated_read(const char *path, isolated_fn fn, void *ctx, char **answer, size_t *size, char *why, size_t why_len)
{
    return isolated_read_with(path, fn, ctx, NULL, answer, size, why, why_len);
}

int isolated_read_with(const char *path, isolated_fn fn, void *ctx, const isolated_extra *extra, char **answer,
                       size_t *size, char *why, size_t why_len)
{
    const double time_limit = isolated_time_limit(path);
    *answer = NULL, *size = 0;
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) {
        snprintf(why, why_len, "cannot start a reader process: %s", strerror(errno));
        return -1;
    }
    fflush(NULL); /* nothing buffered is written twice */
    const pid_t pid = fork();
    if (pid < 0) {
        snprintf(why, why_len, "cannot start a reader process: %s", strerror(errno));
        close(fds[0]), close(fds[1]);
        return -1;
    }
    if (pid == 0) {
        close(fds[0]);
        run_child(path, fds[1], fn, ctx, extra ? extra->bytes : 0.0);
    }
    close(fds[1]);
    stop_reason stopped = RAN_PAST_PROCESSOR;
    const int done = collect(fds[0], pid, time_limit, extra, answer, size, &stopped);
    close(fds[0]);
    if (done <= 0)
        kill(pid, SIGKILL);
    const int ended = reap(pid, why, why_len);
    if (done == 0 && stopped == RAN_PAST_PROCESSOR)
        snprintf(why, why_len, "ran past %g s of processor time", time_limit);
    else if (done == 0 && stopped == RAN_PAST_WALL)
        snprintf(why, why_len, "ran past %g s", ISOLATED_WALL_FACTOR * time_limit);
    else if (done == 0)
        snprintf(why, why_len, "stalled for %g s", time_limit);
    else if (done == -1)
        snprintf(why, why_len, "out of memory for its answer");
    else if (done == -2)
        snprintf(why, why_len, "stopped");
    if (done > 0 && ended == 0)
        return 0;
    free(*answer);
    *answer = NULL, *size = 0;
    return done == -2 ? -2 : -1;
}
