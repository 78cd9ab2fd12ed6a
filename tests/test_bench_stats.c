/* sdftrace tests — the bench statistics (bench/stats.c, and the program
 * bench/stats over it): the median by hand, and the percentile-bootstrap
 * interval of the median against the exact distribution of a resample's
 * median, from binomial sums (independent of the resampling the code does):
 * for n odd, distinct samples x_(1) < ... < x_(n),
 *   P(median of a resample <= x_(j)) = sum_{i >= (n+1)/2} C(n, i) p^i (1 - p)^(n - i),  p = j / n,
 * and the interval's ends are the smallest x_(j) whose probability reaches
 * (1 - level) / 2 and (1 + level) / 2. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "stats.h"
#include "testutil.h"

static double binomial(int n, int k)
{
    double c = 1.0;
    for (int i = 1; i <= k; i++)
        c = c * (n - k + i) / i;
    return c;
}

/* P(median of n draws from {x_(1..n)} <= x_(j)), n odd. */
static double median_cdf(int n, int j)
{
    const double p = (double)j / n;
    double s = 0.0;
    for (int i = (n + 1) / 2; i <= n; i++)
        s += binomial(n, i) * pow(p, i) * pow(1.0 - p, n - i);
    return s;
}

/* The rank (1-based) of the smallest x_(j) with P(median <= x_(j)) >= q,
 * and the distance of q from the nearest such probability (how far the
 * resampling's estimate of it may stray before it picks another rank). */
