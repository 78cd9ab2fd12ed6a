/* Bálint and Valasek's enhanced sphere tracing: Bán–Valasek Algorithm 3,
 * omega in (0, 1]. The next step makes the unbounding sphere at the guess
 * tangent to the current one under a planar model of f along the ray. The
 * loop is march_one's (march.h). */
#include "march.h"

/* line 4: r := f(t), z := r */
MARCH_VARIANT void enhanced_start(march_state *m, const sdft_trace_params *p)
{
    (void)p;
    m->z = m->r;
}

/* lines 6-11, given R = f(T) at the trial point T = t + z */
MARCH_VARIANT void enhanced_step(march_state *m, float T, float R, const sdft_trace_params *p)
{
    const float t = m->t, r = m->r;
    if (m->z <= r + fabsf(R)) { /* line 7 */
        /* line 8; the denominator lies in [0, 2z] for a 1-Lipschitz f
         * and is kept off zero for rays leaving a surface head-on. */
        float denominator = sdft_maxf(T - t - (R - r), 1e-6f * (T - t));
        m->z = R + p->omega * R * (T - t + R - r) / denominator;
        march_accept(m, p, T, R); /* line 9 */
    } else {
        m->z = r; /* line 11 */
        m->fallbacks++;
    }
}

sdft_hit sdft_trace_enhanced(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)
{
    return march_one(f, s, ray, p, enhanced_start, enhanced_step);
}

void march_stream_enhanced(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                           const sdft_trace_params *p)
{
    march_many(f, s, rays, hits, n, p, enhanced_start, enhanced_step);
}
