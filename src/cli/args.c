/* sdftrace CLI — option values. strtod/strtol accept leading blanks, "nan",
 * "inf" and trailing junk; we accept none of those. */
#include "args.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int parse_double(const char *text, const char **end, double *out)
{
    if (!text || !*text || isspace((unsigned char)*text))
        return -1;
    char *stop = NULL;
    errno = 0;
    *out = strtod(text, &stop);
    *end = stop;
    return (stop == text || errno == ERANGE || !isfinite(*out)) ? -1 : 0;
}

int arg_float(const char *flag, const char *text, float lo, float hi, float *out, char *msg, unsigned msg_len)
{
    const char *end;
    double v;
    if (parse_double(text, &end, &v) || *end) {
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

int arg_long(const char *flag, const char *text, long lo, long hi, long *out, char *msg, unsigned msg_len)
{
    char *end = NULL;
    errno = 0;
    long v = (text && *text && !isspace((unsigned char)*text)) ? strtol(text, &end, 10) : 0;
    if (!text || !end || end == text || *end || errno == ERANGE) {
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

int arg_floats(const char *flag, const char *text, int n, float *out, char *msg, unsigned msg_len)
{
    const char *p = text;
    for (int i = 0; i < n; i++) {
        double v;
        const char *end;
        if (parse_double(p, &end, &v) || (i + 1 < n ? *end != ',' : *end != '\0')) {
            snprintf(msg, msg_len, "%s needs %d comma-separated finite numbers, got '%s'", flag, n, text ? text : "");
            return -1;
        }
        out[i] = (float)v;
        p = end + 1;
    }
    return 0;
}

void cli_error(const char *cmd, const char *msg)
{
    fprintf(stderr, "sdftrace%s%s: %s\n", cmd ? " " : "", cmd ? cmd : "", msg);
}
