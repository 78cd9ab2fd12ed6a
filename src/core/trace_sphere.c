/* Hart's sphere tracing: Bán–Valasek Algorithm 1.
 *
 * Written in the while-form of Algorithms 3 and 4 (evaluate first, then loop
 * while r > eps, t + r < t_max, i < i_max), so that all four variants count
 * evaluations identically. */
#include "march.h"

sdft_hit sdft_trace_sphere(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)
{
    float t = ray->tnear, r = march_eval(f, s, ray, t); /* line 4, 6 */
    float t0 = t, r0 = r;
    uint32_t i = 1;
    march_candidate best = {t, r, INFINITY};
    march_offer(&best, p, t, r);

    while (march_on(p, ray, t, r, i)) { /* line 9 */
        t0 = t, r0 = r;
        t = t + r;                    /* line 7 */
        r = march_eval(f, s, ray, t); /* line 6 */
        i = i + 1;                    /* line 8 */
        march_offer(&best, p, t, r);
    }
    return march_finish(f, s, ray, p, t0, r0, t, r, i, 0, best);
}
