/* sdftrace — the whole-image function: primary rays, normals, a hard shadow
 * ray to a point light traced with the same variant, Lambert + ambient
 * shading, and per-pixel counts. OpenMP over tiles; the result is the same
 * for any thread count. The library never prints. */
#ifndef SDFTRACE_RENDER_H
#define SDFTRACE_RENDER_H

#include <stdint.h>

#include "camera.h"
#include "trace.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sdft_render_params {
    sdft_trace_params trace; /* used for primary and shadow rays alike */
    int width, height;       /* pixels, >= 1 */
    sdft_camera camera;
    sdft_vec3 light;         /* point light, world units */
    int shadows;             /* 1: trace a hard shadow ray per hit */
    int screen_space;        /* 1: Keinert's criterion, pixel_radius from the camera */
    int cones;               /* 1: primary rays first march together, per 16x16 tile and 4x4 block, as cones
                              * (sdft_cone_march); each ray's trace starts where its block's cone stopped */
    int depth_only;          /* 1: primary rays only, for depth, status and counts: no normal, shading or
                              * shadow ray (rgb and normal planes 0) */
    int threads;             /* 0: OpenMP's default */
} sdft_render_params;

/* One image's planes, row-major, y down; owned by the image
 * (sdft_image_alloc / sdft_image_free). */
typedef struct sdft_image {
    int width, height;
    float *rgb;          /* linear RGB, 3 floats per pixel */
    float *depth;        /* Z: ray parameter t of the primary hit (distance from the eye); INFINITY where nothing is hit */
    float *normal;       /* unit world-space normal, 3 floats per pixel; 0 where nothing is hit */
    uint32_t *steps;     /* SDF evaluations, primary + shadow ray (not the shared cones') */
    uint32_t *fallbacks; /* fallbacks, primary + shadow ray */
    uint8_t *status;     /* sdft_status of the primary ray */
} sdft_image;

typedef struct sdft_render_stats {
    double ms;             /* wall time of the trace, milliseconds */
    uint64_t rays;         /* primary + shadow rays */
    uint64_t primary_rays; /* width * height */
    uint64_t steps;        /* SDF evaluations over all rays (each ray's own trace) */
    uint64_t cone_steps;   /* SDF evaluations of the cones, shared by their rays (0 without cones) */
    uint64_t fallbacks;
    uint64_t hits;         /* primary rays that hit */
    uint64_t nonconverged; /* primary rays that did not converge */
} sdft_render_stats;

/* Defaults: sdft_trace_defaults(), 1280x720, shadows on, no screen-space,
 * cones on: the fastest settings that give the same picture.
 * sdft_render_papers turns cones and the exact root off. */
sdft_render_params sdft_render_defaults(void);

/* Switches p to the papers' way of counting (Bán–Valasek, Keinert et al.):
 * every primary ray traced on its own from the eye (no cones), stepping to
 * eps to the end (no exact root). The grid bench's `-papers` rows and the
 * method-by-method study use it. */
void sdft_render_papers(sdft_render_params *p);

int sdft_image_alloc(sdft_image *img, int width, int height); /* 0 on success */
void sdft_image_free(sdft_image *img);

/* Renders field f into img (already allocated at params' size). Returns 0,
 * or non-zero with a one-line reason in msg for bad parameters. */
int sdft_render(const sdft_field *f, const sdft_render_params *params, sdft_image *img,
                sdft_render_stats *stats, char *msg, unsigned msg_len);

#ifdef __cplusplus
}
#endif
#endif
