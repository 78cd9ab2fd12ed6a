/* sdftrace — writing rendered images: OpenEXR (all planes), an sRGB PNG
 * preview, and a false-colour heatmap of the per-pixel counts.
 *
 * Every writer writes into a file reserved through src/common/atomic_file.h
 * (the _into forms: the caller's, one of a set written together, all or
 * none), or reserves, writes and renames its own (the forms that take a
 * path), so a failure never leaves a half-written file, and the file gets
 * the mode the umask gives. Each returns 0, or non-zero with a one-line
 * reason in msg. None of them prints. Internal to the tools (not
 * installed). */
#ifndef SDFTRACE_IMAGE_IO_H
#define SDFTRACE_IMAGE_IO_H

#include "atomic_file.h"
#include "sdftrace/render.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Scanline OpenEXR, ZIP compressed, through OpenEXRCore: R, G, B (float,
 * linear), Z (float: primary-ray t, inf on a miss), N.X, N.Y, N.Z (float),
 * steps and fallbacks (uint: primary + shadow ray), primary_steps (uint:
 * the primary ray's steps alone). */
int io_write_exr(const char *path, const sdft_image *img, char *msg, size_t msg_len);
int io_write_exr_into(atomic_file *to, const sdft_image *img, char *msg, size_t msg_len);

/* Reads channels names[0..n-1] of a scanline OpenEXR file as float planes
 * (row-major, top row first; half and float channels), allocated into
 * planes[] for the caller to free, and the data window's size. Returns 0,
 * or non-zero with one line in msg (missing file, not scanline, a channel
 * absent, a corrupt chunk) and every plane NULL. */
int io_read_exr_floats(const char *path, int n, const char *const names[], float *planes[], int *width, int *height,
                       char *msg, size_t msg_len);

/* A linear value, clamped to [0, 1], on the sRGB transfer curve in 8 bits:
 * what the PNG preview stores. */
unsigned char io_srgb8(float linear);

/* 8-bit sRGB PNG of the image's linear RGB, through libpng. */
int io_write_png(const char *path, const sdft_image *img, char *msg, size_t msg_len);
int io_write_png_into(atomic_file *to, const sdft_image *img, char *msg, size_t msg_len);

typedef enum io_heatmap_kind { SDFT_HEATMAP_STEPS = 0, SDFT_HEATMAP_FALLBACKS } io_heatmap_kind;

/* A PNG of the image's steps or fallbacks, green (low) to red (high) as in
 * Bán–Valasek Fig. 1, with a legend bar and numeric tick labels below. The
 * scale runs from 0 to `max` (counts above it are red), so that several maps
 * can share one; max 0 takes the largest count rounded up to a multiple of 4. */
int io_write_heatmap(const char *path, const sdft_image *img, io_heatmap_kind kind, unsigned long max, char *msg,
                     size_t msg_len);
int io_write_heatmap_into(atomic_file *to, const sdft_image *img, io_heatmap_kind kind, unsigned long max, char *msg,
                          size_t msg_len);

/* One file written whole: `path` reserved, `write(to, ctx, ...)` into it,
 * renamed into place (removed on a failure). The path forms above. */
typedef int (*io_writer)(atomic_file *to, const void *ctx, char *msg, size_t msg_len);
int io_write_whole(const char *path, io_writer write, const void *ctx, char *msg, size_t msg_len);

/* The colour of a count on the heatmap's scale [0, max]: 8-bit RGB. */
void io_heatmap_colour(double value, double max, unsigned char rgb[3]);

#ifdef __cplusplus
}
#endif
#endif
