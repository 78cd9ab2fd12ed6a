/* sdftrace — cone marching: one sphere-tracing march for a whole bundle of
 * primary rays, so that each ray's own trace starts near the surface
 * instead of at the eye.
 *
 * Rays o + t d_i with |d_i - a| <= c (a the axis, c the spread). At
 * parameter t the axis point p = o + t a holds r = f(p) <= the distance to
 * the surface. Every ray's point q_i(t') for t' in [t, t + r - c t] lies
 * within |q_i(t') - q_i(t)| + |q_i(t) - p| <= (t' - t) + c t <= r of p,
 * inside the empty ball: so every ray may advance by r - c t. The march
 * stops once that step is under a quarter of the cone's radius c t (the bundle is
 * too wide for the free space there; its rays go on one by one), at tfar,
 * or after MAX_CONE_STEPS evaluations. Plain sphere-tracing steps: this
 * pre-pass is the same for every variant. */
#include "sdftrace/trace.h"

enum { MAX_CONE_STEPS = 64 };

float sdft_cone_march(const sdft_field *f, sdft_scratch *s, sdft_vec3 org, sdft_vec3 axis, float spread, float tnear,
                      float tfar, uint32_t *steps)
{
    if (!f || !f->distance || !s || !steps || !sdft_scratch_serves(s, f))
        return tnear;
    float t = tnear;
    for (int i = 0; i < MAX_CONE_STEPS && t < tfar; i++) {
        const float r = f->distance(f->ctx, s, sdft_madd(org, axis, t));
        (*steps)++;
        const float step = r - spread * t;
        if (!(step > 0.25f * spread * t)) /* NaN stops too */
            break;
        t += step;
    }
    return t;
}
