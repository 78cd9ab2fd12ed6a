/* sdftrace common — numbers on the command line, parsed strictly and the
 * same way by both tools: the whole text must be the number, with no
 * leading blanks, no trailing junk, no "nan" or "inf", and no overflow.
 * (strtod and strtol alone accept all of those.) Range checks and
 * messages stay with each option. Internal header (C and C++). */
#ifndef SDFTRACE_COMMON_PARSE_H
#define SDFTRACE_COMMON_PARSE_H

#ifdef __cplusplus
extern "C" {
#endif

/* A finite decimal or hexadecimal floating-point number: 0, or -1. */
int parse_number(const char *text, double *out);

/* A decimal integer that fits a long: 0, or -1. */
int parse_integer(const char *text, long *out);

/* Exactly n comma-separated finite numbers ("1,2.5,-3"): 0, or -1. */
int parse_numbers(const char *text, int n, double *out);

#ifdef __cplusplus
}
#endif
#endif
