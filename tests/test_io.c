/* sdftrace tests — image output: the EXR read back with OpenEXR's own
 * reader (OpenEXRCore), the PNG preview and heatmap read back with libpng,
 * and no file (half-written or temporary) left behind by a failed write. */
#define _POSIX_C_SOURCE 200809L /* mkfifo, fork, waitpid, kill */
#include <dirent.h>
#include <math.h>
#include <openexr.h>
#include <png.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

#include "image_io.h"
#include "testutil.h"

enum { W = 37, H = 21 }; /* more than one 16-line ZIP chunk, odd sizes */

/* An image whose every plane holds distinct, checkable values. */
static void fill_image(sdft_image *img)
{
    assert_int_equal(sdft_image_alloc(img, W, H, NULL, 0), 0);
    for (int i = 0; i < W * H; i++) {
        for (int k = 0; k < 3; k++) {
            img->rgb[3 * i + k] = 0.001f * (float)i + 0.25f * (float)k;
            img->normal[3 * i + k] = (k == 0) ? sinf((float)i) : (k == 1) ? cosf((float)i) : -0.5f;
        }
        img->depth[i] = (i % 7 == 0) ? INFINITY : 1.0f + 0.125f * (float)i;
        img->steps[i] = (uint32_t)(3 * i + 1);
        img->fallbacks[i] = (uint32_t)(i % 5);
        img->primary_steps[i] = (uint32_t)(2 * i);
        img->status[i] = (uint8_t)(i % 7 == 0 ? SDFT_MISS : SDFT_HIT);
    }
}

/* Reads every channel of a scanline EXR as 4-byte planes via OpenEXRCore. */
typedef struct exr_readback {
    int width, height, channels;
    char names[16][32];
    int types[16];
    unsigned char *planes[16]; /* width * height * 4 bytes each */
    exr_compression_t compression;
    exr_storage_t storage;
} exr_readback;

static void read_exr(const char *path, exr_readback *rb)
{
    memset(rb, 0, sizeof *rb);
    exr_context_t ctx = NULL;
    assert_int_equal(exr_start_read(&ctx, path, NULL), EXR_ERR_SUCCESS);
    assert_int_equal(exr_get_storage(ctx, 0, &rb->storage), EXR_ERR_SUCCESS);
    assert_int_equal(exr_get_compression(ctx, 0, &rb->compression), EXR_ERR_SUCCESS);
    exr_attr_box2i_t dw;
    assert_int_equal(exr_get_data_window(ctx, 0, &dw), EXR_ERR_SUCCESS);
    rb->width = dw.max.x - dw.min.x + 1, rb->height = dw.max.y - dw.min.y + 1;
    const exr_attr_chlist_t *chl = NULL;
    assert_int_equal(exr_get_channels(ctx, 0, &chl), EXR_ERR_SUCCESS);
    rb->channels = chl->num_channels;
    assert_true(rb->channels <= 16);
    for (int c = 0; c < rb->channels; c++) {
        snprintf(rb->names[c], sizeof rb->names[c], "%s", chl->entries[c].name.str);
        rb->types[c] = chl->entries[c].pixel_type;
        rb->planes[c] = calloc((size_t)rb->width * (size_t)rb->height, 4);
    }
    int lines = 0;
    assert_int_equal(exr_get_scanlines_per_chunk(ctx, 0, &lines), EXR_ERR_SUCCESS);
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int y = dw.min.y; y <= dw.max.y; y += lines) {
        exr_chunk_info_t chunk;
        assert_int_equal(exr_read_scanline_chunk_info(ctx, 0, y, &chunk), EXR_ERR_SUCCESS);
        if (started)
            assert_int_equal(exr_decoding_update(ctx, 0, &chunk, &dec), EXR_ERR_SUCCESS);
        else
            assert_int_equal(exr_decoding_initialize(ctx, 0, &chunk, &dec), EXR_ERR_SUCCESS);
        for (int k = 0; k < dec.channel_count; k++) {
            exr_coding_channel_info_t *ch = &dec.channels[k];
            for (int c = 0; c < rb->channels; c++) {
                if (strcmp(ch->channel_name, rb->names[c]) != 0)
                    continue;
                ch->user_bytes_per_element = 4;
                ch->user_data_type = ch->data_type;
                ch->user_pixel_stride = 4;
                ch->user_line_stride = 4 * rb->width;
                ch->decode_to_ptr = rb->planes[c] + (size_t)4 * (size_t)rb->width * (size_t)(y - dw.min.y);
            }
        }
        if (!started)
            assert_int_equal(exr_decoding_choose_default_routines(ctx, 0, &dec), EXR_ERR_SUCCESS);
        started = 1;
        assert_int_equal(exr_decoding_run(ctx, 0, &dec), EXR_ERR_SUCCESS);
    }
    exr_decoding_destroy(ctx, &dec);
    exr_finish(&ctx);
}

