/* sdftrace — Whitted shading (Keinert et al. 4: "the translucent
 * materials ... are computed in a fashion similar to Whitted"): at each
 * hit, the material's colour lit by the point light (a hard shadow ray or
 * the primer's soft shadow, times ambient occlusion), a mirror reflection
 * for a reflective surface, and for a dielectric both a reflection and a
 * refraction weighed by Fresnel's term (Schlick), or the reflection alone
 * at total internal reflection. Every secondary ray starts eps_dynamic off
 * its hit (3.3); every hit may be settled by the fixed-point iteration
 * first (3.4); a ray inside a convex part the field declares leaves it from
 * its bounding sphere's far side (3.5), any other ray inside the surface is
 * traced with f's sign flipped. A path takes at most reflect_bounces
 * reflections and refract_bounces refractions; where a budget runs out,
 * the path ends in the material's own lit colour. No allocation: the
 * recursion is bounded by the two budgets. */
#include "render_whitted.h"

#include <math.h>

#include "secondary.h"

int render_whitted_wanted(const sdft_render_params *rp)
{
    return !rp->depth_only &&
           (rp->materials || rp->eps_min > 0.0f || rp->smooth_iters > 0 || rp->soft_shadows > 0.0f || rp->ao);
}

/* What one pixel's paths share: the frame, the thread's scratch, and the
 * pixel whose counts they add to. */
typedef struct path {
    const frame *fr;
    sdft_scratch *s;
    pixel_result *px;
} path;

/* The material at p. */
static sdft_material material_at(const frame *fr, sdft_vec3 p)
{
    const sdft_render_params *rp = fr->rp;
    return rp->materials && fr->f->material ? fr->f->material(fr->f->ctx, p) : rp->material;
}

/* eps_min of 3.3: the parameter, or where it is 0 the normal's difference
 * step, the scale below which the normal is not known. A floor, as
 * Keinert's global eps_min: how far a hit lies off the surface is |f(p)|'s
 * to say (a refined hit: nothing; one settled by 3.4: eps(t); a
 * screen-space candidate that ran out of steps: its distance). */
static float eps_min_of(const frame *fr) { return fr->rp->eps_min > 0.0f ? fr->rp->eps_min : fr->feature; }

/* A secondary ray's hit; inside: the ray starts inside the surface. */
static sdft_hit trace_secondary(const path *pa, const sdft_ray *ray, int inside, uint32_t *steps)
{
    const frame *fr = pa->fr;
    sdft_hit h;
    const sdft_field_accel *a = fr->f->accel;
    const int part =
        inside && fr->rp->convex && a && a->convex_count ? secondary_convex_part_at(a, pa->s, ray->org, steps) : -1;
    if (part >= 0) {
        h = secondary_trace_convex(&a->convex[part], pa->s, ray, &fr->tp);
        h.distance = -h.distance; /* found from outside the part: -f, as the inside trace would give */
    } else {
        h = sdft_trace(inside ? fr->inside : fr->f, pa->s, ray, &fr->tp);
    }
    *steps += h.steps;
    return h;
}

/* How much of the point light reaches p (normal n) along unit l, dist
 * away: 1, or the shadow ray's verdict, from p lifted by eps. */
static float light_seen(const path *pa, sdft_vec3 p, sdft_vec3 n, float eps, sdft_vec3 l, float dist)
{
    const frame *fr = pa->fr;
    const sdft_render_params *rp = fr->rp;
    pixel_result *px = pa->px;
    const sdft_vec3 org = sdft_madd(p, n, eps);
    px->rays++;
    if (rp->soft_shadows > 0.0f)
        return secondary_soft_shadow(fr->f, pa->s, org, l, dist, rp->soft_shadows, eps, fr->tp.eps, fr->tp.max_steps,
                                     &px->shadow_steps);
    const sdft_ray shadow = {.org = org, .tnear = 0.0f, .dir = l, .tfar = dist};
    const sdft_hit h = sdft_trace(fr->f, pa->s, &shadow, &fr->tp);
    px->shadow_steps += h.steps, px->fallbacks += h.fallbacks;
    return h.status == SDFT_HIT ? 0.0f : 1.0f;
}

/* The material's own colour at p (outward normal n) under the point light
 * and the ambient light, both dimmed by occlusion where asked. */
static sdft_vec3 local_colour(const path *pa, sdft_material m, sdft_vec3 p, sdft_vec3 n, float eps)
{
    const frame *fr = pa->fr;
    const sdft_vec3 to_light = sdft_sub(fr->rp->light, p);
    const float dist = sdft_length(to_light);
    const sdft_vec3 l = sdft_scale(to_light, 1.0f / sdft_maxf(dist, 1e-30f));
    float diffuse = sdft_maxf(sdft_dot(n, l), 0.0f);
    if (diffuse > 0.0f && fr->rp->shadows)
        diffuse *= light_seen(pa, p, n, eps, l, dist);
    const float occ = fr->rp->ao ? secondary_occlusion(fr->f, pa->s, p, n, fr->ao_reach, &pa->px->shadow_steps) : 1.0f;
    return sdft_scale(m.colour, (RENDER_AMBIENT + (1.0f - RENDER_AMBIENT) * diffuse) * occ);
}

static sdft_vec3 radiance(const path *pa, sdft_ray ray, int inside, int reflections, int refractions);

/* A dielectric's colour at p: Fresnel's share reflected, the rest
 * refracted into (or out of) it, tinted by its colour; n faces the ray. */
