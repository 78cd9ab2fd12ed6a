/* Tests of bench/imgdiff, the image error bench/keinert.sh reports: on
 * images made here with known differences, the shares it prints over all
 * pixels, the silhouettes and the far quarter are the ones counted by
 * hand; and bad input is one line and a non-zero exit. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>
#include <math.h>

#include "image_io.h"
#include "sdftrace/render.h"
#include "testutil.h"

static char out[4096];
enum { W = 10, H = 10 };
#define IMGDIFF SDFT_BUILD_DIR "/bench/imgdiff"

/* The reference: columns 0-4 miss (sky blue), 5-9 hit a grey surface at
 * depth 10 + y / 10, smooth enough (steps of 1%) that no two hits side by
 * side are 5% apart. Its silhouettes are columns 4 and 5 (20 pixels); its
 * far quarter is the hit depths from the 38th of 50 up: rows 7-9 of the
 * hit columns (15 pixels). */
static void make_reference(sdft_image *im)
{
    char msg[256];
    assert_int_equal(sdft_image_alloc(im, W, H, msg, sizeof msg), SDFT_OK);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const int i = y * W + x;
            const int hit = x >= 5;
            im->depth[i] = hit ? 10.0f + 0.1f * (float)y : INFINITY;
            im->rgb[3 * i + 0] = hit ? 0.5f : 0.3f;
            im->rgb[3 * i + 1] = hit ? 0.5f : 0.5f;
            im->rgb[3 * i + 2] = hit ? 0.5f : 0.9f;
        }
}

static void write(const char *name, const sdft_image *im, char *path, size_t len)
{
    char msg[256];
    tu_tmp(path, len, name);
    if (io_write_exr(path, im, msg, sizeof msg))
        fail_msg("%s", msg);
}

static void test_shares_counted_by_hand(void **state)
{
    (void)state;
    sdft_image ref, im;
    make_reference(&ref);
    make_reference(&im);
    /* Seven pixels changed by a lot: two on the silhouette (column 4 and 5),
     * three in the far rows, two elsewhere; five by less than 16/255. */
    static const int big[7][2] = {{4, 0}, {5, 1}, {6, 7}, {9, 8}, {8, 9}, {0, 0}, {7, 3}};
    for (int k = 0; k < 7; k++)
        im.rgb[3 * (big[k][1] * W + big[k][0]) + 1] = 0.0f;
    static const int small[5][2] = {{1, 1}, {6, 6}, {5, 9}, {9, 9}, {2, 5}};
    for (int k = 0; k < 5; k++)
        im.rgb[3 * (small[k][1] * W + small[k][0]) + 2] += 0.05f; /* 6 to 8 levels of 255 in sRGB */
    char a[512], b[512];
    write("imgdiff-reference.exr", &ref, a, sizeof a);
    write("imgdiff-image.exr", &im, b, sizeof b);
    assert_int_equal(tu_run(out, sizeof out, "%s --regions %s %s %s", IMGDIFF, a, b, a), 0);
    double all, sil, far, all2, sil2, far2;
    long n, nsil, nfar;
    assert_int_equal(sscanf(out, "%lf %lf %lf %lf %lf %lf pixels %ld %ld %ld", &all, &sil, &far, &all2, &sil2, &far2,
                            &n, &nsil, &nfar),
                     9);
    assert_int_equal(n, W * H);
    assert_int_equal(nsil, 20);
    assert_int_equal(nfar, 15);
    assert_float_equal(all, 7.0 / 100.0, 1e-6);
    assert_float_equal(sil, 2.0 / 20.0, 1e-6);
    assert_float_equal(far, 3.0 / 15.0, 1e-6);
    assert_true(all2 == 0.0 && sil2 == 0.0 && far2 == 0.0); /* the reference against itself */
    /* With a threshold of 3 levels the five small changes count too. */
    assert_int_equal(tu_run(out, sizeof out, "%s --threshold 3 %s %s", IMGDIFF, a, b), 0);
    assert_int_equal(sscanf(out, "%lf", &all), 1);
    assert_float_equal(all, 12.0 / 100.0, 1e-6);
    sdft_image_free(&ref);
    sdft_image_free(&im);
}

static void test_bad_input(void **state)
{
    (void)state;
    char a[512], small[512];
    sdft_image ref, tiny;
    char msg[256];
    make_reference(&ref);
    write("imgdiff-reference.exr", &ref, a, sizeof a);
    assert_int_equal(sdft_image_alloc(&tiny, 3, 2, msg, sizeof msg), SDFT_OK);
    write("imgdiff-small.exr", &tiny, small, sizeof small);
    static const char *const cases[] = {"", "--threshold 300 %s %s", "--bogus %s %s", "%s", "%s /no/such.exr", "%s %s"};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char args[1200];
        snprintf(args, sizeof args, cases[k], a, k == 5 ? small : a);
        const int rc = tu_run(out, sizeof out, "%s %s", IMGDIFF, args);
        if (rc == 0 || tu_lines(out) != 1)
            fail_msg("imgdiff %s: rc %d, '%s'", args, rc, out);
    }
    sdft_image_free(&ref);
    sdft_image_free(&tiny);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shares_counted_by_hand),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests_name("bench_imgdiff", tests, NULL, NULL);
}
