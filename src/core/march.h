/* sdftrace — what the four tracing variants share: evaluating f along the
 * ray, the termination rule, the screen-space candidate, hit refinement.
 * Internal header. */
#ifndef SDFTRACE_MARCH_H
#define SDFTRACE_MARCH_H

#include <math.h>

#include "sdftrace/trace.h"

/* F(t) = f(o + t d): the field along the ray. */
static inline float march_eval(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, float t)
{
    return f->distance(f->ctx, s, sdft_madd(ray->org, ray->dir, t));
}

/* eps(t) = eps + pixel_radius * t: a constant radius, Keinert's screen-space
 * radius, or both. One expression, so the loops do not branch on it. */
static inline float march_eps(const sdft_trace_params *p, float t) { return p->eps + p->pixel_radius * t; }

/* The shared loop condition: r > eps(t), t + r < t_max, i < i_max. */
static inline int march_on(const sdft_trace_params *p, const sdft_ray *ray, float t, float r, uint32_t i)
{
    return r > march_eps(p, t) && t + r < ray->tfar && i < p->max_steps;
}

/* Keinert §3.2: the accepted point with the smallest error r / eps(t). */
typedef struct march_candidate {
    float t, r, error;
} march_candidate;

static inline void march_offer(march_candidate *c, const sdft_trace_params *p, float t, float r)
{
    float error = r / sdft_maxf(march_eps(p, t), 1e-30f);
    if (error < c->error)
        *c = (march_candidate){t, r, error};
}

/* Turns the final state of a march into a hit: classifies it, refines a hit
 * onto the surface from the last two accepted samples (t0, r0), (t, r), and
 * on non-convergence with the screen-space criterion returns the candidate. */
sdft_hit march_finish(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p,
                      float t0, float r0, float t, float r, uint32_t steps, uint32_t fallbacks,
                      march_candidate best);

#endif
