/* sdftrace render — the image's peak memory (render_memory.h).
 *
 * The peak comes while the EXR file is written: the image (sdft_image: RGB,
 * depth and normal floats, three uint32 counts and a status byte, 41 bytes
 * a pixel) and the writer's planes (R, G, B, N.X, N.Y, N.Z as floats, 24
 * bytes a pixel: src/io/exr.c), 65 bytes a pixel, on top of the process
 * with its libraries (about 34 MiB). Measured with /usr/bin/time's maximum
 * resident set: 1024x1024 and 2048x2048 renders within a few percent
 * (tests/test_untrusted.c). The grid's own memory comes on top. */
#include "render_memory.h"

#include <stdio.h>

#include "memory_limit.h"

static const double BASE_BYTES = 34.0 * 1024 * 1024;
static const double BYTES_PER_PIXEL = 41.0 + 24.0;

double render_peak_bytes(int width, int height)
{
    return BASE_BYTES + BYTES_PER_PIXEL * (double)width * (double)height;
}

int render_memory_check(int width, int height, char *msg, size_t len)
{
    char what[64];
    snprintf(what, sizeof what, "a %dx%d image", width, height);
    return memory_check(render_peak_bytes(width, height), what, msg, len);
}
