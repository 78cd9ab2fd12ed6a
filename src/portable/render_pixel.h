/* sdftrace — what one pixel of a frame needs besides its traces: its
 * primary ray's direction, whether its tile can see the field's box, its
 * span of the hull's boxes, the sky, the grey surface's shading and the
 * shadow ray to the point light. The library's frame loop (render.c,
 * render_hull.c) runs these over tiles and blocks of rays; the shader runs
 * them for its one pixel. Portable (portable.h). */
#ifndef SDFTRACE_RENDER_PIXEL_H
#define SDFTRACE_RENDER_PIXEL_H

#include "portable.h"

/* The ambient share of the light on every surface. */
#define RENDER_AMBIENT 0.12f

/* Shading constants: a warm grey surface, a blue sky. */
PORT_CONST sdft_vec3 RENDER_ALBEDO = {0.80f, 0.76f, 0.70f};
PORT_CONST sdft_vec3 RENDER_SKY_HORIZON = {0.78f, 0.85f, 0.95f};
PORT_CONST sdft_vec3 RENDER_SKY_ZENITH = {0.30f, 0.50f, 0.85f};

/* The unit direction of the primary ray through image point (px, py) of
 * a view (sdft_view: top_left, right_per_px and down_per_px): the image
 * point's direction normalized as sdft_normalize does, written without a
 * branch so that a loop over a tile's pixels vectorizes. */
PORT_INLINE sdft_vec3 render_view_dir(sdft_vec3 top_left, sdft_vec3 right_per_px, sdft_vec3 down_per_px, float px,
                                      float py)
{
    const float ax = top_left.x + right_per_px.x * px + down_per_px.x * py,
                ay = top_left.y + right_per_px.y * px + down_per_px.y * py,
                az = top_left.z + right_per_px.z * px + down_per_px.z * py;
    const float len = sqrtf(ax * ax + ay * ay + az * az);
    const float inv = 1.0f / len, s = len > 0.0f ? inv : 1.0f;
    return sdft_v3(ax * s, ay * s, az * s);
}

/* What a ray that hits nothing shows: the sky at its unit direction's
 * height `up`, or black for depth alone. */
PORT_INLINE sdft_vec3 render_sky(int depth_only, float up)
{
    if (depth_only != 0)
        return sdft_v3(0.0f, 0.0f, 0.0f);
    float k = sdft_minf(sdft_maxf(up, 0.0f), 1.0f);
    return sdft_add(sdft_scale(RENDER_SKY_HORIZON, 1.0f - k), sdft_scale(RENDER_SKY_ZENITH, k));
}

/* The grey surface's colour under diffuse light of cosine `diffuse` (0:
 * in shadow). */
PORT_INLINE sdft_vec3 render_lit(float diffuse)
{
    return sdft_scale(RENDER_ALBEDO, RENDER_AMBIENT + (1.0f - RENDER_AMBIENT) * diffuse);
}

/* Whether a hit's normal is one: the exact root's (sdft_hit.normal), else
 * (0, 0, 0) and the field's normal at the hit serves. */
PORT_INLINE bool render_has_normal(sdft_vec3 n) { return sdft_dot(n, n) > 0.25f; }

/* The normal n to shade by, or facing the ray (-dir) where n is not a
 * finite unit vector. */
PORT_INLINE sdft_vec3 render_facing_normal(sdft_vec3 n, sdft_vec3 dir)
{
    return !sdft_isfinite3(n) || !(sdft_dot(n, n) > 0.25f) ? sdft_scale(dir, -1.0f) : n;
}

/* How far a shadow ray's origin is lifted off a hit at t: past the
 * convergence radius there and the normal's difference step (`feature`),
 * so that it does not re-hit its own surface at t = 0. */
PORT_INLINE float render_shadow_lift(sdft_trace_params p, float t, float feature)
{
    return 4.0f * (p.eps + p.pixel_radius * t) + 2.0f * feature;
}

/* The shadow ray from surface point p (normal n) to the point light: its
 * origin lifted off the surface by `lift`. 0 when p is at the light. */
PORT_INLINE int render_shadow_ray(sdft_vec3 p, sdft_vec3 n, float lift, sdft_vec3 light, PORT_OUT(sdft_ray) ray)
{
    sdft_vec3 org = sdft_madd(p, n, lift);
    sdft_vec3 to_light = sdft_sub(light, org);
    float dist = sdft_length(to_light);
    if (!(dist > 0.0f))
        return 0;
    PORT_DEREF(ray).org = org;
    PORT_DEREF(ray).tnear = 0.0f;
    PORT_DEREF(ray).dir = sdft_scale(to_light, 1.0f / dist);
    PORT_DEREF(ray).tfar = dist;
    return 1;
}

