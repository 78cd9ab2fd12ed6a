/* sdftrace — what the Vulkan component's shaders share (GLSL only): the
 * frame's uniform block (gpu_frame.h) and its tables by device address,
 * and PNanoVDB.h over the grid's buffer reference. The including shader
 * defines SDFT_GLSL and enables GL_EXT_buffer_reference and
 * GL_EXT_scalar_block_layout first. */
#ifndef SDFTRACE_GPU_FRAME_GLSL
#define SDFTRACE_GPU_FRAME_GLSL

#include "portable.h"

/* The tables, by device address. */
layout(buffer_reference) buffer pnanovdb_buf_t;
layout(buffer_reference) buffer gpu_words;
layout(buffer_reference) buffer gpu_boxes;
layout(buffer_reference) buffer gpu_slabs;
layout(buffer_reference) buffer gpu_pixels;
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly restrict buffer pnanovdb_buf_t { uint data[]; };

/* PNanoVDB.h over a buffer reference (32-bit byte offsets: grids under 4
 * GiB, which the host checks). */
#define PNANOVDB_GLSL
#define PNANOVDB_BUF_CUSTOM
uint pnanovdb_buf_read_uint32(pnanovdb_buf_t buf, uint byte_offset) { return buf.data[byte_offset >> 2u]; }
uvec2 pnanovdb_buf_read_uint64(pnanovdb_buf_t buf, uint byte_offset)
{
    return uvec2(buf.data[byte_offset >> 2u], buf.data[(byte_offset >> 2u) + 1u]);
}
#define pnanovdb_grid_type_t uint
#define PNANOVDB_GRID_TYPE_GET(grid_typeIn, nameIn) pnanovdb_grid_type_constants[grid_typeIn].nameIn
#include <nanovdb/PNanoVDB.h>

#include "gpu_frame.h"

layout(buffer_reference, scalar, buffer_reference_align = 4) readonly restrict buffer gpu_words { uint data[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly restrict buffer gpu_boxes { sdft_aabb data[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly restrict buffer gpu_slabs { sdft_slab data[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) writeonly restrict buffer gpu_pixels { gpu_pixel data[]; };

layout(scalar, set = 0, binding = 0) uniform frame_block { gpu_frame frame; };

#endif
