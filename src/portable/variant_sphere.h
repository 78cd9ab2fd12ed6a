/* Hart's sphere tracing: Bán–Valasek Algorithm 1.
 *
 * Written in the while-form of Algorithms 3 and 4 (evaluate first, then loop
 * while r > eps, t + r < t_max, i < i_max), so that all variants count
 * evaluations identically. Portable (portable.h); the loop is
 * march_loop.h's. */
#ifndef SDFTRACE_VARIANT_SPHERE_H
#define SDFTRACE_VARIANT_SPHERE_H

#include "march_state.h"

/* line 4: t := tnear, r := f(t); the step is r */
PORT_INLINE void sphere_start(PORT_INOUT(march_state) m, sdft_trace_params p)
{
    PORT_UNUSED(p);
    PORT_DEREF(m).z = PORT_DEREF(m).r;
}

/* lines 6-8, given R = f(T) at T = t + r */
PORT_INLINE void sphere_step(PORT_INOUT(march_state) m, float T, float R, sdft_trace_params p)
{
    march_accept(m, p, T, R); /* line 7: t := t + r; line 6: r := f(t) */
    PORT_DEREF(m).z = R;
}

#endif
