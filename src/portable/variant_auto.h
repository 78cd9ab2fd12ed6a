/* Bán and Valasek's auto-relaxed sphere tracing: Algorithm 4, beta in (0, 1).
 * The slope m of f along the ray is tracked by exponential averaging, and
 * each step is the one that would make consecutive unbounding spheres tangent
 * on a surface of that slope. Portable (portable.h); the loop is
 * march_loop.h's. */
#ifndef SDFTRACE_VARIANT_AUTO_H
#define SDFTRACE_VARIANT_AUTO_H

#include "march_state.h"

/* line 4: r := f(t), z := r, m := -1 */
PORT_INLINE void auto_start(PORT_INOUT(march_state) m, sdft_trace_params p)
{
    PORT_UNUSED(p);
    PORT_DEREF(m).z = PORT_DEREF(m).r;
    PORT_DEREF(m).m = -1.0f;
}

/* lines 6-14, given R = f(T) at the trial point T = t + z */
PORT_INLINE void auto_step(PORT_INOUT(march_state) m, float T, float R, sdft_trace_params p)
{
    const float beta = p.beta;
    if (PORT_DEREF(m).z <= PORT_DEREF(m).r + fabsf(R)) {                          /* line 7 */
        float M = (R - PORT_DEREF(m).r) / sdft_maxf(T - PORT_DEREF(m).t, 1e-30f); /* line 8 */
        PORT_DEREF(m).m = (1.0f - beta) * PORT_DEREF(m).m + beta * M;             /* line 9 */
        march_accept(m, p, T, R);                                                 /* line 10 */
    } else {
        PORT_DEREF(m).m = -1.0f; /* line 12 */
        PORT_DEREF(m).fallbacks++;
    }
    /* line 14; m <= 1 for a 1-Lipschitz f, a grid's interpolant may exceed it slightly */
    PORT_DEREF(m).z = 2.0f * PORT_DEREF(m).r / sdft_maxf(1.0f - PORT_DEREF(m).m, 1e-4f);
}

#endif
