/* sdftrace common — JSON output for the tools: `sdftrace render --json` and
 * mesh2sdf's .npy sidecar. Internal header (C and C++). */
#ifndef SDFTRACE_COMMON_JSON_H
#define SDFTRACE_COMMON_JSON_H

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Writes s as a JSON string literal, quotes included: '"' and '\' escaped,
 * control characters as \u00XX, everything else (UTF-8 too) as it is. s
 * NULL writes null. Returns 0, or -1 when the stream reports an error. */
int json_put_string(FILE *out, const char *s);

#ifdef __cplusplus
}
#endif
#endif