/* The distance from p to box b (0 inside it). */
PORT_INLINE float render_box_distance(sdft_aabb b, sdft_vec3 p)
{
    const sdft_vec3 away = sdft_max_v(sdft_max_v(sdft_sub(b.lo, p), sdft_sub(p, b.hi)), sdft_v3(0.0f, 0.0f, 0.0f));
    return sdft_length(away);
}

/* The corner (k & 1 ? hi : lo, ...) of box b. */
PORT_INLINE sdft_vec3 render_box_corner(sdft_aabb b, int k)
{
    return sdft_v3((k & 1) != 0 ? b.hi.x : b.lo.x, (k & 2) != 0 ? b.hi.y : b.lo.y, (k & 4) != 0 ? b.hi.z : b.lo.z);
}

/* 0 when no ray from the eye `from` with the unit directions d[0..3] at
 * the corners of an image rectangle (in order around it) and c at its
 * centre can meet box b: the box lies wholly on the outer side of one of
 * the four planes through the eye and the rectangle's edges, or wholly
 * behind the eye. Conservative: 1 does not promise a hit. */
PORT_INLINE int render_rect_sees_box(sdft_vec3 from, const sdft_vec3 d[4], sdft_vec3 c, sdft_aabb b)
{
    sdft_vec3 n[5];
    for (int i = 0; i < 4; i++) {
        n[i] = sdft_cross(d[i], d[(i + 1) & 3]);
        if (sdft_dot(n[i], c) < 0.0f)
            n[i] = sdft_scale(n[i], -1.0f);
    }
    n[4] = c;
    for (int i = 0; i < 5; i++) {
        bool outside = true;
        for (int k = 0; k < 8 && outside; k++)
            outside = sdft_dot(sdft_sub(render_box_corner(b, k), from), n[i]) < 0.0f;
        if (outside)
            return 0;
    }
    return 1;
}

/* A direction component's reciprocal for the slab tests, a zero component
 * taken as a huge slope of its sign (no 0 * inf). */
PORT_INLINE float render_slope(float d) { return 1.0f / (fabsf(d) > 1e-30f ? d : copysignf(1e-30f, d)); }

/* One hull box against one pixel's ray from the eye, direction d with
 * reciprocals inv: lo and hi are the box's corners less the eye; slo and
 * shi the slab's planes (n . x between them) less n . eye. Widens
 * [span_in, span_out]
 * by the part of the ray in both (t >= 0); a ray that misses them widens
 * nothing. Selects, not branches, so that a loop over pixels vectorizes. */
PORT_INLINE void render_hull_box_span(const float lo[3], const float hi[3], sdft_vec3 n, float slo, float shi,
                                      float inv_x, float inv_y, float inv_z, float dx, float dy, float dz,
                                      PORT_INOUT(float) span_in, PORT_INOUT(float) span_out)
{
    const float ax = lo[0] * inv_x, bx = hi[0] * inv_x, ay = lo[1] * inv_y, by = hi[1] * inv_y;
    const float az = lo[2] * inv_z, bz = hi[2] * inv_z;
    const float nd = n.x * dx + n.y * dy + n.z * dz;
    const float is = 1.0f / (fabsf(nd) > 1e-30f ? nd : copysignf(1e-30f, nd));
    const float as = slo * is, bs = shi * is;
    const float a =
        sdft_maxf(sdft_maxf(sdft_maxf(sdft_minf(ax, bx), sdft_minf(ay, by)), sdft_maxf(sdft_minf(az, bz), 0.0f)),
                  sdft_minf(as, bs));
    const float c =
        sdft_minf(sdft_minf(sdft_minf(sdft_maxf(ax, bx), sdft_maxf(ay, by)), sdft_maxf(az, bz)), sdft_maxf(as, bs));
    /* a <= c: the ray meets the box; one it misses widens nothing. (Two
     * selects first, then min and max: GCC 12 vectorizes this form.) */
    const float enter = a <= c ? a : INFINITY, leave = a <= c ? c : -INFINITY;
    PORT_DEREF(span_in) = sdft_minf(PORT_DEREF(span_in), enter);
    PORT_DEREF(span_out) = sdft_maxf(PORT_DEREF(span_out), leave);
}

#endif
