/* sdftrace — the Vulkan compute shader: one invocation per pixel, 8 x 8 a
 * group, tracing a NanoVDB float grid with the library's own code (the
 * headers of src/portable, which the C library compiles too), as the frame
 * loop of render.c does for a pixel: its primary ray over its span of the
 * hull's boxes (or from the box's distance where the frame has no bins),
 * the normal, the grey surface lit by the point light, and a hard shadow
 * ray traced with the same variant. The variant is a specialization
 * constant, so the driver compiles the one the frame asks for. */
#version 450
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_control_flow_attributes : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_GOOGLE_include_directive : require

#define SDFT_GLSL
#include "gpu_frame.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(constant_id = 0) const int METHOD = SDFT_AUTO;

#define GRID_SHAPE frame.grid
#include "grid_root.h"
#include "grid_sample.h"

/* The field march_loop.h traces: the frame's grid, float, with the
 * frame's bound; the scratch is the invocation's read accessor. */
#define MARCH_FIELD uint
#define MARCH_SCRATCH inout pnanovdb_readaccessor_t
#define MARCH_EVAL(f, s, ray, t)                                                                                       \
    grid_distance(0u, PNANOVDB_GRID_TYPE_FLOAT, frame.grid.diagonal, s, sdft_madd((ray).org, (ray).dir, (t)),        \
                  frame.bound)
#define MARCH_HAS_ROOT(f, p) ((p).exact_root != 0)
#define MARCH_ROOT_REACH(f, p) (MARCH_HAS_ROOT(f, p) ? frame.root_reach : -INFINITY)
#define MARCH_ROOT(f, s, org, dir, t0, t1, t, normal, reads)                                                           \
    grid_walk(0u, PNANOVDB_GRID_TYPE_FLOAT, s, org, dir, t0, t1, t, normal, reads)
#define MARCH_BOUNDS(f) frame.bounds
#define march_start_fn int
#define march_step_fn int
#define MARCH_START(fn, m, p) march_variant_start(fn, m, p)
#define MARCH_STEP(fn, m, T, R, p) march_variant_step(fn, m, T, R, p)
#include "variants.h"
#include "march_loop.h"
#include "render_pixel.h"

/* sdft_trace: the ray clipped to the grid's box, then marched. */
sdft_hit trace(inout pnanovdb_readaccessor_t acc, sdft_ray ray)
{
    sdft_ray clipped;
    sdft_hit miss;
    if (march_clip(0u, ray, clipped, miss) == 0)
        return miss;
    return march_one(0u, acc, clipped, frame.trace, METHOD, METHOD);
}

/* The direction of the ray through image point (px, py). */
vec3 view_dir(float px, float py)
{
    return render_view_dir(frame.top_left, frame.right_per_px, frame.down_per_px, px, py);
}

/* render.c's rect_sees_box for the 16 x 16 tile whose first pixel is
 * (x0, y0). */
bool tile_sees_box(int x0, int y0)
{
    const float x1 = float(min(x0 + 16, frame.width)), y1 = float(min(y0 + 16, frame.height));
    const vec3 c = sdft_normalize(sdft_madd(sdft_madd(frame.top_left, frame.right_per_px, 0.5f * (float(x0) + x1)),
                                            frame.down_per_px, 0.5f * (float(y0) + y1)));
    vec3 d[4];
    for (int k = 0; k < 4; k++) {
        const float px = (k == 1 || k == 2) ? x1 : float(x0), py = k >= 2 ? y1 : float(y0);
        d[k] = sdft_normalize(sdft_madd(sdft_madd(frame.top_left, frame.right_per_px, px), frame.down_per_px, py));
    }
    return render_rect_sees_box(frame.from, d, c, frame.bounds) != 0;
}

/* The pixel's span of the hull boxes binned to its tile (render_hull_spans
 * for one pixel): [in, out], or false when its ray meets none. */
