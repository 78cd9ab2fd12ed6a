/* Bán and Valasek's auto-relaxed sphere tracing: Algorithm 4, beta in (0, 1).
 * The slope m of f along the ray is tracked by exponential averaging, and
 * each step is the one that would make consecutive unbounding spheres tangent
 * on a surface of that slope. */
#include "march.h"

sdft_hit sdft_trace_auto(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)
{
    const float beta = p->beta;
    float t = ray->tnear, r = march_eval(f, s, ray, t); /* line 4 */
    float z = r, m = -1.0f;
    float t0 = t, r0 = r;
    uint32_t i = 1, fallbacks = 0;
    march_candidate best = {t, r, INFINITY};
    march_offer(&best, p, t, r);

    while (march_on(p, ray, t, r, i)) {                   /* line 5 */
        float T = t + z, R = march_eval(f, s, ray, T);    /* line 6 */
        if (z <= r + fabsf(R)) {                          /* line 7 */
            float M = (R - r) / sdft_maxf(T - t, 1e-30f); /* line 8 */
            m = (1.0f - beta) * m + beta * M;             /* line 9 */
            t0 = t, r0 = r;
            t = T, r = R; /* line 10 */
            march_offer(&best, p, t, r);
        } else {
            m = -1.0f; /* line 12 */
            fallbacks++;
        }
        /* line 14; m <= 1 for a 1-Lipschitz f, a grid's interpolant may exceed it slightly */
        z = 2.0f * r / sdft_maxf(1.0f - m, 1e-4f);
        i = i + 1; /* line 15 */
    }
    return march_finish(f, s, ray, p, t0, r0, t, r, i, fallbacks, best);
}
