/* stats — the bench statistics (stats.h) for the shell benches: reads
 * samples from standard input and prints their median and its 95%
 * percentile-bootstrap interval, as bench/study computes them.
 *
 *   printf '%s\n' 12.1 11.8 12.6 13.9 12.0 | build/bench/stats
 *   12.1 11.8 13.9 5
 *   ... | build/bench/stats --text 1             12.1 [11.8–13.9]
 *   printf '%s %s\n' A1 B1 A2 B2 ... | build/bench/stats --ratio
 *                                                  (the samples are A/B, pair by pair:
 *                                                   rows timed side by side)
 *
 * Samples are numbers separated by white space; with --ratio, each line
 * holds one pair. Anything else is an error: one line, exit 2. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmdline.h" /* src/common: the option table */
#include "parse.h"   /* src/common: parse_number */
#include "stats.h"

typedef struct stats_options {
    double level;
    int ratio, digits;
} stats_options;

static int fail(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("stats: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return 2;
}

/* Appends x to the samples; 0, or 2 with the message printed. */
static int push(double **v, int *n, int *cap, double x)
{
    if (*n == *cap) {
        *cap = *cap ? 2 * *cap : 64;
        double *grown = *cap <= BENCH_MAX_SAMPLES ? realloc(*v, (size_t)*cap * sizeof *grown) : NULL;
        if (!grown)
            return fail("more than %d samples", BENCH_MAX_SAMPLES);
        *v = grown;
    }
    (*v)[(*n)++] = x;
    return 0;
}

/* The samples of standard input into *v: every word, or with --ratio the
 * quotient of each line's pair. 0, or 2 with the message printed. */
static int read_samples(const stats_options *o, double **v, int *n)
{
    char line[4096];
    int cap = 0, lineno = 0;
    while (fgets(line, sizeof line, stdin)) {
        lineno++;
        if (!strchr(line, '\n') && !feof(stdin))
            return fail("line %d: longer than %zu characters", lineno, sizeof line - 2);
        double pair[2];
        int words = 0, rc = 0;
        for (char *w = strtok(line, " \t\r\n"); w && !rc; w = strtok(NULL, " \t\r\n")) {
            double x;
            if (parse_number(w, &x) || !isfinite(x))
                return fail("line %d: '%s' is not a finite number", lineno, w);
            if (!o->ratio)
                rc = push(v, n, &cap, x);
            else if (words == 2)
                return fail("line %d: --ratio takes a pair A B on each line, not more", lineno);
            else
                pair[words++] = x;
        }
        if (rc)
            return rc;
        if (o->ratio && words == 1)
            return fail("line %d: --ratio takes a pair A B on each line, not one number", lineno);
        if (o->ratio && words == 2) {
            if (pair[1] == 0.0)
                return fail("line %d: --ratio: B is 0", lineno);
            if ((rc = push(v, n, &cap, pair[0] / pair[1])))
                return rc;
        }
    }
    return *n ? 0 : fail("no samples on standard input");
}

int main(int argc, char **argv)
{
    stats_options o = {.level = 0.95, .digits = -1};
    const cmdline_option rows[] = {
        {"level", 0, "L", "the interval's confidence level", CMDLINE_DOUBLE, &o.level, .lo = 0, .hi = 1,
         .open = CMDLINE_OPEN_LO | CMDLINE_OPEN_HI},
        {"ratio", 0, NULL, "each line holds a pair A B; the samples are A/B", CMDLINE_SET, &o.ratio, .value = 1,
         .def = ""},
        {"text", 0, "D", "print \"MEDIAN [LO–HI]\" with D decimals instead of \"MEDIAN LO HI N\"", CMDLINE_INT,
         &o.digits, .lo = 0, .hi = 12, .def = ""},
        {"help", 'h', NULL, NULL, CMDLINE_HELP, NULL, .def = ""},
        {0},
    };
    const cmdline_spec spec = {
        .program = "stats",
        .usage = "usage: stats [--level L] [--ratio] [--text D] < SAMPLES\n"
                 "The median of the samples on standard input and its percentile-bootstrap interval\n"
                 "(10000 resamples from a fixed seed): prints MEDIAN LO HI N.\n",
        .rows = rows,
        .column = 14,
    };
    char msg[512];
    const int parsed = cmdline_parse(&spec, argc, argv, msg, sizeof msg);
    if (parsed == CMDLINE_HELP_ASKED) {
        cmdline_help(&spec, stdout);
        return 0;
    }
    if (parsed != CMDLINE_OK)
        return fail("%s", msg);
    double *v = NULL;
    int n = 0;
    int rc = read_samples(&o, &v, &n);
    bench_summary s;
    if (!rc && bench_summarize(v, n, o.level, &s))
        rc = fail("out of memory");
    free(v);
    if (rc)
        return rc;
    char text[128];
    if (o.digits >= 0)
        printf("%s\n", bench_summary_text(&s, o.digits, text, sizeof text));
    else
        printf("%.9g %.9g %.9g %d\n", s.median, s.lo, s.hi, s.n);
    return 0;
}
