/* sdftrace — the light a hit sees, the way the primer's shader measures it
 * from the field alone: soft shadows (the penumbra of a light of some size,
 * from how closely the shadow ray passes the occluders, min k f / t) and
 * ambient occlusion (how far short of its height above the surface f falls
 * a little way out along the normal). */
#include "secondary.h"

float secondary_soft_shadow(const sdft_field *f, sdft_scratch *s, sdft_vec3 org, sdft_vec3 dir, float tfar, float k,
                            float step_min, float eps, uint32_t max_steps, uint32_t *steps)
{
    float lit = 1.0f, t = step_min;
    uint32_t i = 0;
    while (i < max_steps && t < tfar) {
        const float d = sdft_field_distance(f, s, sdft_madd(org, dir, t));
        i++;
        if (d <= eps) { /* the ray meets a surface: no light */
            lit = 0.0f;
            break;
        }
        lit = sdft_minf(lit, k * d / t);
        t += sdft_maxf(d, step_min);
    }
    *steps += i;
    return sdft_minf(sdft_maxf(lit, 0.0f), 1.0f);
}

float secondary_occlusion(const sdft_field *f, sdft_scratch *s, sdft_vec3 p, sdft_vec3 n, float reach, uint32_t *steps)
{
    float occ = 0.0f, weight = 1.0f;
    for (int i = 1; i <= 5; i++) {
        const float h = reach * 0.2f * (float)i;
        occ += (h - sdft_field_distance(f, s, sdft_madd(p, n, h))) * weight;
        weight *= 0.7f;
    }
    *steps += 5;
    /* The primer's 1 - 2 occ at its reach of 0.4, in units of the reach. */
    return sdft_minf(sdft_maxf(1.0f - 0.8f * occ / reach, 0.0f), 1.0f);
}
