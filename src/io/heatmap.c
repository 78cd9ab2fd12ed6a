/* sdftrace io — false-colour maps of the per-pixel counts, as in
 * Bán–Valasek Fig. 1: green for few SDF evaluations (or fallbacks), through
 * yellow, to red for many; a legend bar with numeric ticks below the image,
 * drawn with a built-in 3x5 digit font. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image_io.h"
#include "png_write.h"

enum {
    LEGEND_H = 40, /* rows added below the image */
    MARGIN = 10,   /* left/right margin of the bar */
    BAR_Y = 6,     /* bar top, from the legend's top */
    BAR_H = 12,
    TICK_H = 4,
    GLYPH_SCALE = 2, /* font pixels per glyph cell */
    TICKS = 5,       /* 0, 1/4, 1/2, 3/4, 1 of the scale */
};

/* 3x5 digits, one row per 3 bits (MSB left), rows top to bottom. */
static const unsigned char DIGITS[10][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7},
};

void io_heatmap_colour(double value, double max, unsigned char rgb[3])
{
    double t = max > 0.0 ? value / max : 0.0;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    double r = t < 0.5 ? 2.0 * t : 1.0, g = t < 0.5 ? 1.0 : 2.0 * (1.0 - t);
    rgb[0] = (unsigned char)(255.0 * r + 0.5);
    rgb[1] = (unsigned char)(200.0 * g + 0.5);
    rgb[2] = 0;
}

typedef struct canvas {
    unsigned char *rgb;
    int width, height;
} canvas;

static void put(canvas *c, int x, int y, const unsigned char col[3])
{
    if (x < 0 || y < 0 || x >= c->width || y >= c->height)
        return;
    memcpy(c->rgb + 3 * ((size_t)y * (size_t)c->width + (size_t)x), col, 3);
}

/* Draws the decimal `value` with its centre at x, top at y (clamped inside). */
static void draw_number(canvas *c, unsigned long value, int x, int y, const unsigned char col[3])
{
    char text[24];
    int len = snprintf(text, sizeof text, "%lu", value);
    int advance = 4 * GLYPH_SCALE, text_w = len * advance - GLYPH_SCALE;
    int left = x - text_w / 2;
    if (left + text_w > c->width - 2)
        left = c->width - 2 - text_w;
    if (left < 0)
        left = 0;
    for (int i = 0; i < len; i++)
        for (int row = 0; row < 5; row++)
            for (int bit = 0; bit < 3; bit++)
                if (DIGITS[text[i] - '0'][row] & (4 >> bit))
                    for (int dy = 0; dy < GLYPH_SCALE; dy++)
                        for (int dx = 0; dx < GLYPH_SCALE; dx++)
                            put(c, left + i * advance + bit * GLYPH_SCALE + dx, y + row * GLYPH_SCALE + dy, col);
}

/* The scale's top: the largest count rounded up to a multiple of TICKS-1,
 * so every tick label is a whole number. */
static unsigned long heatmap_scale(const uint32_t *counts, size_t n)
{
    unsigned long max = 0;
    for (size_t i = 0; i < n; i++)
        max = counts[i] > max ? counts[i] : max;
    unsigned long q = TICKS - 1;
    return max == 0 ? q : (max + q - 1) / q * q;
}

static void draw_legend(canvas *c, int top, unsigned long scale)
{
    static const unsigned char BACKGROUND[3] = {38, 38, 38}, INK[3] = {235, 235, 235};
    for (int y = top; y < c->height; y++)
        for (int x = 0; x < c->width; x++)
            put(c, x, y, BACKGROUND);
    int x0 = c->width > 3 * MARGIN ? MARGIN : 0, x1 = c->width - 1 - x0;
    int span = x1 > x0 ? x1 - x0 : 1;
    for (int x = x0; x <= x1; x++) {
        unsigned char col[3];
        io_heatmap_colour((double)(x - x0), (double)span, col);
        for (int y = 0; y < BAR_H; y++)
            put(c, x, top + BAR_Y + y, col);
    }
    for (int k = 0; k < TICKS; k++) {
        int x = x0 + span * k / (TICKS - 1);
        for (int y = 0; y < TICK_H; y++)
            put(c, x, top + BAR_Y + BAR_H + y, INK);
        draw_number(c, (scale * (unsigned long)k + (TICKS - 1) / 2) / (TICKS - 1), x, top + BAR_Y + BAR_H + TICK_H + 2,
                    INK);
    }
}

int io_write_heatmap_into(atomic_file *to, const sdft_image *img, io_heatmap_kind kind, unsigned long max, char *msg,
                          size_t msg_len)
{
    const uint32_t *counts = kind == SDFT_HEATMAP_FALLBACKS ? img->fallbacks : img->steps;
    size_t n = (size_t)img->width * (size_t)img->height;
    canvas c = {.width = img->width, .height = img->height + LEGEND_H};
    c.rgb = malloc((size_t)3 * (size_t)c.width * (size_t)c.height);
    if (!c.rgb) {
        snprintf(msg, msg_len, "out of memory writing %s", to->path);
        return -1;
    }
    unsigned long scale = max ? max : heatmap_scale(counts, n);
    for (size_t i = 0; i < n; i++)
        io_heatmap_colour((double)counts[i], (double)scale, c.rgb + 3 * i);
    draw_legend(&c, img->height, scale);
    int rc = io_png_write_rgb8(to, c.rgb, c.width, c.height, 0, msg, msg_len);
    free(c.rgb);
    return rc;
}

typedef struct heatmap_job {
    const sdft_image *img;
    io_heatmap_kind kind;
    unsigned long max;
} heatmap_job;

static int heatmap_writer(atomic_file *to, const void *ctx, char *msg, size_t msg_len)
{
    const heatmap_job *job = ctx;
    return io_write_heatmap_into(to, job->img, job->kind, job->max, msg, msg_len);
}

int io_write_heatmap(const char *path, const sdft_image *img, io_heatmap_kind kind, unsigned long max, char *msg,
                     size_t msg_len)
{
    const heatmap_job job = {img, kind, max};
    return io_write_whole(path, heatmap_writer, &job, msg, msg_len);
}
