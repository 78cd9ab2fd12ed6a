/* Bán and Valasek's auto-relaxed sphere tracing: Algorithm 4, beta in (0, 1).
 * The slope m of f along the ray is tracked by exponential averaging, and
 * each step is the one that would make consecutive unbounding spheres tangent
 * on a surface of that slope. The loop is march_one's (march.h). */
#include "march.h"

/* line 4: r := f(t), z := r, m := -1 */
MARCH_VARIANT void auto_start(march_state *m, const sdft_trace_params *p)
{
    (void)p;
    m->z = m->r, m->m = -1.0f;
}

/* lines 6-14, given R = f(T) at the trial point T = t + z */
MARCH_VARIANT void auto_step(march_state *m, float T, float R, const sdft_trace_params *p)
{
    const float beta = p->beta;
    if (m->z <= m->r + fabsf(R)) {                          /* line 7 */
        float M = (R - m->r) / sdft_maxf(T - m->t, 1e-30f); /* line 8 */
        m->m = (1.0f - beta) * m->m + beta * M;             /* line 9 */
        march_accept(m, p, T, R);                           /* line 10 */
    } else {
        m->m = -1.0f; /* line 12 */
        m->fallbacks++;
    }
    /* line 14; m <= 1 for a 1-Lipschitz f, a grid's interpolant may exceed it slightly */
    m->z = 2.0f * m->r / sdft_maxf(1.0f - m->m, 1e-4f);
}

sdft_hit sdft_trace_auto(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)
{
    return march_one(f, s, ray, p, auto_start, auto_step);
}

void march_stream_auto(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                       const sdft_trace_params *p)
{
    march_many(f, s, rays, hits, n, p, auto_start, auto_step);
}
