/* sdftrace common — numbers on the command line, parsed strictly and the
 * same way by both tools: the whole text must be the number, with no
 * leading blanks, no trailing junk, no "nan" or "inf", and no overflow.
 * (strtod and strtol alone accept all of those.) And ranges, checked and
 * named the same way wherever a number is checked (the option table, the
 * mesh component's settings). Internal header (C and C++). */
#ifndef SDFTRACE_COMMON_PARSE_H
#define SDFTRACE_COMMON_PARSE_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A finite decimal or hexadecimal floating-point number: 0, or -1. */
int parse_number(const char *text, double *out);

/* A decimal integer that fits a long: 0, or -1. */
int parse_integer(const char *text, long *out);

/* Exactly n comma-separated finite numbers ("1,2.5,-3"): 0, or -1. */
int parse_numbers(const char *text, int n, double *out);

/* The i-th name (from 0) of a list of names separated by spaces ("winding
 * flood none"): its length, with *name at it; 0 when the list has none. */
size_t parse_list_item(const char *list, int i, const char **name);

/* The place of `word` in such a list, or -1. */
int parse_list_index(const char *list, const char *word);

/* parse_in_range and parse_range_text's `open`: an end excluded. */
enum { PARSE_OPEN_LO = 1, PARSE_OPEN_HI = 2 };

/* Whether v lies in [lo, hi], less the ends `open` names: 1 or 0 (NaN: 0). */
int parse_in_range(double v, double lo, double hi, int open);

/* The range as a message says it, into buf: " in [1, 4096]", " in (0, 1]",
 * " > 0", " <= 9" (an infinite end is left out), or "" for no range; each
 * end printed with `fmt` ("%g", "%.0f"). */
void parse_range_text(double lo, double hi, int open, const char *fmt, char *buf, size_t len);

#ifdef __cplusplus
}
#endif
#endif
