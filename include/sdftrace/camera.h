/* sdftrace — a pinhole camera and the primary rays it shoots. World units
 * and degrees; every struct is plain data, passed and returned by value or
 * read through the caller's pointer. */
#ifndef SDFTRACE_CAMERA_H
#define SDFTRACE_CAMERA_H

#include "trace.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sdft_camera {
    sdft_vec3 from, at, up; /* eye, look-at point, up hint (world units) */
    float fov_deg;          /* vertical field of view, degrees, in (0, 180) */
} sdft_camera;

/* Ray through image position (px, py) of a width x height image, pixel
 * centres at integer + 0.5, y down. tnear 0, tfar INFINITY, unit dir. */
SDFT_API sdft_ray sdft_camera_ray(const sdft_camera *c, int width, int height, float px, float py);

/* A camera set up once for one image size, so that a ray costs a few
 * multiplies and a normalisation (the frame and tan(fov / 2) are taken
 * once): sdft_view_ray(&view, px, py) is sdft_camera_ray(c, width,
 * height, px, py). Plain data; share it between threads. */
typedef struct sdft_view {
    sdft_vec3 from;
    sdft_vec3 right_per_px; /* u * (image half-width at unit distance) * 2 / width */
    sdft_vec3 down_per_px;  /* -v * (image half-height at unit distance) * 2 / height */
    sdft_vec3 top_left;     /* w - u * half-width + v * half-height: image position (0, 0) */
} sdft_view;

SDFT_API sdft_view sdft_camera_view(const sdft_camera *c, int width, int height);

static inline sdft_ray sdft_view_ray(const sdft_view *v, float px, float py)
{
    sdft_ray ray;
    ray.org = v->from;
    ray.tnear = 0.0f;
    ray.dir = sdft_normalize(sdft_madd(sdft_madd(v->top_left, v->right_per_px, px), v->down_per_px, py));
    ray.tfar = INFINITY;
    return ray;
}

/* A camera in front of box b (on its +z side, looking along -z, y up) whose
 * vertical field of view fov_deg frames the whole box with a 15% margin in
 * a width x height image: what `sdftrace render --grid` uses without a
 * scene, and the grid bench's front view. */
SDFT_API sdft_camera sdft_camera_front(sdft_aabb b, int width, int height, float fov_deg);

/* Half a pixel's footprint at unit distance: Keinert's pixelRadius. */
SDFT_API float sdft_camera_pixel_radius(const sdft_camera *c, int height);

/* The cone of the rays through the image rectangle [x0, x1] x [y0, y1]
 * (pixel units): its axis, the unit ray through the rectangle's centre, and
 * its spread, the largest |d - axis| over those rays' unit directions d.
 * The angle to the axis is quasi-convex over the image plane (the points
 * within a given angle of the axis form a convex cone), so the largest
 * lies at a corner; the result is nudged up for rounding. */
SDFT_API float sdft_view_cone(const sdft_view *v, float x0, float y0, float x1, float y1, sdft_vec3 *axis);

#ifdef __cplusplus
}
#endif
#endif