bool hull_span(int x, int y, int tile, vec3 dir, out float in_t, out float out_t)
{
    const float ix = render_slope(dir.x), iy = render_slope(dir.y), iz = render_slope(dir.z);
    const vec3 o = frame.from;
    in_t = INFINITY;
    out_t = -INFINITY;
    for (uint j = frame.bin_first.data[tile]; j < frame.bin_first.data[tile + 1]; j++) {
        const uint b = frame.bin_box.data[j];
        const int r0 = int(frame.bin_rect.data[4u * b]), r1 = int(frame.bin_rect.data[4u * b + 1u]);
        const int r2 = int(frame.bin_rect.data[4u * b + 2u]), r3 = int(frame.bin_rect.data[4u * b + 3u]);
        if (x < r0 || x > r2 || y < r1 || y > r3)
            continue;
        const sdft_aabb box = frame.hull.data[b];
        const float lo[3] = {box.lo.x - o.x, box.lo.y - o.y, box.lo.z - o.z};
        const float hi[3] = {box.hi.x - o.x, box.hi.y - o.y, box.hi.z - o.z};
        sdft_slab sl;
        if (frame.has_slabs != 0) {
            sl = frame.hull_slabs.data[b];
        } else {
            sl.n = vec3(0.0f, 0.0f, 0.0f);
            sl.lo = -INFINITY;
            sl.hi = INFINITY;
        }
        const float on = sdft_dot(sl.n, o), slo = sl.lo - on, shi = sl.hi - on;
        render_hull_box_span(lo, hi, sl.n, slo, shi, ix, iy, iz, dir.x, dir.y, dir.z, in_t, out_t);
    }
    return in_t <= out_t;
}

/* The pixel as render.c makes it: the primary ray traced over its span
 * (a miss untraced where its tile sees neither the box nor a hull box),
 * shaded, and the shadow ray to the light traced. One trace call in a
 * loop of the two rays, so that the driver, which inlines every call,
 * compiles the trace once. */
void main()
{
    const int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
    if (x >= frame.width || y >= frame.height)
        return;
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(acc, frame.grid.root);
    const vec3 dir = view_dir(float(x) + 0.5f, float(y) + 0.5f);
    const int tile = (y / 16) * frame.tiles_x + x / 16;

    gpu_pixel px;
    px.depth = INFINITY;
    px.normal[0] = 0.0f;
    px.normal[1] = 0.0f;
    px.normal[2] = 0.0f;
    px.steps = 0u;
    px.fallbacks = 0u;
    px.shadow_steps = 0u;
    px.rays = 1u;

    /* Where the primary ray is traced: its span of the hull, or from the
     * box's distance on. */
    sdft_ray ray;
    ray.org = frame.from;
    ray.dir = dir;
    ray.tnear = frame.cone_tnear;
    ray.tfar = INFINITY;
    bool traced = tile_sees_box((x / 16) * 16, (y / 16) * 16);
    if (traced && frame.has_bins != 0)
        traced = frame.bin_first.data[tile] != frame.bin_first.data[tile + 1] &&
                 hull_span(x, y, tile, dir, ray.tnear, ray.tfar);
    vec3 rgb = render_sky(frame.depth_only, dir.y);
    [[dont_unroll]] for (int pass = 0; pass < 2; pass++) {
        sdft_hit h;
        h.t = INFINITY;
        h.status = SDFT_MISS;
        h.steps = 0u;
        h.fallbacks = 0u;
        h.normal = vec3(0.0f, 0.0f, 0.0f);
        if (traced)
            h = trace(acc, ray);
        px.steps += h.steps;
        px.fallbacks += h.fallbacks;
        if (pass == 1) { /* the shadow ray */
            px.shadow_steps += h.steps;
            px.rays++;
            if (h.status == SDFT_HIT)
                rgb = render_lit(0.0f);
            break;
        }
        px.primary_steps = h.steps;
        px.primary_fallbacks = h.fallbacks;
        px.status = uint(h.status);
        /* A non-converged ray is shaded as a hit only with the screen-space
         * criterion, whose best candidate is meant to be used (Keinert §3.2). */
        const bool surface =
            h.status == SDFT_HIT || (h.status == SDFT_NOT_CONVERGED && frame.trace.pixel_radius > 0.0f);
        if (!surface)
            break;
        px.depth = h.t;
        if (frame.depth_only != 0)
            break;
        const vec3 p = sdft_madd(ray.org, ray.dir, h.t);
        const vec3 n = render_facing_normal(
            render_has_normal(h.normal) ? h.normal : normal_of(0u, PNANOVDB_GRID_TYPE_FLOAT, acc, p), ray.dir);
        px.normal[0] = n.x;
        px.normal[1] = n.y;
        px.normal[2] = n.z;
        const vec3 l = sdft_normalize(sdft_sub(frame.light, p));
        const float diffuse = sdft_maxf(sdft_dot(n, l), 0.0f);
        rgb = render_lit(diffuse);
        sdft_ray shadow;
        if (!(diffuse > 0.0f && frame.shadows != 0 &&
              render_shadow_ray(p, n, render_shadow_lift(frame.trace, h.t, frame.feature), frame.light, shadow) != 0))
            break;
        ray = shadow;
        traced = true;
    }
    px.rgb[0] = rgb.x;
    px.rgb[1] = rgb.y;
    px.rgb[2] = rgb.z;
    frame.pixels.data[y * frame.width + x] = px;
}
