/* Bálint and Valasek's enhanced sphere tracing: Bán–Valasek Algorithm 3,
 * omega in (0, 1]. The next step makes the unbounding sphere at the guess
 * tangent to the current one under a planar model of f along the ray. */
#include "march.h"

sdft_hit sdft_trace_enhanced(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)
{
    const float omega = p->omega;
    float t = ray->tnear, r = march_eval(f, s, ray, t); /* line 4 */
    float z = r;
    float t0 = t, r0 = r;
    uint32_t i = 1, fallbacks = 0;
    march_candidate best = {t, r, INFINITY};
    march_offer(&best, p, t, r);

    while (march_on(p, ray, t, r, i)) {                /* line 5 */
        float T = t + z, R = march_eval(f, s, ray, T); /* line 6 */
        if (z <= r + fabsf(R)) {                       /* line 7 */
            /* line 8; the denominator lies in [0, 2z] for a 1-Lipschitz f
             * and is kept off zero for rays leaving a surface head-on. */
            float denominator = sdft_maxf(T - t - (R - r), 1e-6f * (T - t));
            z = R + omega * R * (T - t + R - r) / denominator;
            t0 = t, r0 = r;
            t = T, r = R; /* line 9 */
            march_offer(&best, p, t, r);
        } else {
            z = r; /* line 11 */
            fallbacks++;
        }
        i = i + 1; /* line 13 */
    }
    return march_finish(f, s, ray, p, t0, r0, t, r, i, fallbacks, best);
}
