/* sdftrace — a grid uploaded to a device (gpu_grid.c), as the renderer
 * (gpu_render.c) reads it. Internal header. */
#ifndef SDFTRACE_GPU_GRID_H
#define SDFTRACE_GPU_GRID_H

#include "gpu_device.h"
#include "gpu_frame.h"
#include "grid_internal.h"

enum { GPU_GRID_TABLES = 6 };

struct sdft_gpu_grid {
    sdft_gpu *gpu;
    const sdft_grid *grid; /* must outlive it: the renderer bins its hull and looks at the eye with its field */
    sdft_field field;      /* sdft_grid_field(grid, SDFT_GRID_BOUND_FAR): what the shader samples */
    gpu_buffer tables[GPU_GRID_TABLES];
    grid_shape shape;
    VkDeviceAddress hull, slabs; /* the hull's boxes and slabs; slabs 0: none */
};

#endif
