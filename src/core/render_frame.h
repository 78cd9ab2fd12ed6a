/* sdftrace — what the frame loop (render.c) and Whitted shading
 * (render_whitted.c) share: a frame's settings, read by every pixel, what
 * one pixel gives the image and the counts, and the sky. Neither file calls
 * into the other but through render_whitted.h. Internal header. */
#ifndef SDFTRACE_RENDER_FRAME_H
#define SDFTRACE_RENDER_FRAME_H

#include "render_hull.h"
#include "render_pixel.h"
#include "sdftrace/render.h"

/* What every pixel of one frame shares, set up once. */
typedef struct frame {
    const sdft_field *f;
    const sdft_render_params *rp;
    sdft_trace_params tp; /* with the screen-space pixel radius, if asked */
    float feature;        /* the field's feature size: the normal's step */
    sdft_view view;
    float cone_tfar;          /* with cones: beyond it every primary ray has left the field's box */
    float cone_tnear;         /* the eye's distance to the field's box: no primary ray meets the surface before it */
    const hull_bins *bins;    /* the field's hull boxes binned to tiles; NULL: not used */
    int whitted;              /* 1: hits shaded by render_whitted (materials, secondary rays, soft shadows, ...) */
    const sdft_field *inside; /* with whitted: f with its sign flipped (secondary_inside), for rays inside it */
    float ao_reach;           /* with ambient occlusion: its farthest sample, 2% of the field's box diagonal */
} frame;

/* What one pixel contributes to the image and the counts. */
typedef struct pixel_result {
    sdft_vec3 rgb, normal;
    float depth;
    uint32_t steps, fallbacks, rays;
    uint32_t primary_steps, primary_fallbacks; /* the primary ray's share of steps and fallbacks */
    uint32_t shadow_steps;                     /* the shadow rays' and occlusion samples' share of steps */
    uint32_t secondary_steps, secondary_rays;  /* reflection and refraction rays: their share, their number */
    uint32_t eps_hits, eps_from_f; /* hits shaded the Whitted way, and of them those whose rays left by 2 |f(p)| */
    uint32_t self_hits;            /* secondary rays that hit within 2 eps_min of their origin */
    sdft_status status;
} pixel_result;

/* What a ray that hits nothing shows: the sky at its unit direction's
 * height `up` (the unit direction's y), or black for depth alone. */
static inline sdft_vec3 render_miss_colour(const sdft_render_params *rp, float up)
{
    return render_sky(rp->depth_only, up);
}

#endif