static const void *channel(const exr_readback *rb, const char *name, int type)
{
    for (int c = 0; c < rb->channels; c++)
        if (strcmp(rb->names[c], name) == 0) {
            assert_int_equal(rb->types[c], type);
            return rb->planes[c];
        }
    fail_msg("channel %s missing", name);
    return NULL;
}

static void test_exr_round_trip(void **state)
{
    (void)state;
    sdft_image img;
    fill_image(&img);
    char path[512], msg[256] = "";
    tu_tmp(path, sizeof path, "io_round_trip.exr");
    remove(path);
    assert_int_equal(io_write_exr(path, &img, msg, sizeof msg), 0);
    tu_assert_no_temporaries(SDFT_TEST_TMP, "io_round_trip.exr");

    exr_readback rb;
    read_exr(path, &rb);
    assert_int_equal(rb.width, W);
    assert_int_equal(rb.height, H);
    assert_int_equal(rb.channels, 10);
    assert_int_equal(rb.storage, EXR_STORAGE_SCANLINE);
    assert_int_equal(rb.compression, EXR_COMPRESSION_ZIP);
    const float *r = channel(&rb, "R", EXR_PIXEL_FLOAT), *g = channel(&rb, "G", EXR_PIXEL_FLOAT);
    const float *b = channel(&rb, "B", EXR_PIXEL_FLOAT), *z = channel(&rb, "Z", EXR_PIXEL_FLOAT);
    const float *nx = channel(&rb, "N.X", EXR_PIXEL_FLOAT), *ny = channel(&rb, "N.Y", EXR_PIXEL_FLOAT);
    const float *nz = channel(&rb, "N.Z", EXR_PIXEL_FLOAT);
    const uint32_t *steps = channel(&rb, "steps", EXR_PIXEL_UINT);
    const uint32_t *fallbacks = channel(&rb, "fallbacks", EXR_PIXEL_UINT);
    const uint32_t *primary_steps = channel(&rb, "primary_steps", EXR_PIXEL_UINT);
    for (int i = 0; i < W * H; i++) {
        /* Lossless: bit-exact floats and counts. */
        assert_true(r[i] == img.rgb[3 * i] && g[i] == img.rgb[3 * i + 1] && b[i] == img.rgb[3 * i + 2]);
        assert_true(nx[i] == img.normal[3 * i] && ny[i] == img.normal[3 * i + 1] && nz[i] == img.normal[3 * i + 2]);
        assert_true(z[i] == img.depth[i]);
        assert_int_equal(steps[i], 3 * i + 1);
        assert_int_equal(fallbacks[i], i % 5);
        assert_int_equal(primary_steps[i], 2 * i);
    }
    assert_true(isinf(z[0]));
    for (int c = 0; c < rb.channels; c++)
        free(rb.planes[c]);
    sdft_image_free(&img);
}

/* Reads a PNG into 8-bit RGB with libpng's simplified API. */
static unsigned char *read_png(const char *path, int *w, int *h)
{
    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    assert_true(png_image_begin_read_from_file(&pi, path));
    pi.format = PNG_FORMAT_RGB;
    unsigned char *buf = malloc(PNG_IMAGE_SIZE(pi));
    assert_true(png_image_finish_read(&pi, NULL, buf, 0, NULL));
    *w = (int)pi.width, *h = (int)pi.height;
    return buf;
}

/* io_read_exr_floats reads back chosen channels bit for bit, and fails
 * with one line, every plane NULL, on a missing file, a file that is not an
 * EXR, and a channel the file lacks. */
