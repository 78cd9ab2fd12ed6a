/* sdftrace — the whole-image function: primary rays, normals, a hard shadow
 * ray to a point light traced with the same variant, Lambert + ambient
 * shading, and per-pixel counts. OpenMP over tiles; the result is the same
 * for any thread count. The library never prints. */
#ifndef SDFTRACE_RENDER_H
#define SDFTRACE_RENDER_H

#include <stdint.h>

#include "camera.h"
#include "sdftrace/config.h"
#include "sdftrace/error.h"
#include "trace.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most reflections, and most refractions, along one path (--bounces). */
#define SDFT_MAX_BOUNCES 16
/* Most discontinuity-reduction iterations per hit (--smooth-iters). */
#define SDFT_MAX_SMOOTH_ITERS 64

/* How to render. It will grow: make one with sdft_render_defaults() and set
 * the fields you change, never with an aggregate initializer alone. */
typedef struct sdft_render_params {
    sdft_trace_params trace; /* used for primary and shadow rays alike */
    int width, height;       /* pixels, >= 1 */
    sdft_camera camera;
    sdft_vec3 light;  /* point light, world units */
    int shadows;      /* 1: trace a hard shadow ray per hit */
    int screen_space; /* 1: Keinert's criterion, pixel_radius from the camera */
    int cones;        /* 1: primary rays skip the empty space together. A field with a hull (a
                       * grid: sdft_field_accel.hull) has each ray traced only over its span of the hull's
                       * boxes, found by ray-box tests, no evaluation; any other field's rays first
                       * march together, per 16x16 tile and 4x4 block, as cones (sdft_cone_march),
                       * each ray's trace starting where its block's cone stopped */
    int depth_only;   /* 1: primary rays only, for depth, status and counts: no normal, shading or
                       * shadow ray (rgb and normal planes 0) */
    int threads;      /* 0: OpenMP's default */
    /* Beyond one hard shadow ray (Keinert et al. 2014, the primer's shading).
     * Each is off by default, and with all of them off the picture is the one
     * above; any of them on, every hit is shaded by Whitted's rules with the
     * chosen variant tracing every secondary ray. */
    int materials;          /* 1: the field's materials (sdft_field.material; a field without: `material`),
                             * their reflections and refractions; 0: one grey opaque surface */
    sdft_material material; /* the one material of a field without materials (a grid); default grey, opaque */
    int reflect_bounces;    /* most mirror reflections along a path, [0, SDFT_MAX_BOUNCES]; default 2 */
    int refract_bounces;    /* most refractions along a path, [0, SDFT_MAX_BOUNCES]; default 8 */
    float eps_min;          /* Keinert 3.3: a secondary ray leaves hit p along the normal by 2 max(eps_min, |f(p)|),
                             * world units; 0: eps_min is the field's feature size (the normal's difference
                             * step), and |f(p)| carries how far the hit lies off the surface */
    int smooth_iters;       /* Keinert 3.4: fixed-point iterations onto f(p) = eps(t) per hit, [0, 64] */
    int convex;             /* Keinert 3.5: a ray that starts inside a convex part the field declares
                             * (sdft_field_accel.convex) leaves it from its bounding sphere's far side; default 1 */
    float soft_shadows;     /* k of the primer's penumbra min k d / t, > 0; 0: hard shadows */
    int ao;                 /* 1: ambient occlusion, five samples along the normal (the primer's) */
} sdft_render_params;

/* One image's planes, row-major, y down. The planes are owned by the image:
 * sdft_image_alloc allocates them, sdft_image_free releases them. */
typedef struct sdft_image {
    int width, height;
    float *rgb;      /* linear RGB, 3 floats per pixel */
    float *depth;    /* Z: ray parameter t of the primary hit (distance from the eye); INFINITY where nothing is hit */
    float *normal;   /* unit world-space normal, 3 floats per pixel; 0 where nothing is hit */
    uint32_t *steps; /* SDF evaluations, primary + shadow + secondary rays (not the shared cones') */
    uint32_t *fallbacks;     /* fallbacks, primary + shadow ray */
    uint32_t *primary_steps; /* SDF evaluations of the primary ray alone (Bán–Valasek Fig. 2) */
    uint8_t *status;         /* sdft_status of the primary ray (never SDFT_INVALID: sdft_render checks first) */
} sdft_image;

