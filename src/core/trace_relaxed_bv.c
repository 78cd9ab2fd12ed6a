/* Over-relaxed sphere tracing as Bán and Valasek write it: their
 * Algorithm 2, omega in [1, 2). After a failed step it takes one basic step
 * and relaxes again (line 8 on the next accepted point): relaxation is
 * re-enabled after every fallback. Keinert et al.'s own Listing 2, which
 * keeps omega = 1 for the rest of the ray, is trace_relaxed.c.
 *
 * The first iteration of Algorithm 2 (z = 0, r = 0) only evaluates f at t;
 * we do that before the loop, as Algorithms 3 and 4 do. The loop is
 * march_one's (march.h). */
#include "march.h"

/* line 4 and the first pass: r := f(t), z := omega r */
MARCH_VARIANT void relaxed_bv_start(march_state *m, const sdft_trace_params *p) { m->z = p->omega * m->r; }

/* lines 6-12, given R = f(T) at the trial point T = t + z */
MARCH_VARIANT void relaxed_bv_step(march_state *m, float T, float R, const sdft_trace_params *p)
{
    if (m->z <= m->r + fabsf(R)) { /* line 7: spheres overlap */
        m->z = p->omega * R;       /* line 8 */
        march_accept(m, p, T, R);  /* line 9 */
    } else {
        m->z = m->r; /* line 11: basic step */
        m->fallbacks++;
    }
}

sdft_hit sdft_trace_relaxed_bv(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)
{
    return march_one(f, s, ray, p, relaxed_bv_start, relaxed_bv_step);
}

void march_stream_relaxed_bv(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                             const sdft_trace_params *p)
{
    march_many(f, s, rays, hits, n, p, relaxed_bv_start, relaxed_bv_step);
}
