/* bench/gpu_bench's second shader: NanoVDB's own level-set ray caster,
 * PNanoVDB's GLSL pnanovdb_hdda_zero_crossing (a hierarchical DDA that
 * skips empty tiles and stops at the first sign change between active
 * voxels), one invocation a pixel, on the frame and grid the library's
 * trace shader gets (src/gpu/gpu_frame.glsl), as bench/hdda_caster.c casts
 * on the CPU: the world ray taken to index space, the voxel-granular hit's
 * index t over the direction's length its depth. Primary rays only. */
#version 450
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_GOOGLE_include_directive : require

#define SDFT_GLSL
#include "gpu_frame.glsl"
#include "render_pixel.h"

layout(local_size_x = 8, local_size_y = 8) in;

void main()
{
    const int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
    if (x >= frame.width || y >= frame.height)
        return;
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(acc, frame.grid.root);
    const vec3 dir = render_view_dir(frame.top_left, frame.right_per_px, frame.down_per_px, float(x) + 0.5f,
                                     float(y) + 0.5f);
    const vec3 from = frame.from;
    vec3 o, d;
    for (int k = 0; k < 3; k++) {
        const float m0 = frame.grid.w2i[3 * k], m1 = frame.grid.w2i[3 * k + 1], m2 = frame.grid.w2i[3 * k + 2];
        o[k] = m0 * from.x + m1 * from.y + m2 * from.z + frame.grid.w2i_t[k];
        d[k] = m0 * dir.x + m1 * dir.y + m2 * dir.z;
    }
    const float len = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    d /= len;
    float t_hit = 0.0f, v = 0.0f;
    const bool hit = pnanovdb_hdda_zero_crossing(PNANOVDB_GRID_TYPE_FLOAT, frame.grid.buf, acc, o, 0.0f, d, 1e19f, t_hit, v);
    gpu_pixel px;
    px.rgb[0] = 0.0f;
    px.rgb[1] = 0.0f;
    px.rgb[2] = 0.0f;
    px.depth = hit ? t_hit / len : INFINITY;
    px.normal[0] = 0.0f;
    px.normal[1] = 0.0f;
    px.normal[2] = 0.0f;
    px.steps = 0u;
    px.fallbacks = 0u;
    px.primary_steps = 0u;
    px.primary_fallbacks = 0u;
    px.shadow_steps = 0u;
    px.status = hit ? SDFT_HIT : SDFT_MISS;
    px.rays = 1u;
    frame.pixels.data[y * frame.width + x] = px;
}