typedef struct sdft_render_stats {
    double ms;              /* wall time of the trace, milliseconds */
    uint64_t rays;          /* primary + shadow rays */
    uint64_t primary_rays;  /* width * height */
    uint64_t steps;         /* SDF evaluations over all rays (each ray's own trace) */
    uint64_t primary_steps; /* of them, the primary rays'; steps - primary_steps: the shadow rays' */
    uint64_t cone_steps;    /* SDF evaluations of the cones, shared by their rays (0 without cones) */
    uint64_t fallbacks;
    uint64_t primary_fallbacks;  /* of them, the primary rays' */
    uint64_t hits;               /* primary rays that hit */
    uint64_t nonconverged;       /* primary rays that did not converge */
    uint64_t shadow_steps;       /* of steps, the shadow rays' and the occlusion samples' */
    uint64_t secondary_rays;     /* reflection and refraction rays (not in rays) */
    uint64_t secondary_steps;    /* of steps, theirs: steps = primary + shadow + secondary */
    uint64_t dynamic_eps_hits;   /* hits shaded the Whitted way, each setting eps_dynamic for the rays it sends (3.3) */
    uint64_t dynamic_eps_from_f; /* of them, those where |f(p)| > eps_min decided it: the hit lay off the surface */
    uint64_t secondary_self_hits; /* secondary rays that hit within 2 eps_min of their origin: almost always their
                                   * own surface again, as when eps_min is below the trace's eps */
} sdft_render_stats;

/* Defaults: sdft_trace_defaults(), 1280x720, a camera at (0, 1, 5) looking
 * at the origin with a 45 degree field of view, a light at (5, 10, 5),
 * shadows on, no screen-space, depth and shading, all threads, and cones
 * on: the fastest settings that give the same picture; no materials,
 * smoothing, soft shadows or occlusion, the convex optimization on, 2
 * reflections and 8 refractions where materials are on. sdft_render_papers
 * turns cones and the exact root off. */
SDFT_API sdft_render_params sdft_render_defaults(void);

/* Switches p to the papers' way of counting (Bán–Valasek, Keinert et al.):
 * every primary ray traced on its own from the eye (no cones), stepping to
 * eps to the end (no exact root). The grid bench's `-papers` rows and the
 * method-by-method study use it. */
SDFT_API void sdft_render_papers(sdft_render_params *p);

/* Allocates every plane of a width x height image into *img (its old
 * contents are not freed). SDFT_OK; SDFT_EINVAL for a NULL img or a size
 * below 1 or too large; SDFT_ENOMEM. On failure *img is all zero. */
SDFT_API sdft_error sdft_image_alloc(sdft_image *img, int width, int height, char *msg, size_t msg_len);

/* Frees the planes and zeroes *img; an all-zero image (or NULL) is fine. */
SDFT_API void sdft_image_free(sdft_image *img);

/* Checks field f and params as sdft_render does, all but the image:
 * SDFT_OK, or SDFT_EINVAL with the reason (a NULL argument, the size, the
 * camera, the light, the threads, the shading's ranges, and
 * sdft_trace_params_check of the trace with the screen-space radius). For
 * a renderer that renders the same parameters elsewhere (sdftrace/gpu.h). */
SDFT_API sdft_error sdft_render_params_check(const sdft_field *f, const sdft_render_params *params, char *msg,
                                             size_t msg_len);

/* Renders field f into img, which must be allocated at params' size, with
 * a scratch per thread of its own (the caller's scratch is not used).
 * stats may be NULL. SDFT_OK; SDFT_EINVAL with the reason for a NULL
 * argument or a bad parameter (the image's size, the camera, the light,
 * sdft_trace_params_check, the shading's ranges above); SDFT_ENOMEM. */
SDFT_API sdft_error sdft_render(const sdft_field *f, const sdft_render_params *params, sdft_image *img,
                                sdft_render_stats *stats, char *msg, size_t msg_len);

#ifdef __cplusplus
}
#endif
#endif
