/* sdftrace — termination, refinement and the screen-space candidate,
 * shared by every tracing variant. */
#include "march.h"

enum { REFINE_STEPS = 3 };

/* Secant steps towards F(t) = 0 through the last two samples, until the
 * step the secant asks for is under a tenth of eps(t): the root is then
 * known to that accuracy, and evaluating there would only confirm it (at
 * the papers' distances and eps, t's own float resolution is a hundredth of
 * eps). Each step is clamped to what the unbounding spheres allow: ahead of
 * a point outside (r > 0) the root is no nearer than r, since |F'| <= 1,
 * and we step at most 32 r, so a grazing hit (slope down to 1/32) still
 * lands on the surface while the step stays within a few eps; behind a
 * point inside (r < 0) the root is at least |r| back and no farther back
 * than the last outside sample. A step that does not bring |F| down is
 * discarded. */
static void refine(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p, float t0,
                   float r0, float *t, float *r, uint32_t *steps)
{
    for (int k = 0; k < REFINE_STEPS; k++) {
        float t1 = *t, r1 = *r;
        float dt = (r1 != r0) ? -r1 * (t1 - t0) / (r1 - r0) : r1;
        if (!isfinite(dt))
            dt = r1;
        if (r1 > 0.0f)
            dt = sdft_minf(sdft_maxf(dt, r1), 32.0f * r1);
        else
            dt = (r0 > 0.0f && t0 < t1) ? sdft_minf(sdft_maxf(dt, t0 - t1), r1) : r1;
        if (!(fabsf(dt) > 0.1f * march_eps(p, t1)))
            break;
        float tn = t1 + dt, rn = march_eval(f, s, ray, tn);
        (*steps)++;
        if (!(fabsf(rn) < fabsf(r1)))
            break;
        t0 = t1, r0 = r1;
        *t = tn, *r = rn;
    }
}

sdft_hit march_finish(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p, float t0,
                      float r0, float t, float r, uint32_t steps, uint32_t fallbacks, march_candidate best)
{
    sdft_hit hit = {.t = t, .distance = r, .steps = steps, .fallbacks = fallbacks};
    if (r <= march_eps(p, t)) {
        hit.status = SDFT_HIT;
        /* A field with an exact root gives the hit itself, from the last
         * point known outside (a step may have landed inside). */
        const float from = r > 0.0f ? t : t0;
        float at;
        const sdft_field_accel *a = f->accel;
        if (p->exact_root && a && a->root && (r > 0.0f || (r0 > 0.0f && t0 < t))) {
            if (a->root(a->ctx, s, ray->org, ray->dir, from, ray->tfar, &at, &hit.normal, &hit.steps)) {
                hit.t = at, hit.distance = 0.0f;
                return hit;
            }
            /* Within eps of the surface, but it proved there is no root
             * before the ray's end: the ray passes the surface by (whether
             * a march lands within eps of it there depends on where the
             * march started; the root does not). */
            if (at >= ray->tfar) {
                hit.status = SDFT_MISS;
                return hit;
            }
        }
        refine(f, s, ray, p, t0, r0, &hit.t, &hit.distance, &hit.steps);
    } else if (t + r >= ray->tfar || !isfinite(r)) {
        hit.status = SDFT_MISS;
    } else {
        hit.status = SDFT_NOT_CONVERGED;
        if (p->pixel_radius > 0.0f)
            hit.t = best.t, hit.distance = best.r;
    }
    return hit;
}
