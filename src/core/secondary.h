/* sdftrace — what secondary rays need, each close to its section of
 * Keinert et al., "Enhanced sphere tracing" (2014), and the primer's
 * shading: where a secondary ray starts (3.3), Snell's and Fresnel's laws
 * for its direction, the fixed-point iteration that settles a hit (3.4),
 * the convex-object optimization (3.5), soft shadows and ambient
 * occlusion. Internal header. */
#ifndef SDFTRACE_SECONDARY_H
#define SDFTRACE_SECONDARY_H

#include <math.h>

#include "sdftrace/trace.h"

/* Keinert 3.3: the offset of a secondary ray's origin from hit p along the
 * normal, eps_dynamic = 2 max(eps_min, |f(p)|): at least 2 eps_min, and
 * twice as far as the hit may lie from the surface. */
static inline float secondary_eps(float eps_min, float f_at_hit) { return 2.0f * sdft_maxf(eps_min, fabsf(f_at_hit)); }

/* The mirror direction of unit d about unit normal n. */
static inline sdft_vec3 secondary_reflect(sdft_vec3 d, sdft_vec3 n) { return sdft_madd(d, n, -2.0f * sdft_dot(d, n)); }

/* Snell's law: unit d refracted through unit normal n (facing d's origin,
 * d . n < 0) with eta = n_from / n_to, into *t; 0 at total internal
 * reflection (sin of the refracted angle above 1), *t then untouched. */
static inline int secondary_refract(sdft_vec3 d, sdft_vec3 n, float eta, sdft_vec3 *t)
{
    const float cos_i = -sdft_dot(d, n);
    const float k = 1.0f - eta * eta * (1.0f - cos_i * cos_i); /* cos^2 of the refracted angle */
    if (k < 0.0f)
        return 0;
    *t = sdft_normalize(sdft_madd(sdft_scale(d, eta), n, eta * cos_i - sqrtf(k)));
    return 1;
}

/* Schlick's approximation of Fresnel's reflectance between media of
 * indices n1 and n2, cos_theta the cosine on the rarer side. */
static inline float secondary_schlick(float n1, float n2, float cos_theta)
{
    const float r0 = (n1 - n2) / (n1 + n2), c = 1.0f - sdft_minf(sdft_maxf(cos_theta, 0.0f), 1.0f);
    return r0 * r0 + (1.0f - r0 * r0) * c * c * c * c * c;
}

/* Keinert 3.4, Equation 3: `iters` steps of t := t + f(p(t)) - err(t), with
 * err(t) = eps(t) of the trace parameters (trace.h), settling the hit at t
 * on f(p) = err(|p - o|). Returns the new t (never below ray->tnear); *f_out
 * is f there; the evaluations are added to *steps. */
float secondary_smooth(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, float t, float f_at_t,
                       const sdft_trace_params *p, int iters, float *f_out, uint32_t *steps);

/* Keinert 3.5: the ray against convex part c alone, its three cases: from
 * outside the bounding sphere, traced from where it enters; from inside
 * the sphere and outside the part, traced from the origin; from inside the
 * part, traced backwards from where it leaves the sphere, which finds the
 * part's exit point without marching through it. Every trace ends at the
 * sphere. The hit's t is along the ray as given; its counts include the
 * one evaluation that tells the cases apart. */
sdft_hit secondary_trace_convex(const sdft_convex_part *c, sdft_scratch *s, const sdft_ray *ray,
                                const sdft_trace_params *p);

/* The index of the first convex part of a (of a->convex_count) that holds
 * p (inside its sphere, its distance < 0), or -1; the evaluations are
 * added to *steps. */
int secondary_convex_part_at(const sdft_field_accel *a, sdft_scratch *s, sdft_vec3 p, uint32_t *steps);

/* The field f with its sign flipped, for rays inside its surface (Keinert
 * 3.3: refraction traces inside with -f): its ctx is f, which must outlive
 * it; its scratch is f's (sdft_scratch_init(f, ...)); no accel. */
sdft_field secondary_inside(const sdft_field *f);

/* The primer's soft shadow: the light seen from org along unit dir up to
 * tfar, marching with steps of at least step_min, as min k f / t (k > 0),
 * in [0, 1]: 0 where the ray meets a surface (f <= eps), 1 where it passes
 * everything by at least t / k. At most max_steps evaluations, added to
 * *steps. */
float secondary_soft_shadow(const sdft_field *f, sdft_scratch *s, sdft_vec3 org, sdft_vec3 dir, float tfar, float k,
                            float step_min, float eps, uint32_t max_steps, uint32_t *steps);

/* The primer's ambient occlusion at p with unit normal n: five samples at
 * reach / 5, 2 reach / 5, ... along n, each short of its distance by what
 * is near, weighted 0.7 per sample farther out; 1 in the open, less in
 * creases. Five evaluations, added to *steps. */
float secondary_occlusion(const sdft_field *f, sdft_scratch *s, sdft_vec3 p, sdft_vec3 n, float reach, uint32_t *steps);

#endif
