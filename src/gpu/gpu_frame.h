/* sdftrace — what the Vulkan renderer's host side (gpu_render.c) hands its
 * compute shader (trace.comp) for a frame, and what the shader writes back
 * per pixel: plain structs, declared once here for both (portable.h), laid
 * out alike by C and by GLSL's scalar block layout (members in C's order,
 * each at its own alignment: 8 for a buffer's device address, 4 for the
 * rest). The shader sees each table as a buffer reference, the host as its
 * device address. */
#ifndef SDFTRACE_GPU_FRAME_H
#define SDFTRACE_GPU_FRAME_H

#include "portable.h"

#if defined(SDFT_GLSL)
#define GPU_REF(T) T
#define GPU_ROOT pnanovdb_root_handle_t
#else
#define GPU_REF(T) uint64_t
#define GPU_ROOT uint32_t /* the root's byte offset in the grid */
#endif

/* The grid as the portable sampler reads it (grid_layout.h): the members
 * of sdft_grid it reads, under the same names, and its tables. */
struct grid_leaves_shape {
    int32_t r0[3]; /* first region, in regions (index >> 6) */
    int32_t nr[3]; /* regions per axis */
};
PORT_TYPEDEF(grid_leaves_shape)

struct grid_far_shape {
    int32_t n[3];    /* cells per axis */
    int32_t cell;    /* voxels per cell edge */
    float inv_cell;  /* 1 / cell */
    float origin[3]; /* index coordinates of corner 0 */
    float bonus;     /* world units added: the band's guarantee */
};
PORT_TYPEDEF(grid_far_shape)

struct grid_shape {
    GPU_REF(pnanovdb_buf_t) buf;   /* the NanoVDB grid, 32-bit words */
    GPU_REF(gpu_words) top;        /* the leaf directory's top table and chunks (grid_leaves.c) */
    GPU_REF(gpu_words) chunk;      /* (both empty: has_directory 0) */
    GPU_REF(gpu_words) far_corner; /* the far bound's corner words, 16 bits each, two a word */
    GPU_ROOT root;
    float w2i[9], w2i_t[3]; /* index = w2i * world + w2i_t */
    int32_t diagonal;
    float sigma_min, sigma_max, background;
    int32_t has_directory, has_far;
    grid_leaves_shape leaves;
    grid_far_shape far;
};
PORT_TYPEDEF(grid_shape)

/* One frame: the grid, the hull's boxes binned to the image's 16 x 16
 * tiles (render_hull.h's hull_bins, has_bins 0: none), where the pixels
 * go, and the render's parameters. */
struct gpu_frame {
    grid_shape grid;
    GPU_REF(gpu_words) bin_first; /* tiles + 1 */
    GPU_REF(gpu_words) bin_box;
    GPU_REF(gpu_words) bin_rect; /* 4 int32 a box: its pixel rectangle, inclusive */
    GPU_REF(gpu_boxes) hull;
    GPU_REF(gpu_slabs) hull_slabs;                       /* has_slabs 0: none */
    GPU_REF(gpu_pixels) pixels;                          /* width x height, rows top down */
    sdft_trace_params trace;                             /* pixel_radius set for the screen-space criterion */
    sdft_aabb bounds;                                    /* the field's: rays are clipped to it */
    sdft_vec3 from, right_per_px, down_per_px, top_left; /* sdft_view */
    sdft_vec3 light;
    float feature;    /* the normal's step: the smallest voxel edge */
    float cone_tnear; /* the eye's distance to the box: where rays start without the hull */
    float root_reach; /* the exact root's reach, world units */
    int32_t width, height, tiles_x;
    int32_t shadows, depth_only, bound, has_bins, has_slabs;
};
PORT_TYPEDEF(gpu_frame)

/* What the shader writes for a pixel: sdft_image's planes and the counts
 * sdft_render_stats sums. */
struct gpu_pixel {
    float rgb[3];
    float depth;
    float normal[3];
    uint32_t steps, fallbacks, primary_steps, primary_fallbacks, shadow_steps;
    uint32_t status; /* sdft_status of the primary ray */
    uint32_t rays;   /* primary + shadow */
};
PORT_TYPEDEF(gpu_pixel)

#endif