static void test_exr_read_floats(void **state)
{
    (void)state;
    sdft_image img;
    fill_image(&img);
    char path[512], other[512], msg[256] = "";
    tu_tmp(path, sizeof path, "io_read.exr");
    tu_tmp(other, sizeof other, "io_read.png");
    assert_int_equal(io_write_exr(path, &img, msg, sizeof msg), 0);
    assert_int_equal(io_write_png(other, &img, msg, sizeof msg), 0);
    static const char *const names[3] = {"Z", "N.Y", "R"};
    float *planes[3];
    int w = 0, h = 0;
    assert_int_equal(io_read_exr_floats(path, 3, names, planes, &w, &h, msg, sizeof msg), 0);
    assert_int_equal(w, W);
    assert_int_equal(h, H);
    for (int i = 0; i < W * H; i++) {
        assert_memory_equal(&planes[0][i], &img.depth[i], sizeof(float));
        assert_true(planes[1][i] == img.normal[3 * i + 1]);
        assert_true(planes[2][i] == img.rgb[3 * i]);
    }
    for (int c = 0; c < 3; c++)
        free(planes[c]);

    static const char *const absent[2] = {"R", "Q"};
    const struct {
        const char *path, *needle;
        int n;
        const char *const *names;
    } bad[] = {{SDFT_TEST_TMP "/no_such.exr", "no_such.exr", 3, names},
               {other, "io_read.png", 3, names},
               {path, "no channel 'Q'", 2, absent}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        msg[0] = 0;
        assert_int_not_equal(io_read_exr_floats(bad[k].path, bad[k].n, bad[k].names, planes, &w, &h, msg, sizeof msg),
                             0);
        print_message("%s\n", msg);
        assert_non_null(strstr(msg, bad[k].needle));
        assert_null(strchr(msg, '\n'));
        for (int c = 0; c < bad[k].n; c++)
            assert_null(planes[c]);
    }
    sdft_image_free(&img);
}

static void test_png_is_srgb(void **state)
{
    (void)state;
    sdft_image img;
    fill_image(&img);
    img.rgb[0] = 0.0f, img.rgb[1] = 0.5f, img.rgb[2] = 1.0f;
    img.rgb[3] = 0.0031308f, img.rgb[4] = 0.21586f, img.rgb[5] = 7.0f; /* -> sRGB 128/255 */
    char path[512], msg[256] = "";
    tu_tmp(path, sizeof path, "io_preview.png");
    assert_int_equal(io_write_png(path, &img, msg, sizeof msg), 0);
    int w, h;
    unsigned char *px = read_png(path, &w, &h);
    assert_int_equal(w, W);
    assert_int_equal(h, H);
    assert_int_equal(px[0], 0);
    assert_int_equal(px[1], 188); /* 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354 */
    assert_int_equal(px[2], 255);
    assert_int_equal(px[3], 10); /* 12.92 * 0.0031308 = 0.04045 */
    assert_int_equal(px[4], 128);
    assert_int_equal(px[5], 255); /* clamped */
    free(px);
    sdft_image_free(&img);
}

static void test_heatmap(void **state)
{
    (void)state;
    sdft_image img;
    fill_image(&img);
    char path[512], msg[256] = "";
    tu_tmp(path, sizeof path, "io_heat.png");
    assert_int_equal(io_write_heatmap(path, &img, SDFT_HEATMAP_STEPS, 0, msg, sizeof msg), 0);
    int w, h;
    unsigned char *px = read_png(path, &w, &h);
    assert_int_equal(w, W);
    assert_true(h > H); /* the legend below */
    /* steps run 1 .. 3*W*H-2; the scale's top is that rounded up to a multiple of 4. */
    unsigned long max = 3ul * W * H - 2, scale = (max + 3) / 4 * 4;
    for (int i = 0; i < W * H; i += 17) {
        unsigned char want[3];
        io_heatmap_colour((double)img.steps[i], (double)scale, want);
        assert_memory_equal(px + 3 * i, want, 3);
    }
    /* Few steps are green, many are red. */
    assert_true(px[1] > 150 && px[0] < 20);
    size_t last = (size_t)(W * H - 1);
    assert_true(px[3 * last] > 200 && px[3 * last + 1] < 30);
    free(px);

    assert_int_equal(io_write_heatmap(path, &img, SDFT_HEATMAP_FALLBACKS, 0, msg, sizeof msg), 0);
    px = read_png(path, &w, &h);
    unsigned char want[3];
    io_heatmap_colour(4.0, 4.0, want); /* fallbacks 0..4: scale 4 */
    assert_memory_equal(px + 3 * 4, want, 3);
    free(px);

    /* A fixed scale (--heatmap-max 40) draws exactly what the data's own
     * scale draws for the counts clamped at 40, whose largest is 40: the
     * same colours, larger counts red, and the same legend, ticks 0..40. */
    assert_int_equal(io_write_heatmap(path, &img, SDFT_HEATMAP_STEPS, 40, msg, sizeof msg), 0);
    unsigned char *fixed = read_png(path, &w, &h);
    assert_true(img.steps[W * H - 1] > 40);
    for (int i = 0; i < W * H; i++)
        img.steps[i] = img.steps[i] < 40 ? img.steps[i] : 40;
    assert_int_equal(io_write_heatmap(path, &img, SDFT_HEATMAP_STEPS, 0, msg, sizeof msg), 0);
    int w2, h2;
    px = read_png(path, &w2, &h2);
    assert_true(w2 == w && h2 == h);
    assert_memory_equal(fixed, px, 3 * (size_t)w * (size_t)h);
    free(fixed);
    free(px);
    sdft_image_free(&img);
}

