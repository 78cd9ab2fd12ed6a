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
 * which relaxes again after every fallback, is trace_relaxed_bv.c.
 *
 * In march_state terms the failed point is not accepted: (t, r) stays
 * p_i-1 and z = stepLength, so line 20's fallback point is t + (2 - omega) z.
 * Line 12's functionSign is the caller's (secondary_inside.c negates f for
 * rays that start inside), and lines 27-35 are the shared termination and
 * screen-space candidate (march.h), offered accepted points only, as line
 * 29's !sorFail has it. The loop is march_one's (march.h). */
#include "march.h"

/* lines 6-12 and the first pass of the loop: r := f(t), stepLength := omega r (line 23) */
MARCH_VARIANT void relaxed_start(march_state *m, const sdft_trace_params *p)
{
    (void)p;
    m->z = m->omega * m->r;
}

/* lines 14-24, given R = f(T) at the trial point T = t + z */
MARCH_VARIANT void relaxed_step(march_state *m, float T, float R, const sdft_trace_params *p)
{
    if (m->omega > 1.0f && m->r + fabsf(R) < m->z) { /* lines 17-18: sorFail */
        m->z *= 2.0f - m->omega;                     /* line 20: back by stepLength (1 - omega) from T */
        m->omega = 1.0f;                             /* line 21 */
        m->fallbacks++;
    } else {
        m->z = m->omega * R; /* line 23 */
        march_accept(m, p, T, R);
    }
}

sdft_hit sdft_trace_relaxed(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)
{
    return march_one(f, s, ray, p, relaxed_start, relaxed_step);
}

void march_stream_relaxed(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                          const sdft_trace_params *p)
{
    march_many(f, s, rays, hits, n, p, relaxed_start, relaxed_step);
}
