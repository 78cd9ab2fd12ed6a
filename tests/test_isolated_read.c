/* sdftrace tests — a dependency's reader in a child process
 * (src/common/isolated_read.h): its answer comes back; a crash, a child
 * that loops and one that waits forever give one line each; a child that
 * takes longer than the limit in wall time but not in processor time (one
 * that waits its turn on a loaded machine) is not stopped. */
#define _POSIX_C_SOURCE 200809L /* setenv, nanosleep */
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "isolated_read.h"

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int answer_hello(void *ctx, int fd)
{
    (void)ctx;
    return isolated_write_all(fd, "hello", 5);
}

static void sleep_s(double s)
{
    struct timespec t = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    while (nanosleep(&t, &t) != 0) {
    }
}

static double cpu_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Works 5 ms of processor time and waits 45 ms, over and over for *ctx
 * seconds of wall time (as a reader given a tenth of a processor), then
 * answers. */
static int work_slowly_then_answer(void *ctx, int fd)
{
    const double until = now_s() + *(const double *)ctx;
    volatile uint64_t n = 0;
    while (now_s() < until) {
        const double t = cpu_s();
        while (cpu_s() - t < 0.005)
            n += 1;
        sleep_s(0.045);
    }
    return isolated_write_all(fd, "late", 4);
}

static int wait_forever(void *ctx, int fd)
{
    (void)ctx, (void)fd;
    for (;;)
        sleep_s(60.0);
    return 0;
}

static int spin_forever(void *ctx, int fd)
{
    (void)fd;
    volatile uint64_t *n = ctx;
    for (;;)
        *n += 1;
    return 0;
}

static int crash(void *ctx, int fd)
{
    (void)fd;
    (void)ctx;
    raise(SIGSEGV);
    return 0;
}

static int run(isolated_fn fn, void *ctx, char *why, size_t why_len, char **answer, size_t *size)
{
    return isolated_read("/dev/null", fn, ctx, answer, size, why, why_len);
}

static void test_answer_comes_back(void **state)
{
    (void)state;
    char why[128] = "", *answer = NULL;
    size_t size = 0;
    assert_int_equal(run(answer_hello, NULL, why, sizeof why, &answer, &size), 0);
    assert_int_equal(size, 5);
    assert_memory_equal(answer, "hello", 5);
    free(answer);
}

static void test_crash_is_one_line(void **state)
{
    (void)state;
    char why[128] = "", *answer = NULL;
    size_t size = 0;
    assert_int_equal(run(crash, NULL, why, sizeof why, &answer, &size), -1);
    assert_non_null(strstr(why, "signal 11"));
    assert_null(answer);
}

/* A child that loops is stopped once it has spent the limit in processor
 * time, and says so; soon after (not at the wall limit, ten times later). */
static void test_loop_stops_at_processor_limit(void **state)
{
    (void)state;
    setenv("SDFT_READ_TIME_LIMIT", "0.5", 1);
    assert_true(isolated_time_limit("/dev/null") == 0.5);
    char why[128] = "", *answer = NULL;
    size_t size = 0;
    uint64_t n = 0;
    const double t0 = now_s();
    assert_int_equal(run(spin_forever, &n, why, sizeof why, &answer, &size), -1);
    const double took = now_s() - t0;
    assert_string_equal(why, "ran past 0.5 s of processor time");
    assert_true(took >= 0.5);
    assert_true(took < 0.5 * ISOLATED_WALL_FACTOR);
    unsetenv("SDFT_READ_TIME_LIMIT");
}

/* A child that takes three times the limit in wall time, a tenth of it
 * working, answers; one that waits forever is stopped once it has spent
 * no processor time for the limit's seconds. */
static void test_slow_wall_is_not_stopped(void **state)
{
    (void)state;
    setenv("SDFT_READ_TIME_LIMIT", "0.5", 1);
    char why[128] = "", *answer = NULL;
    size_t size = 0;
    double wall = 1.5;
    assert_int_equal(run(work_slowly_then_answer, &wall, why, sizeof why, &answer, &size), 0);
    assert_int_equal(size, 4);
    assert_memory_equal(answer, "late", 4);
    free(answer);
    answer = NULL;
    const double t0 = now_s();
    assert_int_equal(run(wait_forever, NULL, why, sizeof why, &answer, &size), -1);
    assert_string_equal(why, "stalled for 0.5 s");
    assert_true(now_s() - t0 < 0.5 * ISOLATED_WALL_FACTOR);
    unsetenv("SDFT_READ_TIME_LIMIT");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_answer_comes_back),
        cmocka_unit_test(test_crash_is_one_line),
        cmocka_unit_test(test_loop_stops_at_processor_limit),
        cmocka_unit_test(test_slow_wall_is_not_stopped),
    };
    return cmocka_run_group_tests_name("isolated_read", tests, NULL, NULL);
}
