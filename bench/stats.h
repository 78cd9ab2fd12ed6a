/* bench statistics — what every time on a results page is: the median of
 * repeated, interleaved measurements and its 95% percentile-bootstrap
 * interval. One implementation, for bench/study (linked) and for the shell
 * benches (the program bench/stats, over this file).
 *
 * Why the median and the bootstrap: on a shared machine a few repeats are
 * hit by someone else's build and run long; the median ignores them, and
 * the bootstrap interval of the median needs no assumption about their
 * distribution. Resampling n values with replacement, the median of the
 * resample is one of the samples (n odd), and its distribution is exact
 * combinatorics: P(median <= x_(j)) = P(at least (n+1)/2 of n draws are
 * <= x_(j)) = sum_{i >= (n+1)/2} C(n, i) (j/n)^i (1 - j/n)^(n-i). For n = 5
 * that puts 5.8% of the mass on each extreme, so the 95% interval of five
 * repeats is their range; from n = 7 on it is narrower (x_(2) to x_(n-1)).
 * The resamples are drawn from a fixed seed, so a page's interval is a
 * function of its samples alone. */
#ifndef SDFT_BENCH_STATS_H
#define SDFT_BENCH_STATS_H

typedef struct bench_summary {
    double median;
    double lo, hi; /* the percentile-bootstrap interval of the median at the asked level */
    int n;         /* samples */
} bench_summary;

enum {
    BENCH_RESAMPLES = 10000, /* bootstrap resamples */
    BENCH_MAX_SAMPLES = 100000,
};

/* The median of x[0..n) (n >= 1; the mean of the middle two for even n). x
 * is left as it was. NAN for n < 1. */
double bench_median(const double *x, int n);

/* The median of x[0..n) and its percentile-bootstrap interval at `level`
 * (0.95 for 95%): BENCH_RESAMPLES resamples of n with replacement, their
 * medians sorted, the interval from the ceil(B (1 - level) / 2)-th to the
 * ceil(B (1 + level) / 2)-th of them. One sample: an interval of that
 * sample alone. Returns 0, or -1 (and *out all NAN, n 0) when n is outside
 * [1, BENCH_MAX_SAMPLES], a sample is not finite, level is outside (0, 1)
 * or memory runs out. */
int bench_summarize(const double *x, int n, double level, bench_summary *out);

/* How a summary reads on a page: "12.3 [11.9–12.8]" with `digits`
 * decimals; "–" for a summary of no samples. Returns buf. */
const char *bench_summary_text(const bench_summary *s, int digits, char *buf, unsigned long len);

/* The machine's 1-minute load average now (/proc/loadavg); NAN if unknown. */
double bench_load_average(void);

#endif
