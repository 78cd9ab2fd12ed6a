/* imgdiff — how far images are from a reference, as a viewer sees them:
 * the share of pixels whose 8-bit sRGB colour (the PNG preview's) differs
 * from the reference's by more than THRESHOLD levels in some channel, over
 * all pixels and over two regions of the reference:
 *   silhouettes  pixels whose 4-neighbourhood in the reference holds both a
 *                hit and a miss, or depths more than 5% apart;
 *   far          hit pixels at the farthest quarter of the reference's
 *                depths.
 * For the bench pages (bench/keinert.sh): one line per image,
 *   SHARE_ALL SHARE_SILHOUETTES SHARE_FAR
 * as fractions, then one line "pixels N SILHOUETTES FAR" for the regions'
 * sizes when --regions is given.
 *
 * usage: imgdiff [--threshold T] [--regions] REFERENCE.exr IMAGE.exr... */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image_io.h"

typedef struct image {
    float *rgb[3], *z;
    int width, height;
} image;

static const char *const CHANNELS[4] = {"R", "G", "B", "Z"};

static int load(const char *path, image *im)
{
    char msg[512];
    float *planes[4];
    if (io_read_exr_floats(path, 4, CHANNELS, planes, &im->width, &im->height, msg, sizeof msg)) {
        fprintf(stderr, "imgdiff: %s\n", msg);
        return -1;
    }
    for (int c = 0; c < 3; c++)
        im->rgb[c] = planes[c];
    im->z = planes[3];
    return 0;
}

static void release(image *im)
{
    for (int c = 0; c < 3; c++)
        free(im->rgb[c]);
    free(im->z);
}

static int cmp_float(const void *a, const void *b)
{
    const float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* 1 where pixels i and j of the reference lie across an edge of what it shows. */
static int edge(const image *r, size_t i, size_t j)
{
    const float a = r->z[i], b = r->z[j];
    if (isfinite(a) != isfinite(b))
        return 1;
    return isfinite(a) && fabsf(a - b) > 0.05f * fminf(a, b);
}

/* The regions of the reference: mask bit 1 silhouettes, bit 2 far. */
static unsigned char *regions(const image *r)
{
    const size_t n = (size_t)r->width * (size_t)r->height;
    unsigned char *mask = calloc(n, 1);
    float *depths = malloc(n * sizeof *depths);
    if (!mask || !depths) {
        free(mask), free(depths);
        return NULL;
    }
    size_t hits = 0;
    for (size_t i = 0; i < n; i++)
        if (isfinite(r->z[i]))
            depths[hits++] = r->z[i];
    qsort(depths, hits, sizeof *depths, cmp_float);
    const float far = hits ? depths[hits * 3 / 4] : INFINITY;
    free(depths);
    for (int y = 0; y < r->height; y++)
        for (int x = 0; x < r->width; x++) {
            const size_t i = (size_t)y * (size_t)r->width + (size_t)x;
            int e = 0;
            if (x > 0)
                e |= edge(r, i, i - 1);
            if (x + 1 < r->width)
                e |= edge(r, i, i + 1);
            if (y > 0)
                e |= edge(r, i, i - (size_t)r->width);
            if (y + 1 < r->height)
                e |= edge(r, i, i + (size_t)r->width);
            mask[i] = (unsigned char)(e | (isfinite(r->z[i]) && r->z[i] >= far ? 2 : 0));
        }
    return mask;
}

int main(int argc, char **argv)
{
    int threshold = 16, show_regions = 0, a = 1;
    for (; a < argc && argv[a][0] == '-'; a++) {
        if (!strcmp(argv[a], "--threshold") && a + 1 < argc) {
            char *end;
            threshold = (int)strtol(argv[++a], &end, 10);
            if (*end || threshold < 0 || threshold > 255) {
                fprintf(stderr, "imgdiff: --threshold takes 0..255, not '%s'\n", argv[a]);
                return 2;
            }
        } else if (!strcmp(argv[a], "--regions")) {
            show_regions = 1;
        } else {
            fprintf(stderr, "imgdiff: unknown option '%s' (usage: imgdiff [--threshold T] [--regions] REF IMAGE...)\n",
                    argv[a]);
            return 2;
        }
    }
    if (argc - a < 2) {
        fprintf(stderr, "usage: imgdiff [--threshold T] [--regions] REFERENCE.exr IMAGE.exr...\n");
        return 2;
    }
    image ref;
    if (load(argv[a], &ref))
        return 1;
    unsigned char *mask = regions(&ref);
    if (!mask) {
        fprintf(stderr, "imgdiff: out of memory\n");
        release(&ref);
        return 1;
    }
    const size_t n = (size_t)ref.width * (size_t)ref.height;
    size_t in[3] = {n, 0, 0};
    for (size_t i = 0; i < n; i++)
        in[1] += mask[i] & 1, in[2] += (mask[i] >> 1) & 1;
    int rc = 0;
    for (int k = a + 1; k < argc && !rc; k++) {
        image im;
        if (load(argv[k], &im)) {
            rc = 1;
            break;
        }
        if (im.width != ref.width || im.height != ref.height) {
            fprintf(stderr, "imgdiff: %s is %dx%d, the reference %dx%d\n", argv[k], im.width, im.height, ref.width,
                    ref.height);
            release(&im);
            rc = 1;
            break;
        }
        size_t changed[3] = {0, 0, 0};
        for (size_t i = 0; i < n; i++) {
            int d = 0;
            for (int c = 0; c < 3; c++) {
                const int e = abs((int)io_srgb8(im.rgb[c][i]) - (int)io_srgb8(ref.rgb[c][i]));
                d = e > d ? e : d;
            }
            if (d > threshold)
                changed[0]++, changed[1] += mask[i] & 1, changed[2] += (mask[i] >> 1) & 1;
        }
        printf("%.6f %.6f %.6f\n", (double)changed[0] / (double)n, in[1] ? (double)changed[1] / (double)in[1] : 0.0,
               in[2] ? (double)changed[2] / (double)in[2] : 0.0);
        release(&im);
    }
    if (show_regions && !rc)
        printf("pixels %zu %zu %zu\n", in[0], in[1], in[2]);
    free(mask);
    release(&ref);
    return rc;
}
