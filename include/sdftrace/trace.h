/* sdftrace — the tracing variants.
 *
 * Five ways to find the first root of f(o + t d) along a ray, each a short
 * function that reads like its listing in the papers (Bán and Valasek,
 * "Automatic step size relaxation in sphere tracing", 2023; Keinert et al.,
 * "Enhanced sphere tracing", 2014):
 *   SDFT_SPHERE      Hart's sphere tracing          (Bán–Valasek Algorithm 1)
 *   SDFT_RELAXED     Keinert et al. over-relaxed    (Keinert Listing 2), omega in [1, 2):
 *                    after the first fallback, omega = 1 for the rest of the ray
 *   SDFT_RELAXED_BV  over-relaxed as Bán–Valasek write it (Algorithm 2), omega in [1, 2):
 *                    relaxation resumes after every fallback
 *   SDFT_ENHANCED    Bálint–Valasek enhanced        (Algorithm 3), omega in (0, 1]
 *   SDFT_AUTO        Bán–Valasek auto-relaxed       (Algorithm 4), beta in (0, 1)
 *
 * All five share one termination rule so their counts compare: with (t, r)
 * the accepted point and its distance, stop with a hit when r <= eps(t), a
 * miss when t + r >= tfar, and "not converged" after max_steps evaluations,
 * where eps(t) = eps + pixel_radius * t (pixel_radius = 0: a constant eps;
 * eps = 0, pixel_radius > 0: Keinert's screen-space criterion). */
#ifndef SDFTRACE_TRACE_H
#define SDFTRACE_TRACE_H

#include <stddef.h>
#include <stdint.h>

#include "field.h"
#include "sdftrace/config.h"
#include "sdftrace/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A ray: plain data. `dir` must be unit length; t is in world units. */
typedef struct sdft_ray {
    sdft_vec3 org;
    float tnear;
    sdft_vec3 dir;
    float tfar;
} sdft_ray;

typedef enum sdft_method {
    SDFT_SPHERE = 0,
    SDFT_RELAXED,
    SDFT_ENHANCED,
    SDFT_AUTO,
    SDFT_RELAXED_BV,
    SDFT_METHOD_COUNT
} sdft_method;

typedef enum sdft_status {
    SDFT_HIT = 0,
    SDFT_MISS,
    SDFT_NOT_CONVERGED,
    SDFT_INVALID /* refused, nothing traced: a NULL argument, an unknown method, or a
                  * scratch prepared for another field (sdft_trace_check says which) */
} sdft_status;

/* How to trace. It will grow: make one with sdft_trace_defaults() and set
 * the fields you change, never with an aggregate initializer alone, so that
 * a field added later gets its default. */
typedef struct sdft_trace_params {
    sdft_method method;
    float omega;        /* relaxed, relaxed-bv: [1, 2); enhanced: (0, 1] */
    float beta;         /* auto: (0, 1) */
    float eps;          /* absolute convergence radius, world units (>= 0) */
    float pixel_radius; /* screen-space criterion: half a pixel's footprint at t = 1; 0 = off */
    uint32_t max_steps; /* i_max: most SDF evaluations while marching (>= 1) */
    int exact_root;     /* 1: near the surface, the field's exact root (sdft_field_accel.root, a grid's trilinear
                         * cell) instead of steps to eps, its reads counted; 0: every step to eps, as the
                         * papers count (fields without a root march so anyway) */
} sdft_trace_params;

/* What a trace found. */
typedef struct sdft_hit {
    float t;        /* hit: refined surface parameter; not converged: last point
                     * (or, with pixel_radius > 0, the best screen-space candidate);
                     * miss: the t where marching stopped */
    float distance; /* f at t */
    sdft_status status;
    uint32_t steps;     /* SDF evaluations, refinement included */
    uint32_t fallbacks; /* relaxed steps rejected: consecutive unbounding spheres disjoint */
    sdft_vec3 normal;   /* hit at the field's exact root (exact_root, sdft_field_accel.root): the unit outward
                         * normal there, as the root gives it; otherwise (0, 0, 0), and
                         * sdft_field_normal gives one at the hit point */
} sdft_hit;

