/* sdftrace common — strict number parsing (see parse.h). */
#include "parse.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>

/* The number at the start of text: 0 with *end after it, or -1. */
static int leading_number(const char *text, double *out, const char **end)
{
    if (!text || !*text || isspace((unsigned char)*text))
        return -1;
    char *stop = NULL;
    errno = 0;
    const double v = strtod(text, &stop);
    if (stop == text || errno == ERANGE || !isfinite(v))
        return -1;
    *out = v, *end = stop;
    return 0;
}

int parse_number(const char *text, double *out)
{
    const char *end;
    double v;
    if (leading_number(text, &v, &end) || *end)
        return -1;
    *out = v;
    return 0;
}

int parse_integer(const char *text, long *out)
{
    if (!text || !*text || isspace((unsigned char)*text))
        return -1;
    char *end = NULL;
    errno = 0;
    const long v = strtol(text, &end, 10);
    if (end == text || *end || errno == ERANGE)
        return -1;
    *out = v;
    return 0;
}

int parse_numbers(const char *text, int n, double *out)
{
    const char *p = text;
    for (int i = 0; i < n; i++) {
        const char *end;
        if (leading_number(p, &out[i], &end) || (i + 1 < n ? *end != ',' : *end != '\0'))
            return -1;
        p = end + 1;
    }
    return 0;
}
