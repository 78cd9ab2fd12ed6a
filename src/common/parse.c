/* sdftrace common — strict number parsing (see parse.h). */
#include "parse.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

int parse_in_range(double v, double lo, double hi, int open)
{
    const int lo_ok = (open & PARSE_OPEN_LO) ? v > lo : v >= lo;
    const int hi_ok = (open & PARSE_OPEN_HI) ? v < hi : v <= hi;
    return lo_ok && hi_ok;
}

void parse_range_text(double lo, double hi, int open, const char *fmt, char *buf, size_t len)
{
    const int lo_open = open & PARSE_OPEN_LO, hi_open = open & PARSE_OPEN_HI;
    char a[32], b[32];
    snprintf(a, sizeof a, fmt, lo);
    snprintf(b, sizeof b, fmt, hi);
    if (isinf(lo) && isinf(hi))
        buf[0] = '\0';
    else if (isinf(hi))
        snprintf(buf, len, " %s %s", lo_open ? ">" : ">=", a);
    else if (isinf(lo))
        snprintf(buf, len, " %s %s", hi_open ? "<" : "<=", b);
    else
        snprintf(buf, len, " in %c%s, %s%c", lo_open ? '(' : '[', a, b, hi_open ? ')' : ']');
}

size_t parse_list_item(const char *list, int i, const char **name)
{
    const char *c = list ? list : "";
    for (c += strspn(c, " "); i > 0 && *c; i--) {
        c += strcspn(c, " ");
        c += strspn(c, " ");
    }
    *name = c;
    return i == 0 ? strcspn(c, " ") : 0;
}

int parse_list_index(const char *list, const char *word)
{
    const char *name;
    size_t n;
    for (int i = 0; (n = parse_list_item(list, i, &name)) > 0; i++)
        if (strlen(word) == n && strncmp(word, name, n) == 0)
            return i;
    return -1;
}
