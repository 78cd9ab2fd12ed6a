/* Keinert et al.'s over-relaxed sphere tracing: Bán–Valasek Algorithm 2
 * (Keinert et al. 2014, §3.1 and Listing 2), omega in [1, 2).
 *
 * The first iteration of Algorithm 2 (z = 0, r = 0) only evaluates f at t;
 * we do that before the loop, as Algorithms 3 and 4 do. */
#include "march.h"

sdft_hit sdft_trace_relaxed(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)
{
    const float omega = p->omega;
    float t = ray->tnear, r = march_eval(f, s, ray, t); /* line 4 and the first pass */
    float z = omega * r;
    float t0 = t, r0 = r;
    uint32_t i = 1, fallbacks = 0;
    march_candidate best = {t, r, INFINITY};
    march_offer(&best, p, t, r);

    while (march_on(p, ray, t, r, i)) {                /* line 14 */
        float T = t + z, R = march_eval(f, s, ray, T); /* line 6: try the step */
        if (z <= r + fabsf(R)) {                       /* line 7: spheres overlap */
            z = omega * R;                             /* line 8 */
            t0 = t, r0 = r;
            t = T, r = R; /* line 9 */
            march_offer(&best, p, t, r);
        } else {
            z = r; /* line 11: basic step */
            fallbacks++;
        }
        i = i + 1; /* line 13 */
    }
    return march_finish(f, s, ray, p, t0, r0, t, r, i, fallbacks, best);
}
