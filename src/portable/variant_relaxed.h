/* Keinert et al.'s over-relaxed sphere tracing: Listing 2 of "Enhanced
 * sphere tracing" (2014, §3.1), omega in [1, 2). Lines are the listing's,
 * counted from its first comment line (`// o, d : ...` is line 1).
 *
 * Each step is omega f. When the unbounding spheres of two consecutive
 * points do not overlap (lines 17-18: |f(p_i)| + |f(p_i-1)| < stepLength),
 * the ray steps back by stepLength (1 - omega) from the failed point
 * (line 20), to t_i-1 + (2 - omega) stepLength = t_i-1 + omega (2 - omega)
 * f(p_i-1), inside the last unbounding sphere since omega (2 - omega) <= 1,
 * and omega is 1 for the rest of the ray (line 21): plain sphere tracing
 * from there on, never another fallback. Bán and Valasek's Algorithm 2,
 * which relaxes again after every fallback, is variant_relaxed_bv.h.
 *
 * In march_state terms the failed point is not accepted: (t, r) stays
 * p_i-1 and z = stepLength, so line 20's fallback point is t + (2 - omega) z.
 * Line 12's functionSign is the caller's (secondary_inside.c negates f for
 * rays that start inside), and lines 27-35 are the shared termination and
 * screen-space candidate (march_loop.h), offered accepted points only, as
 * line 29's !sorFail has it. Portable (portable.h). */
#ifndef SDFTRACE_VARIANT_RELAXED_H
#define SDFTRACE_VARIANT_RELAXED_H

#include "march_state.h"

/* lines 6-12 and the first pass of the loop: r := f(t), stepLength := omega r (line 23) */
PORT_INLINE void relaxed_start(PORT_INOUT(march_state) m, sdft_trace_params p)
{
    PORT_UNUSED(p);
    PORT_DEREF(m).z = PORT_DEREF(m).omega * PORT_DEREF(m).r;
}

/* lines 14-24, given R = f(T) at the trial point T = t + z */
PORT_INLINE void relaxed_step(PORT_INOUT(march_state) m, float T, float R, sdft_trace_params p)
{
    if (PORT_DEREF(m).omega > 1.0f && PORT_DEREF(m).r + fabsf(R) < PORT_DEREF(m).z) { /* lines 17-18: sorFail */
        PORT_DEREF(m).z *= 2.0f - PORT_DEREF(m).omega; /* line 20: back by stepLength (1 - omega) from T */
        PORT_DEREF(m).omega = 1.0f;                    /* line 21 */
        PORT_DEREF(m).fallbacks++;
    } else {
        PORT_DEREF(m).z = PORT_DEREF(m).omega * R; /* line 23 */
        march_accept(m, p, T, R);
    }
}

#endif
