/* Trace your own SDF: a torus, given to sdftrace as a C callback. */
#include <math.h>
#include <stdio.h>

#include "sdftrace/render.h"

typedef struct torus {
    float major, minor;
} torus;

static float torus_distance(const void *ctx, sdft_scratch *scratch, sdft_vec3 p)
{
    (void)scratch; /* a procedural field keeps no per-thread state */
    const torus *t = ctx;
    float q = sqrtf(p.x * p.x + p.z * p.z) - t->major;
    return sqrtf(q * q + p.y * p.y) - t->minor;
}

int main(void)
{
    torus ring = {1.0f, 0.25f};
    sdft_field field = sdft_field_defaults(); /* then what this field has */
    field.distance = torus_distance;
    field.ctx = &ring;
    field.bounds = (sdft_aabb){{-1.25f, -0.25f, -1.25f}, {1.25f, 0.25f, 1.25f}};

    /* One ray from above the hole through the middle of the tube at (1, 0, 0):
     * it should stop sqrt(5) - 0.25 away. */
    sdft_scratch scratch;
    sdft_scratch_init(&field, &scratch);
    sdft_trace_params params = sdft_trace_defaults(); /* auto-relaxed, beta 0.3, eps 1e-4 */
    sdft_ray ray = {.org = {0, 2, 0}, .tnear = 0, .dir = sdft_normalize(sdft_v3(1, -2, 0)), .tfar = INFINITY};
    sdft_hit hit = sdft_trace(&field, &scratch, &ray, &params);
    printf("t = %.4f after %u evaluations\n", hit.t, hit.steps);

    /* A whole image, shadows and all, on every core. */
    sdft_render_params rp = sdft_render_defaults();
    rp.width = 320, rp.height = 180;
    rp.camera = (sdft_camera){.from = {0, 2, 3}, .at = {0, 0, 0}, .up = {0, 1, 0}, .fov_deg = 45};
    sdft_image img;
    sdft_render_stats stats;
    char msg[128];
    sdft_error err = sdft_image_alloc(&img, rp.width, rp.height, msg, sizeof msg);
    if (!err)
        err = sdft_render(&field, &rp, &img, &stats, msg, sizeof msg);
    if (err) { /* every fallible call: a code, and one line saying why */
        fprintf(stderr, "%s: %s\n", sdft_error_name(err), msg);
        sdft_image_free(&img);
        return 1;
    }
    printf("%.1f%% of pixels hit, %.1f evaluations per pixel\n",
           100.0 * (double)stats.hits / (double)stats.primary_rays, (double)stats.steps / (double)stats.primary_rays);
    sdft_image_free(&img);
    return hit.status == SDFT_HIT && fabsf(hit.t - (sqrtf(5.0f) - 0.25f)) < 1e-3f ? 0 : 1;
}
