/* bench statistics — the median and its percentile-bootstrap interval
 * (stats.h says why these). */
#include "stats.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median of v[0..n), which it sorts. */
static double median_sorting(double *v, int n)
{
    if (n <= 16) {
        for (int i = 1; i < n; i++) /* insertion sort: the resamples are a handful */
            for (int j = i; j > 0 && v[j - 1] > v[j]; j--) {
                const double t = v[j];
                v[j] = v[j - 1], v[j - 1] = t;
            }
    } else {
        qsort(v, (size_t)n, sizeof *v, cmp_double);
    }
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double bench_median(const double *x, int n)
{
    if (n < 1 || n > BENCH_MAX_SAMPLES)
        return NAN;
    double *v = malloc((size_t)n * sizeof *v);
    if (!v)
        return NAN;
    memcpy(v, x, (size_t)n * sizeof *v);
    const double m = median_sorting(v, n);
    free(v);
    return m;
}

/* xorshift64*: a fixed stream, so an interval is a function of its samples. */
static uint64_t next_random(uint64_t *s)
{
    *s ^= *s >> 12, *s ^= *s << 25, *s ^= *s >> 27;
    return *s * 0x2545F4914F6CDD1Dull;
}

/* A uniform index in [0, n): the top 32 bits scaled (Lemire's multiply-shift,
 * bias below n / 2^32). */
static int random_index(uint64_t *s, int n) { return (int)(((next_random(s) >> 32) * (uint64_t)n) >> 32); }

int bench_summarize(const double *x, int n, double level, bench_summary *out)
{
    *out = (bench_summary){NAN, NAN, NAN, 0};
    if (n < 1 || n > BENCH_MAX_SAMPLES || !(level > 0.0 && level < 1.0))
        return -1;
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i]))
            return -1;
    double *resample = malloc((size_t)n * sizeof *resample);
    double *medians = malloc(BENCH_RESAMPLES * sizeof *medians);
    if (!resample || !medians) {
        free(resample);
        free(medians);
        return -1;
    }
    uint64_t seed = 0x853C49E6748FEA9Bull;
    for (int b = 0; b < BENCH_RESAMPLES; b++) {
        for (int i = 0; i < n; i++)
            resample[i] = x[random_index(&seed, n)];
        medians[b] = median_sorting(resample, n);
    }
    qsort(medians, BENCH_RESAMPLES, sizeof *medians, cmp_double);
    /* The smallest resampled median at or above each tail's share: the
     * ceil(B a)-th smallest, counting from 1. */
    const double tail = 0.5 * (1.0 - level);
    int lo = (int)ceil(BENCH_RESAMPLES * tail - 1e-9), hi = (int)ceil(BENCH_RESAMPLES * (1.0 - tail) - 1e-9);
    lo = lo < 1 ? 1 : lo, hi = hi > BENCH_RESAMPLES ? BENCH_RESAMPLES : hi;
    memcpy(resample, x, (size_t)n * sizeof *resample);
    *out = (bench_summary){.median = median_sorting(resample, n), .lo = medians[lo - 1], .hi = medians[hi - 1], .n = n};
    free(resample);
    free(medians);
    return 0;
}

const char *bench_summary_text(const bench_summary *s, int digits, char *buf, unsigned long len)
{
    if (s->n < 1)
        snprintf(buf, len, "–");
    else
        snprintf(buf, len, "%.*f [%.*f–%.*f]", digits, s->median, digits, s->lo, digits, s->hi);
    return buf;
}

double bench_load_average(void)
{
    double l = NAN;
    FILE *f = fopen("/proc/loadavg", "r");
    if (f) {
        if (fscanf(f, "%lf", &l) != 1)
            l = NAN;
        fclose(f);
    }
    return l;
}