static sdft_vec3 dielectric(const path *pa, sdft_material m, sdft_vec3 d, sdft_vec3 p, sdft_vec3 n, float eps,
                            int inside, int reflections, int refractions)
{
    const float n1 = inside ? m.ior : 1.0f, n2 = inside ? 1.0f : m.ior;
    sdft_vec3 refracted;
    const int passes = secondary_refract(d, n, n1 / n2, &refracted);
    /* Schlick takes the cosine on the rarer side: the refracted ray's when leaving. */
    const float cos_rare = inside ? -sdft_dot(refracted, n) : -sdft_dot(d, n);
    const float fresnel = passes ? secondary_schlick(n1, n2, cos_rare) : 1.0f;
    sdft_vec3 c = sdft_v3(0, 0, 0);
    if (passes && refractions > 0) {
        const sdft_ray r = {.org = sdft_madd(p, n, -eps), .tnear = 0.0f, .dir = refracted, .tfar = INFINITY};
        c = sdft_scale(sdft_mul(m.colour, radiance(pa, r, !inside, reflections, refractions - 1)), 1.0f - fresnel);
    } else if (passes) {
        c = sdft_scale(m.colour, 1.0f - fresnel); /* the budget spent: the glass's own colour */
    }
    /* Total internal reflection is refraction's budget: the light stays in the glass. */
    const int budget = passes ? reflections : refractions;
    if (budget > 0) {
        const sdft_ray r = {
            .org = sdft_madd(p, n, eps), .tnear = 0.0f, .dir = secondary_reflect(d, n), .tfar = INFINITY};
        c = sdft_madd(c, radiance(pa, r, inside, reflections - passes, refractions - !passes), fresnel);
    }
    return c;
}

/* The colour at hit h of ray (inside: travelling inside the surface):
 * settled (3.4), its material, its light, its reflection and refraction;
 * *n_out the outward normal there. */
static sdft_vec3 shade_hit(const path *pa, const sdft_ray *ray, sdft_hit h, int inside, int reflections,
                           int refractions, uint32_t *steps, sdft_vec3 *n_out)
{
    const frame *fr = pa->fr;
    const sdft_field *traced = inside ? fr->inside : fr->f;
    float fp = isfinite(h.distance) ? h.distance : 0.0f;
    float t = h.t;
    if (fr->rp->smooth_iters > 0)
        t = secondary_smooth(traced, pa->s, ray, t, fp, &fr->tp, fr->rp->smooth_iters, &fp, steps);
    const sdft_vec3 p = sdft_madd(ray->org, ray->dir, t);
    sdft_vec3 n = !inside && sdft_dot(h.normal, h.normal) > 0.25f ? h.normal : sdft_field_normal(fr->f, pa->s, p);
    if (!sdft_isfinite3(n) || !(sdft_dot(n, n) > 0.25f))
        n = sdft_scale(ray->dir, inside ? 1.0f : -1.0f);
    *n_out = n;
    const sdft_vec3 facing = inside ? sdft_scale(n, -1.0f) : n;
    const float eps_min = eps_min_of(fr);
    const float eps = secondary_eps(eps_min, fp); /* 3.3 */
    pa->px->eps_hits++, pa->px->eps_from_f += fabsf(fp) > eps_min;
    const sdft_material m = material_at(fr, p);
    if (m.ior > 0.0f)
        return dielectric(pa, m, ray->dir, p, facing, eps, inside, reflections, refractions);
    const sdft_vec3 local = local_colour(pa, m, p, facing, eps);
    if (!(m.reflectance > 0.0f) || reflections <= 0)
        return local;
    const sdft_ray r = {
        .org = sdft_madd(p, facing, eps), .tnear = 0.0f, .dir = secondary_reflect(ray->dir, facing), .tfar = INFINITY};
    return sdft_add(sdft_scale(local, 1.0f - m.reflectance),
                    sdft_scale(radiance(pa, r, inside, reflections - 1, refractions), m.reflectance));
}

/* What a secondary ray sees: its hit shaded, or the sky. */
static sdft_vec3 radiance(const path *pa, sdft_ray ray, int inside, int reflections, int refractions)
{
    pixel_result *px = pa->px;
    px->secondary_rays++;
    const sdft_hit h = trace_secondary(pa, &ray, inside, &px->secondary_steps);
    px->fallbacks += h.fallbacks;
    px->self_hits += h.status == SDFT_HIT && h.t < 2.0f * eps_min_of(pa->fr);
    if (h.status != SDFT_HIT && !(h.status == SDFT_NOT_CONVERGED && pa->fr->tp.pixel_radius > 0.0f))
        return render_miss_colour(pa->fr->rp, ray.dir.y);
    sdft_vec3 n;
    return shade_hit(pa, &ray, h, inside, reflections, refractions, &px->secondary_steps, &n);
}

void render_whitted_pixel(const frame *fr, sdft_scratch *s, sdft_ray ray, sdft_hit h, pixel_result *out)
{
    *out = (pixel_result){.depth = INFINITY,
                          .fallbacks = h.fallbacks,
                          .rays = 1,
                          .primary_steps = h.steps,
                          .primary_fallbacks = h.fallbacks,
                          .status = h.status};
    /* As render.c: a non-converged ray is a hit only with the screen-space criterion (3.2). */
    const int surface = h.status == SDFT_HIT || (h.status == SDFT_NOT_CONVERGED && fr->tp.pixel_radius > 0.0f);
    if (!surface) {
        out->rgb = render_miss_colour(fr->rp, ray.dir.y);
    } else {
        const path pa = {fr, s, out};
        out->depth = h.t;
        uint32_t primary = 0;
        out->rgb = shade_hit(&pa, &ray, h, 0, fr->rp->reflect_bounces, fr->rp->refract_bounces, &primary, &out->normal);
        out->primary_steps += primary; /* the settling iterations are the primary ray's */
    }
    out->steps = out->primary_steps + out->shadow_steps + out->secondary_steps;
}
