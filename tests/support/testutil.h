/* sdftrace tests — small helpers shared by the cmocka programs: running the
 * command-line tools, temporary paths, a deterministic random stream. */
#ifndef SDFT_TESTUTIL_H
#define SDFT_TESTUTIL_H

#include <stddef.h>
#include <stdint.h>

#include "sdftrace/vdb.h"

/* Runs a shell command; captures up to out_len-1 bytes of stdout+stderr into
 * out (may be NULL) and returns its exit status (-1 if it could not run). */
int tu_run(char *out, size_t out_len, const char *fmt, ...);

/* A path under the build's test temporary folder: SDFT_TEST_TMP/name.
 * The returned string is static per call site buffer `buf`. */
const char *tu_tmp(char *buf, size_t len, const char *name);

int tu_file_exists(const char *path);

/* The number of newlines in s: a tool's error must be one line. */
int tu_lines(const char *s);

/* The whole of a file, NUL-terminated, for the caller to free; NULL if it
 * cannot be read. */
char *tu_slurp(const char *path);

/* Writes `text` as the whole of a file: 0, or -1 if it cannot. */
int tu_write_text(const char *path, const char *text);
#define tu_assert_write_text(path, text) assert_int_equal(tu_write_text(path, text), 0)

/* 1 when README.md holds the whole of the repository's file `path` (a
 * path from the repository's root), so that what it shows cannot rot. */
int tu_readme_shows(const char *path);

/* How many temporary files of an atomic write to `name` (".NAME.tmp-*",
 * src/common/atomic_file.h) are in folder `dir`. */
int tu_temporaries(const char *dir, const char *name);
#define tu_assert_no_temporaries(dir, name) assert_int_equal(tu_temporaries(dir, name), 0)

/* The permission bits of path (e.g. 0644); -1 if it does not exist. */
int tu_file_mode(const char *path);

/* xorshift64*: deterministic, so failures reproduce. */
typedef struct tu_rng {
    uint64_t state;
} tu_rng;
static inline tu_rng tu_rng_seed(uint64_t seed) { return (tu_rng){seed * 0x9E3779B97F4A7C15ull + 1}; }
float tu_uniform(tu_rng *r, float lo, float hi);

/* The one way to open a grid, as the tests call it: sdft_grid_open on a
 * path (read as a .nvdb file whatever its name); sdft_vdb_open on a path
 * (by its extension) with `quant` and the other defaults, or with o's
 * options (o NULL is passed on as NULL); sdft_grid_open on a buffer taken
 * as `memory` (release: SDFT_GRID_ADOPT's). */
sdft_error tu_open_nvdb(const char *path, const char *name, sdft_grid **out, char *msg, size_t msg_len);
sdft_error tu_open_file(const char *path, const char *name, sdft_quant quant, sdft_grid **out, char *msg,
                        size_t msg_len);
sdft_error tu_open_with(const char *path, const char *name, const sdft_grid_options *o, sdft_grid **out, char *msg,
                        size_t msg_len);
sdft_error tu_open_buffer(const void *data, size_t size, const char *name, sdft_grid_memory memory,
                          void (*release)(void *data), sdft_grid **out, char *msg, size_t msg_len);

#endif
