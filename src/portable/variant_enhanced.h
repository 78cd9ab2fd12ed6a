/* Bálint and Valasek's enhanced sphere tracing: Bán–Valasek Algorithm 3,
 * omega in (0, 1]. The next step makes the unbounding sphere at the guess
 * tangent to the current one under a planar model of f along the ray.
 * Portable (portable.h); the loop is march_loop.h's. */
#ifndef SDFTRACE_VARIANT_ENHANCED_H
#define SDFTRACE_VARIANT_ENHANCED_H

#include "march_state.h"

/* line 4: r := f(t), z := r */
PORT_INLINE void enhanced_start(PORT_INOUT(march_state) m, sdft_trace_params p)
{
    PORT_UNUSED(p);
    PORT_DEREF(m).z = PORT_DEREF(m).r;
}

/* lines 6-11, given R = f(T) at the trial point T = t + z */
PORT_INLINE void enhanced_step(PORT_INOUT(march_state) m, float T, float R, sdft_trace_params p)
{
    const float t = PORT_DEREF(m).t, r = PORT_DEREF(m).r;
    if (PORT_DEREF(m).z <= r + fabsf(R)) { /* line 7 */
        /* line 8; the denominator lies in [0, 2z] for a 1-Lipschitz f
         * and is kept off zero for rays leaving a surface head-on. */
        float denominator = sdft_maxf(T - t - (R - r), 1e-6f * (T - t));
        PORT_DEREF(m).z = R + p.omega * R * (T - t + R - r) / denominator;
        march_accept(m, p, T, R); /* line 9 */
    } else {
        PORT_DEREF(m).z = r; /* line 11 */
        PORT_DEREF(m).fallbacks++;
    }
}

#endif