static int exact_rank(int n, double q, double *margin)
{
    *margin = INFINITY;
    int rank = n;
    for (int j = n; j >= 1; j--) {
        const double c = median_cdf(n, j);
        *margin = fmin(*margin, fabs(c - q));
        if (c >= q)
            rank = j;
    }
    return rank;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void test_median_by_hand(void **state)
{
    (void)state;
    const double odd[] = {7.0, 1.0, 3.0, 9.0, 2.0}; /* sorted: 1 2 3 7 9 */
    assert_true(bench_median(odd, 5) == 3.0);
    const double even[] = {4.0, 10.0, 1.0, 6.0}; /* sorted: 1 4 6 10 */
    assert_true(bench_median(even, 4) == 5.0);
    assert_true(bench_median(odd, 1) == 7.0);
    assert_true(isnan(bench_median(odd, 0)));
    assert_true(odd[0] == 7.0 && odd[4] == 2.0); /* left as it was */
}

/* n = 5, 7 and 11 random samples, unsorted: the interval's ends are the
 * ranks the binomial sums give (5: the range; 7: the 2nd and 6th; 11: the
 * 3rd and 9th), and the median the middle one. */
static void test_interval_is_the_exact_bootstrap_ranks(void **state)
{
    (void)state;
    static const int ns[] = {5, 7, 11};
    static const int want_lo[] = {1, 2, 3}, want_hi[] = {5, 6, 9};
    tu_rng rng = tu_rng_seed(42);
    for (size_t k = 0; k < sizeof ns / sizeof ns[0]; k++) {
        const int n = ns[k];
        double x[16], sorted[16];
        for (int i = 0; i < n; i++)
            x[i] = sorted[i] = 100.0 + tu_uniform(&rng, 0.0f, 50.0f);
        qsort(sorted, (size_t)n, sizeof *sorted, cmp_double);
        double m_lo, m_hi;
        const int lo = exact_rank(n, 0.025, &m_lo), hi = exact_rank(n, 0.975, &m_hi);
        /* The binomial sums themselves, against the ranks worked out by hand. */
        assert_int_equal(lo, want_lo[k]);
        assert_int_equal(hi, want_hi[k]);
        /* 10000 resamples estimate a probability within about 0.002: these n
         * keep every one at least 0.01 from the thresholds. */
        assert_true(m_lo > 0.01 && m_hi > 0.01);
        bench_summary s;
        assert_int_equal(bench_summarize(x, n, 0.95, &s), 0);
        assert_int_equal(s.n, n);
        assert_true(s.median == sorted[n / 2]);
        if (s.lo != sorted[lo - 1] || s.hi != sorted[hi - 1])
            fail_msg("n = %d: interval [%g, %g], exact bootstrap [%g, %g] (ranks %d, %d)", n, s.lo, s.hi,
                     sorted[lo - 1], sorted[hi - 1], lo, hi);
    }
}

/* Two samples a < b, by hand: a resample's median is a with probability
 * 1/4, (a + b) / 2 with 1/2, b with 1/4. At level 0.6 (tails 0.2) the
 * interval is [a, b]; at level 0.4 (tails 0.3) it is the midpoint alone. */
static void test_even_samples_by_hand(void **state)
{
    (void)state;
    const double x[] = {30.0, 10.0};
    bench_summary s;
    assert_int_equal(bench_summarize(x, 2, 0.6, &s), 0);
    assert_true(s.median == 20.0 && s.lo == 10.0 && s.hi == 30.0);
    assert_int_equal(bench_summarize(x, 2, 0.4, &s), 0);
    assert_true(s.median == 20.0 && s.lo == 20.0 && s.hi == 20.0);
}

static void test_one_sample_and_bad_input(void **state)
{
    (void)state;
    const double one = 4.5, bad[] = {1.0, NAN, 3.0}, inf[] = {1.0, INFINITY};
    bench_summary s;
    assert_int_equal(bench_summarize(&one, 1, 0.95, &s), 0);
    assert_true(s.median == 4.5 && s.lo == 4.5 && s.hi == 4.5 && s.n == 1);
    assert_int_equal(bench_summarize(bad, 3, 0.95, &s), -1);
    assert_true(isnan(s.median) && s.n == 0);
    assert_int_equal(bench_summarize(inf, 2, 0.95, &s), -1);
    assert_int_equal(bench_summarize(&one, 0, 0.95, &s), -1);
    assert_int_equal(bench_summarize(&one, 1, 1.0, &s), -1);
    assert_int_equal(bench_summarize(&one, 1, 0.0, &s), -1);
    char text[64];
    assert_string_equal(bench_summary_text(&s, 1, text, sizeof text), "–");
    const double five[] = {12.14, 11.8, 12.6, 13.9, 12.0};
    assert_int_equal(bench_summarize(five, 5, 0.95, &s), 0);
    assert_string_equal(bench_summary_text(&s, 1, text, sizeof text), "12.1 [11.8–13.9]");
}

/* The program: the same numbers from standard input, pairs divided with
 * --ratio, and one line and exit 2 for what is not a sample. */
static void test_program(void **state)
{
    (void)state;
    static char out[4096];
    const char *stats = SDFT_BENCH_STATS;
    if (!*stats)
        skip();
    /* 7 samples: median 40, the exact bootstrap's 2nd and 6th. */
    assert_int_equal(tu_run(out, sizeof out, "printf '70 10 40 20 60 50 30\\n' | %s", stats), 0);
    assert_string_equal(out, "40 20 60 7\n");
    assert_int_equal(tu_run(out, sizeof out, "printf '70\\n10\\n40\\n20\\n60\\n50\\n30\\n' | %s --text 1", stats), 0);
    assert_string_equal(out, "40.0 [20.0–60.0]\n");
    /* Pairs A B: the samples 2, 3, 5, 0.5, 4; median 3, the range. */
    assert_int_equal(tu_run(out, sizeof out, "printf '4 2\\n9 3\\n10 2\\n1 2\\n8 2\\n' | %s --ratio", stats), 0);
    assert_string_equal(out, "3 0.5 5 5\n");
    static const char *const bad[] = {
        "printf '1 x 3\\n'",   "printf ''",       "printf '1 2 3\\n' | cat -",
        "printf '1\\n2 1\\n'", "printf '1 0\\n'", "printf 'nan\\n'",
    };
    static const char *const flags[] = {"", "", "--ratio", "--ratio", "--ratio", ""};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        const int rc = tu_run(out, sizeof out, "%s | %s %s 2>&1", bad[i], stats, flags[i]);
        if (rc != 2 || tu_lines(out) != 1)
            fail_msg("'%s | stats %s': rc %d, output '%s'", bad[i], flags[i], rc, out);
    }
    assert_int_equal(tu_run(out, sizeof out, "echo 1 | %s --level 1.5 2>&1", stats), 2);
    assert_int_equal(tu_lines(out), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_median_by_hand),
        cmocka_unit_test(test_interval_is_the_exact_bootstrap_ranks),
        cmocka_unit_test(test_even_samples_by_hand),
        cmocka_unit_test(test_one_sample_and_bad_input),
        cmocka_unit_test(test_program),
    };
    return cmocka_run_group_tests_name("bench_stats", tests, NULL, NULL);
}
