/* Keinert et al. 3.4, discontinuity reduction: the hits sphere tracing
 * returns lie anywhere within eps(t) of the surface, and where that
 * distance jumps from pixel to pixel, so do texture and shading. A few
 * steps of the fixed-point iteration p := p + d (f(p) - err(|p - o|))
 * (Equation 3) move every hit towards the level set f(p) = err, the same
 * for neighbours. */
#include "secondary.h"

float secondary_smooth(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, float t, float f_at_t,
                       const sdft_trace_params *p, int iters, float *f_out, uint32_t *steps)
{
    float ft = f_at_t;
    for (int i = 0; i < iters; i++) {
        const float err = p->eps + p->pixel_radius * t; /* err(|p_i - o|): the trace's own eps(t) */
        t = sdft_maxf(t + ft - err, ray->tnear);
        ft = sdft_field_distance(f, s, sdft_madd(ray->org, ray->dir, t));
    }
    *steps += (uint32_t)iters;
    *f_out = ft;
    return t;
}
