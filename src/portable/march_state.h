/* sdftrace — what the tracing variants share between iterations: the
 * termination rule, the screen-space candidate, and the state Algorithms
 * 1-4 keep. Portable (portable.h). */
#ifndef SDFTRACE_MARCH_STATE_H
#define SDFTRACE_MARCH_STATE_H

#include "portable.h"

/* eps(t) = eps + pixel_radius * t: a constant radius, Keinert's screen-space
 * radius, or both. One expression, so the loops do not branch on it. */
PORT_INLINE float march_eps(sdft_trace_params p, float t) { return p.eps + p.pixel_radius * t; }

/* The shared loop condition: r > eps(t), t + r < t_max, i < i_max. */
PORT_INLINE bool march_on(sdft_trace_params p, sdft_ray ray, float t, float r, uint32_t i)
{
    return r > march_eps(p, t) && t + r < ray.tfar && i < p.max_steps;
}

/* Keinert §3.2: the accepted point with the smallest error r / eps(t). */
struct march_candidate {
    float t, r, error;
};
PORT_TYPEDEF(march_candidate)

PORT_INLINE void march_offer(PORT_INOUT(march_candidate) c, sdft_trace_params p, float t, float r)
{
    float error = r / sdft_maxf(march_eps(p, t), 1e-30f);
    if (error < PORT_DEREF(c).error) {
        PORT_DEREF(c).t = t;
        PORT_DEREF(c).r = r;
        PORT_DEREF(c).error = error;
    }
}

/* What Algorithms 1-4 and Keinert's Listing 2 keep between iterations: the
 * accepted point (t, r), the step z to the next trial point T = t + z,
 * auto's slope m, the relaxation omega in force (Listing 2 drops it to 1 for
 * the rest of the ray), the point accepted before (t0, r0) for refinement,
 * the count i of evaluations, the fallbacks and the screen-space candidate;
 * and root_t, up to where the field's exact root was last asked for
 * (march_root). A variant changes it
 * in place (PORT_INOUT): where a march keeps many, in memory (march_many),
 * a copy in and out of each step would cost more than the step. */
struct march_state {
    float t, r, z, m, omega;
    float t0, r0;
    uint32_t i, fallbacks;
    march_candidate best;
    float root_t;
};
PORT_TYPEDEF(march_state)

/* Line 4's first evaluation: (t, r) = (t, f(t)), i = 1, omega as given;
 * the variant's start sets z (and m). */
PORT_INLINE void march_begin(PORT_OUT(march_state) m, sdft_trace_params p, float t, float r)
{
    PORT_DEREF(m).t = t;
    PORT_DEREF(m).r = r;
    PORT_DEREF(m).z = 0.0f;
    PORT_DEREF(m).m = 0.0f;
    PORT_DEREF(m).omega = p.omega;
    PORT_DEREF(m).t0 = t;
    PORT_DEREF(m).r0 = r;
    PORT_DEREF(m).i = 1u;
    PORT_DEREF(m).fallbacks = 0u;
    PORT_DEREF(m).best.t = t;
    PORT_DEREF(m).best.r = r;
    PORT_DEREF(m).best.error = INFINITY;
    PORT_DEREF(m).root_t = -INFINITY;
    march_offer(PORT_REF(PORT_DEREF(m).best), p, t, r);
}

/* t := T, r := R, keeping the point before for refinement. */
PORT_INLINE void march_accept(PORT_INOUT(march_state) m, sdft_trace_params p, float T, float R)
{
    PORT_DEREF(m).t0 = PORT_DEREF(m).t;
    PORT_DEREF(m).r0 = PORT_DEREF(m).r;
    PORT_DEREF(m).t = T;
    PORT_DEREF(m).r = R;
    march_offer(PORT_REF(PORT_DEREF(m).best), p, T, R);
}

/* Marching resumes at t, r = f(t), after the field's root proved the ray
 * free up to t: like line 4 (the variant's start follows), but the counts,
 * the candidate and the omega in force go on; f(t) is one more evaluation. */
PORT_INLINE void march_restart(PORT_INOUT(march_state) m, sdft_trace_params p, float t, float r)
{
    march_accept(m, p, t, r);
    PORT_DEREF(m).i++;
}

/* A variant is two functions of the state (variant_*.h): `start`
 * completes line 4 once f(tnear) is in (t, r) (it sets z, and m for
 * auto); `step` is the body of the loop given R = f(T) at the trial point
 * T = t + z: it accepts or falls back and sets the next z. The loop
 * (march_loop.h) counts i. */

#endif
