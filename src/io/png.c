/* sdftrace io — 8-bit PNGs through libpng: the sRGB preview of a render,
 * and the shared writer the heatmap uses. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "atomic_file.h"
#include "image_io.h"
#include "png_write.h"

/* libpng reports errors by longjmp; keep its message for ours. */
typedef struct png_errors {
    char text[200];
} png_errors;

static void png_error_cb(png_structp png, png_const_charp text)
{
    png_errors *e = png_get_error_ptr(png);
    snprintf(e->text, sizeof e->text, "%s", text);
    png_longjmp(png, 1);
}

static void png_warning_cb(png_structp png, png_const_charp text)
{
    (void)png, (void)text; /* the library never prints */
}

/* Separate from the setjmp frame, so no local is clobbered by longjmp. */
static int png_encode(FILE *fp, const unsigned char *rgb, int width, int height, int srgb, png_errors *errors)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, errors, png_error_cb, png_warning_cb);
    if (!png)
        return -1;
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return -1;
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (srgb)
        png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    for (int y = 0; y < height; y++)
        png_write_row(png, rgb + (size_t)3 * (size_t)width * (size_t)y);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return 0;
}

int io_png_write_rgb8(atomic_file *to, const unsigned char *rgb, int width, int height, int srgb, char *msg,
                      size_t msg_len)
{
    /* A stream on a copy of the reserved file's descriptor: closing the
     * stream leaves the descriptor open for the commit. */
    const int fd = dup(to->fd);
    FILE *fp = fd >= 0 ? fdopen(fd, "wb") : NULL;
    if (!fp) {
        if (fd >= 0)
            close(fd);
        snprintf(msg, msg_len, "cannot write %s", to->path);
        return -1;
    }
    png_errors errors = {{0}};
    int rc = png_encode(fp, rgb, width, height, srgb, &errors);
    if (fclose(fp) != 0)
        rc = -1;
    if (rc != 0) {
        snprintf(msg, msg_len, "cannot write %s: %s", to->path, errors.text[0] ? errors.text : "write failed");
        return -1;
    }
    return 0;
}

int io_write_whole(const char *path, io_writer write, const void *ctx, char *msg, size_t msg_len)
{
    atomic_file af;
    if (atomic_file_begin(&af, path, msg, msg_len))
        return -1;
    if (write(&af, ctx, msg, msg_len)) {
        atomic_file_abort(&af);
        return -1;
    }
    return atomic_file_commit(&af, msg, msg_len) ? -1 : 0;
}

unsigned char io_srgb8(float linear)
{
    float c = fminf(fmaxf(linear, 0.0f), 1.0f);
    float s = c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f;
    return (unsigned char)(s * 255.0f + 0.5f);
}

int io_write_png_into(atomic_file *to, const sdft_image *img, char *msg, size_t msg_len)
{
    size_t n = (size_t)img->width * (size_t)img->height;
    unsigned char *rgb = malloc(3 * n);
    if (!rgb) {
        snprintf(msg, msg_len, "out of memory writing %s", to->path);
        return -1;
    }
    for (size_t i = 0; i < 3 * n; i++)
        rgb[i] = io_srgb8(img->rgb[i]);
    int rc = io_png_write_rgb8(to, rgb, img->width, img->height, 1, msg, msg_len);
    free(rgb);
    return rc;
}

static int png_writer(atomic_file *to, const void *img, char *msg, size_t msg_len)
{
    return io_write_png_into(to, img, msg, msg_len);
}

int io_write_png(const char *path, const sdft_image *img, char *msg, size_t msg_len)
{
    return io_write_whole(path, png_writer, img, msg, msg_len);
}
