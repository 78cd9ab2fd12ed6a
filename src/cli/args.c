/* sdftrace CLI — option values: the shared strict parser, then the range. */
#include "args.h"

#include <stdio.h>

#include "parse.h"

int arg_float(const char *flag, const char *text, float lo, float hi, float *out, char *msg, size_t msg_len)
{
    double v;
    if (sdft_parse_number(text, &v)) {
        snprintf(msg, msg_len, "%s needs a finite number, got '%s'", flag, text ? text : "");
        return -1;
    }
    if (!(v >= lo && v <= hi)) {
        snprintf(msg, msg_len, "%s must be in [%g, %g], got %s", flag, lo, hi, text);
        return -1;
    }
    *out = (float)v;
    return 0;
}

int arg_long(const char *flag, const char *text, long lo, long hi, long *out, char *msg, size_t msg_len)
{
    long v;
    if (sdft_parse_integer(text, &v)) {
        snprintf(msg, msg_len, "%s needs an integer, got '%s'", flag, text ? text : "");
        return -1;
    }
    if (v < lo || v > hi) {
        snprintf(msg, msg_len, "%s must be in [%ld, %ld], got %s", flag, lo, hi, text);
        return -1;
    }
    *out = v;
    return 0;
}

int arg_floats(const char *flag, const char *text, int n, float *out, char *msg, size_t msg_len)
{
    double v[16];
    if (n > 16 || sdft_parse_numbers(text, n, v)) {
        snprintf(msg, msg_len, "%s needs %d comma-separated finite numbers, got '%s'", flag, n, text ? text : "");
        return -1;
    }
    for (int i = 0; i < n; i++)
        out[i] = (float)v[i];
    return 0;
}

void cli_error(const char *cmd, const char *msg)
{
    fprintf(stderr, "sdftrace%s%s: %s\n", cmd ? " " : "", cmd ? cmd : "", msg);
}
