/* sdftrace — making a field, and what every field gets for free: normals
 * by tetrahedral differences and clipping rays to its bounds. */
#include <string.h>

#include "ray_box.h"
#include "sdftrace/field.h"

sdft_field sdft_field_defaults(void)
{
    sdft_field f;
    memset(&f, 0, sizeof f);
    return f;
}

sdft_field_accel sdft_field_accel_defaults(void)
{
    sdft_field_accel a;
    memset(&a, 0, sizeof a);
    return a;
}

float sdft_field_feature_size(const sdft_field *f)
{
    return f->feature_size > 0.0f ? f->feature_size : 1e-4f * sdft_length(sdft_sub(f->bounds.hi, f->bounds.lo));
}

sdft_vec3 sdft_field_normal(const sdft_field *f, sdft_scratch *s, sdft_vec3 p)
{
    if (f->normal)
        return f->normal(f->ctx, s, p);
    const float h = sdft_field_feature_size(f);
    /* The four corners (1,-1,-1), (-1,-1,1), (-1,1,-1), (1,1,1) of a
     * tetrahedron: their weighted sum is the central-difference gradient. */
    static const sdft_vec3 k[4] = {{1, -1, -1}, {-1, -1, 1}, {-1, 1, -1}, {1, 1, 1}};
    sdft_vec3 g = {0, 0, 0};
    for (int i = 0; i < 4; i++)
        g = sdft_madd(g, k[i], f->distance(f->ctx, s, sdft_madd(p, k[i], h)));
    return sdft_normalize(g);
}

void sdft_field_distances(const sdft_field *f, sdft_scratch *s, const sdft_vec3 *p, size_t n, float *d)
{
    const size_t ahead = SDFT_FIELD_DISTANCES_AHEAD;
    const sdft_field_accel *a = f->accel;
    size_t i = 0;
    if (a && a->prefetch) {
        for (size_t k = 0; k < n && k < ahead; k++)
            a->prefetch(a->ctx, p[k]);
        for (; i + ahead < n; i++) {
            a->prefetch(a->ctx, p[i + ahead]);
            d[i] = f->distance(f->ctx, s, p[i]);
        }
    }
    for (; i < n; i++)
        d[i] = f->distance(f->ctx, s, p[i]);
}

int sdft_aabb_clip(sdft_aabb box, sdft_vec3 org, sdft_vec3 dir, float tnear, float tfar, float *t0, float *t1)
{
    return ray_box_clip(box, org, dir, tnear, tfar, t0, t1);
}
