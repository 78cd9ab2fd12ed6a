/* sdftrace — a field seen from inside its surface: -f, for the rays that
 * travel through a refractive object (Keinert et al. 3.3, 4: refraction
 * rays are traced with the sign of f flipped, so that every tracing
 * variant, which marches towards f = 0 from f > 0, finds the exit). */
#include "secondary.h"

static float flipped_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    const sdft_field *f = ctx;
    return -f->distance(f->ctx, s, p);
}

static sdft_vec3 flipped_normal(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    return sdft_scale(sdft_field_normal(ctx, s, p), -1.0f);
}

sdft_field secondary_inside(const sdft_field *f)
{
    sdft_field in = sdft_field_defaults();
    in.distance = flipped_distance;
    in.normal = flipped_normal;
    in.ctx = f; /* no scratch_init: the scratch prepared for f serves, as f's own callbacks read it */
    in.bounds = f->bounds;
    in.feature_size = sdft_field_feature_size(f);
    return in;
}
