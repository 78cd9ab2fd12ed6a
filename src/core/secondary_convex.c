/* Keinert et al. 3.5, the optimization for convex objects: a ray that
 * starts inside a convex part leaves it where a ray from the far side of
 * the part's convex bounding volume, traced backwards, first meets it. So
 * instead of marching through the inside, where steps are as short as the
 * distance to the nearest face, the ray is traced from outside, where they
 * grow towards the surface it will hit. Convexity is what makes the first
 * hit from the far side the last crossing from the inside: a line meets a
 * convex surface at most twice. */
#include "secondary.h"

/* The part as a field of its own, clipped to its sphere's box. */
static sdft_field part_field(const sdft_convex_part *c)
{
    sdft_field f = sdft_field_defaults();
    f.distance = c->distance;
    f.ctx = c->ctx;
    const sdft_vec3 r = sdft_v3(c->radius, c->radius, c->radius);
    f.bounds = (sdft_aabb){sdft_sub(c->centre, r), sdft_add(c->centre, r)};
    f.feature_size = 1e-4f * c->radius;
    return f;
}

/* Where the line org + t dir (unit dir) is inside the sphere: [*t0, *t1];
 * 0 when it misses it. */
static int sphere_span(const sdft_convex_part *c, sdft_vec3 org, sdft_vec3 dir, float *t0, float *t1)
{
    const sdft_vec3 oc = sdft_sub(org, c->centre);
    const float b = sdft_dot(oc, dir), q = sdft_dot(oc, oc) - c->radius * c->radius, disc = b * b - q;
    if (disc < 0.0f)
        return 0;
    const float h = sqrtf(disc);
    *t0 = -b - h, *t1 = -b + h;
    return 1;
}

sdft_hit secondary_trace_convex(const sdft_convex_part *c, sdft_scratch *s, const sdft_ray *ray,
                                const sdft_trace_params *p)
{
    const sdft_field f = part_field(c);
    float t0, t1;
    sdft_hit miss = {.t = ray->tfar, .distance = INFINITY, .status = SDFT_MISS};
    if (!sphere_span(c, ray->org, ray->dir, &t0, &t1) || t1 <= ray->tnear || t0 >= ray->tfar)
        return miss;
    sdft_ray r = *ray;
    r.tfar = sdft_minf(t1, ray->tfar);
    if (t0 > ray->tnear) { /* case 1: from outside the sphere, traced from where it enters */
        r.tnear = t0;
        return sdft_trace(&f, s, &r, p);
    }
    const float f0 = sdft_field_distance(&f, s, sdft_madd(ray->org, ray->dir, ray->tnear));
    sdft_hit h;
    if (f0 > 0.0f) { /* case 2: inside the sphere, outside the part, traced from the origin */
        h = sdft_trace(&f, s, &r, p);
    } else { /* case 3: inside the part, traced backwards from the sphere's far side */
        const sdft_ray back = {.org = sdft_madd(ray->org, ray->dir, t1),
                               .tnear = 0.0f,
                               .dir = sdft_scale(ray->dir, -1.0f),
                               .tfar = t1 - ray->tnear};
        h = sdft_trace(&f, s, &back, p);
        h.t = t1 - h.t;
        h.normal = sdft_v3(0, 0, 0);
        if (h.status == SDFT_HIT && h.t > r.tfar)
            h.status = SDFT_MISS;
    }
    h.steps++;
    return h;
}

int secondary_convex_part_at(const sdft_field_accel *a, sdft_scratch *s, sdft_vec3 p, uint32_t *steps)
{
    for (size_t i = 0; a && i < a->convex_count; i++) {
        const sdft_convex_part *c = &a->convex[i];
        const sdft_vec3 pc = sdft_sub(p, c->centre);
        if (sdft_dot(pc, pc) >= c->radius * c->radius)
            continue;
        ++*steps;
        if (c->distance(c->ctx, s, p) < 0.0f)
            return (int)i;
    }
    return -1;
}
