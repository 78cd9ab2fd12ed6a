/* sdftrace — rendering NanoVDB float grids on a GPU: the Vulkan component
 * (libsdftrace_gpu, built where Vulkan and glslc are found;
 * SDFT_WITH_VULKAN). Its compute shader traces with the library's own
 * code, the same variants, sampling, bounds, exact root, screen-space
 * criterion and shadow rays as sdft_render, compiled for the GPU from the
 * same source; so its images and counts agree with sdft_render's on the
 * same grid (the GPU's division and square root may round otherwise: a
 * hit's depth then differs in its last bits, a pixel at a silhouette can
 * go the other way).
 *
 * Two handles, each with a create / release life (Open VKL's): an
 * sdft_gpu is a Vulkan device, its queue and its pipelines; an
 * sdft_gpu_grid a grid uploaded to it (the NanoVDB buffer as it is, its
 * leaf directory, its far bound and its hull). The sdft_grid must outlive
 * its uploaded copy: each frame bins its hull on the host. Every function
 * is thread-safe: the device serializes its queue, and a frame's buffers
 * are its own. Errors follow sdftrace/error.h; nothing here
 * prints. */
#ifndef SDFTRACE_GPU_H
#define SDFTRACE_GPU_H

#include <stddef.h>

#include "grid.h"
#include "render.h"
#include "sdftrace/config.h"
#include "sdftrace/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sdft_gpu sdft_gpu;
typedef struct sdft_gpu_grid sdft_gpu_grid;

/* Which device. It will grow: make one with sdft_gpu_options_defaults()
 * and set what you change. */
typedef struct sdft_gpu_options {
    int device; /* the index of a Vulkan device, as vulkaninfo lists them; -1: the first discrete GPU, else the
                 * first integrated one, else the first device of any kind (a CPU's: lavapipe) [-1] */
    size_t memory_budget; /* most bytes of device memory a grid and its tables may take (a share of a GPU
                           * that others use too); 0: the device's largest memory heap [0] */
} sdft_gpu_options;

SDFT_API sdft_gpu_options sdft_gpu_options_defaults(void);

/* Opens a Vulkan device for rendering into *out (free it with
 * sdft_gpu_release). SDFT_EINVAL (NULL o or out, a device index out of
 * range), SDFT_ENOTFOUND (no Vulkan driver or no device), SDFT_EFORMAT (the
 * device lacks what the shader needs: buffer device addresses, the scalar
 * block layout, 64-bit floats), SDFT_ENOMEM, SDFT_EINTERNAL (another
 * Vulkan failure, named in msg). */
SDFT_API sdft_error sdft_gpu_create(const sdft_gpu_options *o, sdft_gpu **out, char *msg, size_t msg_len);

/* The device's name (e.g. "NVIDIA H100 80GB HBM3", "llvmpipe (LLVM 15.0.6,
 * 256 bits)"); owned by gpu. */
SDFT_API const char *sdft_gpu_device_name(const sdft_gpu *gpu);

/* Frees the device; NULL is fine. Its grids must be released first. */
SDFT_API void sdft_gpu_release(sdft_gpu *gpu);

/* Uploads grid g to the device into *out (free it with
 * sdft_gpu_grid_release, before g). A deferred grid's
 * leaves are all read first (sdft_grid_data). SDFT_EINVAL (a NULL
 * argument), SDFT_ENOTSCALAR (not a float grid: the GPU renders float
 * grids; a .vdb is loaded as float unless asked otherwise), SDFT_ENOMEM
 * (the grid and its tables do not fit the device: more than its memory or
 * the options' memory_budget, a buffer above its largest, or a grid above
 * 4 GiB, which the shader's 32-bit addresses cannot reach), SDFT_EINTERNAL. */
SDFT_API sdft_error sdft_gpu_grid_create(sdft_gpu *gpu, const sdft_grid *g, sdft_gpu_grid **out, char *msg,
                                         size_t msg_len);

/* Frees an uploaded grid; NULL is fine. */
SDFT_API void sdft_gpu_grid_release(sdft_gpu_grid *gg);

/* Renders the uploaded grid into img, allocated at params' size, as
 * sdft_render renders the grid's field with SDFT_GRID_BOUND_FAR (the
 * variant, screen-space criterion, exact root, hard shadows, depth only,
 * the hull with `cones`; not the Whitted shading: materials, dynamic eps,
 * smoothing, soft shadows and occlusion are refused). stats->ms is the
 * GPU's time for the frame's dispatch (its timestamps), the rest as
 * sdft_render's. One invocation a pixel, in groups of 8 x 8. SDFT_EINVAL
 * (as sdft_render, and shading the GPU does not do), SDFT_ENOMEM,
 * SDFT_EINTERNAL (a Vulkan failure, the device lost). */
SDFT_API sdft_error sdft_gpu_render(sdft_gpu_grid *gg, const sdft_render_params *params, sdft_image *img,
                                    sdft_render_stats *stats, char *msg, size_t msg_len);

#ifdef __cplusplus
}
#endif
#endif
