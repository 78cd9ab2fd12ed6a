/* sdftrace tests — small helpers shared by the cmocka programs: running the
 * command-line tools, temporary paths, a deterministic random stream. */
#ifndef SDFT_TESTUTIL_H
#define SDFT_TESTUTIL_H

#include <stddef.h>
#include <stdint.h>

/* Runs a shell command; captures up to out_len-1 bytes of stdout+stderr into
 * out (may be NULL) and returns its exit status (-1 if it could not run). */
int tu_run(char *out, size_t out_len, const char *fmt, ...);

/* A path under the build's test temporary folder: SDFT_TEST_TMP/name.
 * The returned string is static per call site buffer `buf`. */
const char *tu_tmp(char *buf, size_t len, const char *name);

int tu_file_exists(const char *path);

/* The number of newlines in s: a tool's error must be one line. */
int tu_lines(const char *s);

/* xorshift64*: deterministic, so failures reproduce. */
typedef struct tu_rng {
    uint64_t state;
} tu_rng;
static inline tu_rng tu_rng_seed(uint64_t seed) { return (tu_rng){seed * 0x9E3779B97F4A7C15ull + 1}; }
float tu_uniform(tu_rng *r, float lo, float hi);

#endif
