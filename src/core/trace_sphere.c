/* Hart's sphere tracing: Bán–Valasek Algorithm 1.
 *
 * Written in the while-form of Algorithms 3 and 4 (evaluate first, then loop
 * while r > eps, t + r < t_max, i < i_max), so that all four variants count
 * evaluations identically. The loop is march_one's (march.h). */
#include "march.h"

/* line 4: t := tnear, r := f(t); the step is r */
MARCH_VARIANT void sphere_start(march_state *m, const sdft_trace_params *p)
{
    (void)p;
    m->z = m->r;
}

/* lines 6-8, given R = f(T) at T = t + r */
MARCH_VARIANT void sphere_step(march_state *m, float T, float R, const sdft_trace_params *p)
{
    march_accept(m, p, T, R); /* line 7: t := t + r; line 6: r := f(t) */
    m->z = R;
}

sdft_hit sdft_trace_sphere(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)
{
    return march_one(f, s, ray, p, sphere_start, sphere_step);
}

void march_stream_sphere(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                         const sdft_trace_params *p)
{
    march_many(f, s, rays, hits, n, p, sphere_start, sphere_step);
}
