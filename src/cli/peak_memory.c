/* sdftrace — the peak memory of a render and of a dense bake
 * (peak_memory.h).
 *
 * RENDER. The peak comes while the EXR file is written: the image (sdft_image: RGB,
 * depth and normal floats, three uint32 counts and a status byte, 41 bytes
 * a pixel) and the writer's planes (R, G, B, N.X, N.Y, N.Z as floats, 24
 * bytes a pixel: src/io/exr.c), 65 bytes a pixel, on top of the process
 * with its libraries (about 34 MiB). Measured with /usr/bin/time's maximum
 * resident set: 1024x1024 and 2048x2048 renders within a few percent
 * (tests/test_untrusted.c). The grid's own memory comes on top.
 *
 * DENSE BAKE. Every voxel of the box in full leaves: 4.5 bytes a voxel
 * (values, masks, the tree), and 4.2 more for the NanoVDB copy a .nvdb
 * file is written from, on the same 34 MiB: a 512x123x512 dodecahedron
 * measured 175 MiB (.vdb) and 310 MiB (.nvdb), estimated 172 and 300. */
#include "peak_memory.h"

#include <math.h>
#include <stdio.h>

#include "memory_limit.h"

static const double BASE_BYTES = 34.0 * 1024 * 1024;
static const double BYTES_PER_PIXEL = 41.0 + 24.0;
static const double BYTES_PER_DENSE_VOXEL = 4.5, NANO_BYTES_PER_VOXEL = 4.2;

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

int bake_memory_check(const sdft_field *f, int res, int nvdb, char *msg, size_t len)
{
    /* The bake's box (src/vdb/bake.cpp): cubic voxels of the longest edge / res. */
    const double e[3] = {f->bounds.hi.x - f->bounds.lo.x, f->bounds.hi.y - f->bounds.lo.y,
                         f->bounds.hi.z - f->bounds.lo.z};
    const double h = fmax(e[0], fmax(e[1], e[2])) / res;
    double voxels = 1;
    for (int k = 0; k < 3; k++)
        voxels *= h > 0 ? fmin(fmax(ceil(e[k] / h - 1e-3), 1.0), res) : 1.0;
    char what[96];
    snprintf(what, sizeof what, "a dense bake of %.0f voxels", voxels);
    const double per_voxel = BYTES_PER_DENSE_VOXEL + (nvdb ? NANO_BYTES_PER_VOXEL : 0.0);
    return memory_check(BASE_BYTES + per_voxel * voxels, what, msg, len);
}
