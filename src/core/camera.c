/* sdftrace — the pinhole camera: an orthonormal frame from (from, at, up)
 * and a vertical field of view. */
#include <math.h>

#include "sdftrace/camera.h"

/* Right, up and forward unit vectors. An up hint parallel to the view
 * direction is replaced by the world axis least aligned with it. */
static void camera_frame(const sdft_camera *c, sdft_vec3 *u, sdft_vec3 *v, sdft_vec3 *w)
{
    *w = sdft_normalize(sdft_sub(c->at, c->from));
    sdft_vec3 right = sdft_cross(*w, c->up);
    if (!(sdft_length(right) > 1e-6f))
        right = sdft_cross(*w, fabsf(w->y) < 0.9f ? sdft_v3(0, 1, 0) : sdft_v3(1, 0, 0));
    *u = sdft_normalize(right);
    *v = sdft_cross(*u, *w);
}

/* tan(fov / 2): half the image height at unit distance. */
static float camera_half_height(const sdft_camera *c) { return tanf(0.5f * c->fov_deg * 3.14159265358979f / 180.0f); }

sdft_view sdft_camera_view(const sdft_camera *c, int width, int height)
{
    sdft_vec3 u, v, w;
    camera_frame(c, &u, &v, &w);
    const float th = camera_half_height(c), tw = th * (float)width / (float)height;
    return (sdft_view){
        .from = c->from,
        .right_per_px = sdft_scale(u, 2.0f * tw / (float)width),
        .down_per_px = sdft_scale(v, -2.0f * th / (float)height),
        .top_left = sdft_add(w, sdft_add(sdft_scale(u, -tw), sdft_scale(v, th))),
    };
}

sdft_ray sdft_camera_ray(const sdft_camera *c, int width, int height, float px, float py)
{
    const sdft_view view = sdft_camera_view(c, width, height);
    return sdft_view_ray(&view, px, py);
}

sdft_camera sdft_camera_front(sdft_aabb b, int width, int height, float fov_deg)
{
    const sdft_vec3 c = sdft_scale(sdft_add(b.lo, b.hi), 0.5f), e = sdft_scale(sdft_sub(b.hi, b.lo), 0.5f);
    const float aspect = (float)width / (float)height;
    const float half = sdft_maxf(e.y, e.x / aspect) * 1.15f;
    const float dist = e.z + half / camera_half_height(&(sdft_camera){.fov_deg = fov_deg});
    return (sdft_camera){.from = sdft_v3(c.x, c.y, c.z + dist), .at = c, .up = sdft_v3(0, 1, 0), .fov_deg = fov_deg};
}

float sdft_camera_pixel_radius(const sdft_camera *c, int height)
{
    /* A pixel is 2 tan(fov/2) / height tall at unit distance; half of it. */
    return camera_half_height(c) / (float)height;
}

float sdft_view_cone(const sdft_view *v, float x0, float y0, float x1, float y1, sdft_vec3 *axis)
{
    *axis = sdft_view_ray(v, 0.5f * (x0 + x1), 0.5f * (y0 + y1)).dir;
    float spread = 0.0f;
    for (int k = 0; k < 4; k++) {
        const sdft_vec3 d = sdft_view_ray(v, (k & 1) ? x1 : x0, (k & 2) ? y1 : y0).dir;
        spread = sdft_maxf(spread, sdft_length(sdft_sub(d, *axis)));
    }
    return spread * 1.0001f + 1e-7f;
}