/* The defaults of the papers' measurements: auto, beta 0.3, eps 1e-4, 1000
 * steps, no screen-space, and omega 1; and the field's exact root where it
 * has one (exact_root 1, which the papers' way of counting turns off).
 * Omega is the relaxed and enhanced variants' only parameter and has no
 * value right for all: after choosing one of them, set omega =
 * sdft_default_omega(method) (1.5 or 0.88). */
SDFT_API sdft_trace_params sdft_trace_defaults(void);

/* Default omega of a method (relaxed and relaxed-bv 1.5, enhanced 0.88, else 1). */
SDFT_API float sdft_default_omega(sdft_method m);

/* Checks a parameter set: SDFT_OK, or SDFT_EINVAL with one line in msg (an
 * unknown method, omega or beta outside its variant's range, a negative or
 * NaN eps or pixel radius, both 0, max_steps 0). */
SDFT_API sdft_error sdft_trace_params_check(const sdft_trace_params *p, char *msg, size_t msg_len);

/* Everything sdft_trace would refuse (SDFT_INVALID), and the parameter
 * checks above: SDFT_OK, or SDFT_EINVAL with the reason. */
SDFT_API sdft_error sdft_trace_check(const sdft_field *f, const sdft_scratch *s, const sdft_trace_params *p, char *msg,
                                     size_t msg_len);

/* Traces one ray: clips it to the field's bounds, then runs the chosen
 * variant. Returns status SDFT_INVALID, having traced nothing, when an
 * argument is NULL, the method is unknown or s does not serve f
 * (sdft_scratch_serves); the other parameters are the caller's to check
 * once (sdft_trace_params_check). Thread-safe given a per-thread scratch;
 * allocates nothing; every pointer stays the caller's. */
SDFT_API sdft_hit sdft_trace(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p);

/* Traces n rays: hits[k] is exactly what sdft_trace(f, s, &rays[k], p)
 * returns, same t and counts (every hit SDFT_INVALID when sdft_trace
 * would refuse). Up to 16 rays march at once, interleaved, so that one
 * ray's memory loads overlap another's (Open VKL's stream entry points, for
 * a tracer): on a grid this is the faster way to trace a block of rays.
 * Thread-safe given a per-thread scratch; allocates nothing. */
SDFT_API void sdft_trace_stream(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                                const sdft_trace_params *p);

/* The variants themselves, on the unclipped ray [ray->tnear, ray->tfar],
 * unchecked: p->method is ignored, and s must serve f. */
SDFT_API sdft_hit sdft_trace_sphere(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray,
                                    const sdft_trace_params *p);
SDFT_API sdft_hit sdft_trace_relaxed(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray,
                                     const sdft_trace_params *p);
SDFT_API sdft_hit sdft_trace_relaxed_bv(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray,
                                        const sdft_trace_params *p);
SDFT_API sdft_hit sdft_trace_enhanced(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray,
                                      const sdft_trace_params *p);
SDFT_API sdft_hit sdft_trace_auto(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray,
                                  const sdft_trace_params *p);

/* Cone marching, a pre-pass for a bundle of rays that leave one origin
 * (the primary rays through a block of pixels): with `axis` a unit vector
 * and `spread` >= |d - axis| for every ray's unit direction d, every ray's
 * point at parameter t lies within spread * t of the axis point, so all of
 * them may advance from t by f(axis point) - spread * t at once. Marches
 * the axis from tnear while the ball is much wider than the cone
 * (f > 1.25 spread t), at most 64 evaluations, and returns a t from which
 * every ray of the bundle may start its own trace: no surface lies on any
 * of them before it. Adds the evaluations to *steps. Returns tnear, having
 * evaluated nothing, when an argument is NULL or s does not serve f. */
SDFT_API float sdft_cone_march(const sdft_field *f, sdft_scratch *s, sdft_vec3 org, sdft_vec3 axis, float spread,
                               float tnear, float tfar, uint32_t *steps);

/* "sphere", "relaxed", "enhanced", "auto" or "relaxed-bv"; "unknown" for any other value.
 * A static string. */
SDFT_API const char *sdft_method_name(sdft_method m);

/* The method called `name` into *out: SDFT_OK, or SDFT_EINVAL (an unknown
 * name, or a NULL argument) with one line in msg. */
SDFT_API sdft_error sdft_method_parse(const char *name, sdft_method *out, char *msg, size_t msg_len);

#ifdef __cplusplus
}
#endif
#endif
