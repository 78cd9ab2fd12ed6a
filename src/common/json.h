/* sdftrace common — JSON output: `sdftrace render --json`, and the one
 * writer of the sidecar files beside .npy arrays (a converted grid's, by
 * libsdftrace_mesh; mesh2sdf's samples' and queries'). Internal header (C
 * and C++). */
#ifndef SDFTRACE_COMMON_JSON_H
#define SDFTRACE_COMMON_JSON_H

#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Writes s as a JSON string literal, quotes included: '"' and '\' escaped,
 * control characters as \u00XX, everything else (UTF-8 too) as it is. s
 * NULL writes null. Returns 0, or -1 when the stream reports an error. */
int json_put_string(FILE *out, const char *s);

/* One member of a JSON object: its value a string (quoted and escaped as
 * json_put_string does) or, `raw`, JSON text written as it is (a number,
 * an array, true). */
typedef struct json_member {
    const char *key;
    const char *value;
    int raw;
} json_member;

/* Writes the members, in order, as one JSON object into a new file at path
 * (by name: the caller's temporary file), a member a line, two spaces in:
 * "{\n  \"a\": 1,\n  \"b\": \"x\"\n}\n". 0, or -1 with one line in msg. */
int json_write_object(const char *path, const json_member *members, size_t count, char *msg, size_t msg_len);

#ifdef __cplusplus
}
#endif
#endif
