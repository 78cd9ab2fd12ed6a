/* sdftrace — the tracing variants.
 *
 * Four ways to find the first root of f(o + t d) along a ray, each a short
 * function that reads like its listing in the papers (../shared/seeds):
 *   SDFT_SPHERE   Hart's sphere tracing         (Bán–Valasek Algorithm 1)
 *   SDFT_RELAXED  Keinert et al. over-relaxed  (Algorithm 2, Keinert Listing 2), omega in [1, 2)
 *   SDFT_ENHANCED Bálint–Valasek enhanced       (Algorithm 3), omega in (0, 1]
 *   SDFT_AUTO     Bán–Valasek auto-relaxed      (Algorithm 4), beta in (0, 1)
 *
 * All four share one termination rule so their counts compare: with (t, r)
 * the accepted point and its distance, stop with a hit when r <= eps(t), a
 * miss when t + r >= tfar, and "not converged" after max_steps evaluations,
 * where eps(t) = eps + pixel_radius * t (pixel_radius = 0: a constant eps;
 * eps = 0, pixel_radius > 0: Keinert's screen-space criterion). */
#ifndef SDFTRACE_TRACE_H
#define SDFTRACE_TRACE_H

#include <stddef.h>
#include <stdint.h>

#include "field.h"

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
    SDFT_METHOD_COUNT
} sdft_method;

typedef enum sdft_status {
    SDFT_HIT = 0,
    SDFT_MISS,
    SDFT_NOT_CONVERGED
} sdft_status;

typedef struct sdft_trace_params {
    sdft_method method;
    float omega;        /* relaxed: [1, 2); enhanced: (0, 1] */
    float beta;         /* auto: (0, 1) */
    float eps;          /* absolute convergence radius, world units (>= 0) */
    float pixel_radius; /* screen-space criterion: half a pixel's footprint at t = 1; 0 = off */
    uint32_t max_steps; /* i_max: most SDF evaluations while marching (>= 1) */
    int exact_root;     /* 1: near the surface, the field's exact root (sdft_field.root, a grid's trilinear
                         * cell) instead of steps to eps, its reads counted; 0: every step to eps, as the
                         * papers count (fields without a root march so anyway) */
} sdft_trace_params;

/* What a trace found. */
typedef struct sdft_hit {
    float t;             /* hit: refined surface parameter; not converged: last point
                          * (or, with pixel_radius > 0, the best screen-space candidate);
                          * miss: the t where marching stopped */
    float distance;      /* f at t */
    sdft_status status;
    uint32_t steps;      /* SDF evaluations, refinement included */
    uint32_t fallbacks;  /* relaxed steps rejected: consecutive unbounding spheres disjoint */
} sdft_hit;

/* The defaults of the papers' measurements: auto, beta 0.3, 1000 steps,
 * omega 1.5 / 0.88 for relaxed / enhanced when chosen, eps 1e-4, no
 * screen-space; and the field's exact root where it has one (exact_root 1,
 * which the papers' way of counting turns off). */
sdft_trace_params sdft_trace_defaults(void);

/* Default omega of a method (relaxed 1.5, enhanced 0.88, else 1). */
float sdft_default_omega(sdft_method m);

/* Checks a parameter set; on error returns non-zero and writes one line to msg. */
int sdft_trace_params_check(const sdft_trace_params *p, char *msg, unsigned msg_len);

/* Traces one ray: clips it to the field's bounds, then runs the chosen
 * variant. Thread-safe given a per-thread scratch; allocates nothing. */
sdft_hit sdft_trace(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p);

/* Traces n rays: hits[k] is exactly what sdft_trace(f, s, &rays[k], p)
 * returns, same t and counts. Up to 4 rays march at once, interleaved, so
 * that one ray's memory loads overlap another's (Open VKL's stream entry
 * points, for a tracer): on a grid this is the faster way to trace a
 * block of rays. Thread-safe given a per-thread scratch; allocates nothing. */
void sdft_trace_stream(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                       const sdft_trace_params *p);

/* The variants themselves, on the unclipped ray [ray->tnear, ray->tfar]. */
sdft_hit sdft_trace_sphere(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p);
sdft_hit sdft_trace_relaxed(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p);
sdft_hit sdft_trace_enhanced(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p);
sdft_hit sdft_trace_auto(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p);

/* Cone marching, a pre-pass for a bundle of rays that leave one origin
 * (the primary rays through a block of pixels): with `axis` a unit vector
 * and `spread` >= |d - axis| for every ray's unit direction d, every ray's
 * point at parameter t lies within spread * t of the axis point, so all of
 * them may advance from t by f(axis point) - spread * t at once. Marches
 * the axis from tnear while the ball is much wider than the cone
 * (f > 1.25 spread t), at most 64 evaluations, and returns a t from which
 * every ray of the bundle may start its own trace: no surface lies on any
 * of them before it. Adds the evaluations to *steps. */
float sdft_cone_march(const sdft_field *f, sdft_scratch *s, sdft_vec3 org, sdft_vec3 axis, float spread, float tnear,
                      float tfar, uint32_t *steps);

/* "sphere" / "relaxed" / "enhanced" / "auto" and back; -1 if unknown. */
const char *sdft_method_name(sdft_method m);
int sdft_method_parse(const char *name);

#ifdef __cplusplus
}
#endif
#endif
