/* sdftrace — a pinhole camera and the primary rays it shoots. */
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
sdft_ray sdft_camera_ray(const sdft_camera *c, int width, int height, float px, float py);

/* Half a pixel's footprint at unit distance: Keinert's pixelRadius. */
float sdft_camera_pixel_radius(const sdft_camera *c, int height);

#ifdef __cplusplus
}
#endif
#endif