static void test_colour_scale(void **state)
{
    (void)state;
    unsigned char lo[3], mid[3], hi[3], over[3];
    io_heatmap_colour(0, 10, lo);
    io_heatmap_colour(5, 10, mid);
    io_heatmap_colour(10, 10, hi);
    io_heatmap_colour(50, 10, over);
    assert_true(lo[0] == 0 && lo[1] > 150);     /* green */
    assert_true(mid[0] == 255 && mid[1] > 150); /* yellow */
    assert_true(hi[0] == 255 && hi[1] == 0);    /* red */
    assert_memory_equal(hi, over, 3);
}

/* A write that cannot finish leaves neither the target nor a temporary. */
static void test_failed_writes_leave_nothing(void **state)
{
    (void)state;
    sdft_image img;
    fill_image(&img);
    char msg[256] = "";
    const char *missing = SDFT_TEST_TMP "/no/such/folder/out.exr";
    assert_int_not_equal(io_write_exr(missing, &img, msg, sizeof msg), 0);
    assert_true(strlen(msg) > 0 && strchr(msg, '\n') == NULL);
    assert_false(tu_file_exists(missing));
    assert_int_not_equal(atomic_file_check_writable(missing, msg, sizeof msg), 0);
    assert_int_not_equal(io_write_png(SDFT_TEST_TMP "/no/such/out.png", &img, msg, sizeof msg), 0);
    assert_int_not_equal(io_write_heatmap(SDFT_TEST_TMP "/no/such/h.png", &img, 0, 0, msg, sizeof msg), 0);

    /* The target is a folder: refused before anything is written. */
    char dir[512];
    tu_tmp(dir, sizeof dir, "io_is_a_dir.exr");
    mkdir(dir, 0755);
    msg[0] = '\0';
    assert_int_not_equal(io_write_exr(dir, &img, msg, sizeof msg), 0);
    assert_true(strlen(msg) > 0);
    tu_assert_no_temporaries(SDFT_TEST_TMP, "io_is_a_dir.exr");
    assert_int_not_equal(io_write_png(dir, &img, msg, sizeof msg), 0);
    tu_assert_no_temporaries(SDFT_TEST_TMP, "io_is_a_dir.exr");

    char ok[512];
    assert_int_equal(atomic_file_check_writable(tu_tmp(ok, sizeof ok, "io_check.exr"), msg, sizeof msg), 0);
    assert_false(tu_file_exists(ok));
    tu_assert_no_temporaries(SDFT_TEST_TMP, "io_check.exr");
    sdft_image_free(&img);
}

/* A target that is a named pipe (as /dev/null is a device) is written in
 * place: renaming a temporary file onto it would replace it with a file. */
static void test_pipe_target_written_in_place(void **state)
{
    (void)state;
    char fifo[512], copy[512], msg[256] = "";
    tu_tmp(fifo, sizeof fifo, "io_fifo.png");
    tu_tmp(copy, sizeof copy, "io_fifo_copy.png");
    unlink(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    const pid_t reader = fork();
    assert_true(reader >= 0);
    if (reader == 0) { /* copies what comes through the pipe */
        FILE *in = fopen(fifo, "rb"), *out = fopen(copy, "wb");
        int c;
        while (in && out && (c = fgetc(in)) != EOF)
            fputc(c, out);
        _exit(in && out && fclose(out) == 0 ? 0 : 1);
    }
    sdft_image img;
    fill_image(&img);
    const int written = io_write_png(fifo, &img, msg, sizeof msg);
    struct stat st;
    const int still_a_pipe = stat(fifo, &st) == 0 && S_ISFIFO(st.st_mode);
    if (!still_a_pipe) /* nobody will open the pipe: the reader would wait forever */
        kill(reader, SIGKILL);
    int status = 0;
    assert_int_equal(waitpid(reader, &status, 0), reader);
    assert_int_equal(written, 0);
    assert_true(still_a_pipe);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    tu_assert_no_temporaries(SDFT_TEST_TMP, "io_fifo.png");
    int w, h;
    unsigned char *px = read_png(copy, &w, &h);
    assert_true(w == img.width && h == img.height);
    free(px);
    unlink(fifo);
    sdft_image_free(&img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exr_round_trip),
        cmocka_unit_test(test_exr_read_floats),
        cmocka_unit_test(test_png_is_srgb),
        cmocka_unit_test(test_heatmap),
        cmocka_unit_test(test_colour_scale),
        cmocka_unit_test(test_failed_writes_leave_nothing),
        cmocka_unit_test(test_pipe_target_written_in_place),
    };
    return cmocka_run_group_tests_name("io", tests, NULL, NULL);
}
