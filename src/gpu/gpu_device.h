/* sdftrace — the Vulkan component's device: what a device, its buffers,
 * its pipelines and one-off command buffers are to the renderer
 * (gpu_render.c), the grid upload (gpu_grid.c) and the bench's second
 * shader (bench/gpu_bench.c). Internal header. */
#ifndef SDFTRACE_GPU_DEVICE_H
#define SDFTRACE_GPU_DEVICE_H

#include <pthread.h>
#include <stddef.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "sdftrace/gpu.h"

/* A buffer with its memory, its device address (what the shader reads it
 * through) and, where its memory is the host's to see, its mapping. */
typedef struct gpu_buffer {
    VkBuffer buffer;
    VkDeviceMemory memory;
    VkDeviceSize size;
    VkDeviceAddress address;
    void *mapped; /* NULL: device memory only */
} gpu_buffer;

/* Where a buffer's memory lives: the device's own (for what the shader
 * reads often), or the host's, seen by both (for what the host writes once
 * or reads back). */
typedef enum gpu_place { GPU_ON_DEVICE, GPU_ON_HOST } gpu_place;

struct sdft_gpu {
    VkInstance instance;
    VkPhysicalDevice physical;
    VkDevice device;
    VkQueue queue;
    uint32_t family;
    VkPhysicalDeviceMemoryProperties memory;
    VkDeviceSize most_allocation;     /* maxMemoryAllocationSize */
    VkDeviceSize most_buffer;         /* maxBufferSize (Vulkan 1.3), else most_allocation */
    VkDeviceSize device_memory;       /* the largest device-local heap */
    double ns_per_tick;               /* timestampPeriod; 0: no timestamps on the queue */
    uint64_t tick_mask;               /* timestampValidBits' mask */
    VkDescriptorSetLayout set_layout; /* one uniform buffer: the frame */
    VkPipelineLayout layout;
    VkShaderModule trace_module;
    VkPipeline trace[SDFT_METHOD_COUNT]; /* made on first use */
    pthread_mutex_t lock;                /* the queue and the pipelines */
    char name[VK_MAX_PHYSICAL_DEVICE_NAME_SIZE];
};

/* One line for a Vulkan failure: "what: VK_ERROR_...". SDFT_ENOMEM for the
 * out-of-memory results, else SDFT_EINTERNAL. */
sdft_error gpu_fail(char *msg, size_t msg_len, VkResult r, const char *what);

/* A buffer of `size` bytes for `usage` (the device address is added), at
 * `place`; SDFT_OK or an error with msg. */
sdft_error gpu_buffer_create(sdft_gpu *gpu, VkDeviceSize size, VkBufferUsageFlags usage, gpu_place place,
                             gpu_buffer *out, char *msg, size_t msg_len);
void gpu_buffer_free(sdft_gpu *gpu, gpu_buffer *b);

/* A buffer on the device holding `size` bytes of data (at least 4, so that
 * an empty table still has an address), copied through host memory in
 * pieces. */
sdft_error gpu_buffer_upload(sdft_gpu *gpu, const void *data, VkDeviceSize size, gpu_buffer *out, char *msg,
                             size_t msg_len);

/* A command buffer recorded by the caller between gpu_commands_begin and
 * gpu_commands_run, which submits it, waits for it and frees it. */
typedef struct gpu_commands {
    VkCommandPool pool;
    VkCommandBuffer buffer;
} gpu_commands;
sdft_error gpu_commands_begin(sdft_gpu *gpu, gpu_commands *c, char *msg, size_t msg_len);
sdft_error gpu_commands_run(sdft_gpu *gpu, gpu_commands *c, char *msg, size_t msg_len);

/* A shader module from SPIR-V `code`, `bytes` long; a compute pipeline of
 * it over the frame's layout (one uniform buffer), its specialization
 * constant 0 set to `constant`. */
sdft_error gpu_module_create(sdft_gpu *gpu, const uint32_t *code, size_t bytes, VkShaderModule *out, char *msg,
                             size_t msg_len);
sdft_error gpu_pipeline_create(sdft_gpu *gpu, VkShaderModule module, int32_t constant, VkPipeline *out, char *msg,
                               size_t msg_len);

/* One frame's dispatch of `pipeline` over a width x height image in 8 x 8
 * groups, `frame` (frame_bytes long) its uniform buffer; the pixels it
 * writes are copied from `pixels` to `readback` (host memory) after it. */
typedef struct gpu_dispatch {
    VkPipeline pipeline;
    const void *frame;
    size_t frame_bytes;
    int width, height;
    gpu_buffer *pixels, *readback;
} gpu_dispatch;

/* Runs one frame: the frame's uniform buffer and descriptor set made for
 * it, the dispatch between two timestamps, the copy back, and the wait.
 * *ms: the GPU's time between the timestamps, or the host's around the
 * submission where the queue has none. */
sdft_error gpu_dispatch_run(sdft_gpu *gpu, const gpu_dispatch *d, double *ms, char *msg, size_t msg_len);

#endif
