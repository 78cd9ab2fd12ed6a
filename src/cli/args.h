/* sdftrace CLI — option values, parsed strictly (src/common/parse.h) and
 * checked against their range, else one line in msg. Shared by the
 * commands. */
#ifndef SDFTRACE_ARGS_H
#define SDFTRACE_ARGS_H

#include <stddef.h>

/* A finite float in [lo, hi]. 0 on success. */
int arg_float(const char *flag, const char *text, float lo, float hi, float *out, char *msg, size_t msg_len);
/* An integer in [lo, hi]. 0 on success. */
int arg_long(const char *flag, const char *text, long lo, long hi, long *out, char *msg, size_t msg_len);
/* Exactly n (at most 16) comma-separated finite floats. 0 on success. */
int arg_floats(const char *flag, const char *text, int n, float *out, char *msg, size_t msg_len);

/* Prints "sdftrace CMD: MSG" as one line on stderr. */
void cli_error(const char *cmd, const char *msg);

#endif
