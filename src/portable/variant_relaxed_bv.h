/* Over-relaxed sphere tracing as Bán and Valasek write it: their
 * Algorithm 2, omega in [1, 2). After a failed step it takes one basic step
 * and relaxes again (line 8 on the next accepted point): relaxation is
 * re-enabled after every fallback. Keinert et al.'s own Listing 2, which
 * keeps omega = 1 for the rest of the ray, is variant_relaxed.h.
 *
 * The first iteration of Algorithm 2 (z = 0, r = 0) only evaluates f at t;
 * we do that before the loop, as Algorithms 3 and 4 do. Portable
 * (portable.h); the loop is march_loop.h's. */
#ifndef SDFTRACE_VARIANT_RELAXED_BV_H
#define SDFTRACE_VARIANT_RELAXED_BV_H

#include "march_state.h"

/* line 4 and the first pass: r := f(t), z := omega r */
PORT_INLINE void relaxed_bv_start(PORT_INOUT(march_state) m, sdft_trace_params p)
{
    PORT_DEREF(m).z = p.omega * PORT_DEREF(m).r;
}

/* lines 6-12, given R = f(T) at the trial point T = t + z */
PORT_INLINE void relaxed_bv_step(PORT_INOUT(march_state) m, float T, float R, sdft_trace_params p)
{
    if (PORT_DEREF(m).z <= PORT_DEREF(m).r + fabsf(R)) { /* line 7: spheres overlap */
        PORT_DEREF(m).z = p.omega * R;                   /* line 8 */
        march_accept(m, p, T, R);                        /* line 9 */
    } else {
        PORT_DEREF(m).z = PORT_DEREF(m).r; /* line 11: basic step */
        PORT_DEREF(m).fallbacks++;
    }
}

#endif
