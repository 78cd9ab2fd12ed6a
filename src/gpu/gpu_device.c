/* sdftrace — the Vulkan component's device: choosing and opening a device
 * with what the shader needs (Vulkan 1.2's buffer device addresses and
 * scalar block layout, 64-bit floats for the exact root), buffers by
 * device address, pipelines from the SPIR-V the build embeds, and one-off
 * submissions. One mutex per device guards its queue and its pipelines;
 * everything else a call makes is its own. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fail.h"
#include "gpu_device.h"

/* The compute shader, compiled to SPIR-V by glslc at build time
 * (CMakeLists.txt): its words, as glslc -mfmt=c writes them. */
static const uint32_t trace_spirv[] =
#include "trace.spv.inc"
    ;

static const char *result_name(VkResult r)
{
    switch (r) {
    case VK_ERROR_OUT_OF_HOST_MEMORY:
        return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
        return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED:
        return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST:
        return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED:
        return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT:
        return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT:
        return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT:
        return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
        return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS:
        return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_OUT_OF_POOL_MEMORY:
        return "VK_ERROR_OUT_OF_POOL_MEMORY";
    case VK_TIMEOUT:
        return "VK_TIMEOUT";
    default:
        return "a Vulkan error";
    }
}

sdft_error gpu_fail(char *msg, size_t msg_len, VkResult r, const char *what)
{
    const sdft_error e =
        r == VK_ERROR_OUT_OF_HOST_MEMORY || r == VK_ERROR_OUT_OF_DEVICE_MEMORY ? SDFT_ENOMEM : SDFT_EINTERNAL;
    return fail_with(msg, msg_len, e, "%s: %s (%d)", what, result_name(r), (int)r);
}

sdft_gpu_options sdft_gpu_options_defaults(void) { return (sdft_gpu_options){.device = -1}; }

/* The device o asks for: its index, or the first discrete GPU, else the
 * first integrated one, else the first. */
static int choose_device(const VkPhysicalDevice *devices, uint32_t n, int wanted)
{
    if (wanted >= 0)
        return wanted < (int)n ? wanted : -1;
    static const VkPhysicalDeviceType preference[] = {VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU,
                                                      VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU};
    for (int k = 0; k < 2; k++)
        for (uint32_t i = 0; i < n; i++) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(devices[i], &p);
            if (p.deviceType == preference[k])
                return (int)i;
        }
    return n ? 0 : -1;
}

/* What the shader needs that device d lacks, or NULL. */
static const char *lacking(VkPhysicalDevice d)
{
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    if (p.apiVersion < VK_API_VERSION_1_2)
        return "Vulkan 1.2";
    VkPhysicalDeviceVulkan12Features v12 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 f = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &v12};
    vkGetPhysicalDeviceFeatures2(d, &f);
    if (!v12.bufferDeviceAddress)
        return "buffer device addresses";
    if (!v12.scalarBlockLayout)
        return "the scalar block layout";
    if (!f.features.shaderFloat64)
        return "64-bit floats in shaders (the exact root and the normals use them)";
    return NULL;
}

/* A queue family that computes, or UINT32_MAX. */
static uint32_t compute_family(VkPhysicalDevice d, uint32_t *tick_bits)
{
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &n, NULL);
    VkQueueFamilyProperties q[64];
    n = n < 64 ? n : 64;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &n, q);
    for (uint32_t i = 0; i < n; i++)
        if (q[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
            *tick_bits = q[i].timestampValidBits;
            return i;
        }
    return UINT32_MAX;
}

static sdft_error pick_device(sdft_gpu *gpu, int wanted, char *msg, size_t msg_len)
{
    uint32_t n = 0;
    VkResult r = vkEnumeratePhysicalDevices(gpu->instance, &n, NULL);
    if (r != VK_SUCCESS)
        return gpu_fail(msg, msg_len, r, "listing the Vulkan devices");
    if (n == 0)
        return fail_with(msg, msg_len, SDFT_ENOTFOUND,
                         "no Vulkan device (install a driver; mesa-vulkan-drivers has "
                         "lavapipe, a CPU device)");
    VkPhysicalDevice devices[64];
    n = n < 64 ? n : 64;
    vkEnumeratePhysicalDevices(gpu->instance, &n, devices);
    const int i = choose_device(devices, n, wanted);
    if (i < 0)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no Vulkan device %d: there are %u (0 to %u)", wanted, n, n - 1);
    gpu->physical = devices[i];
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(gpu->physical, &p);
    snprintf(gpu->name, sizeof gpu->name, "%s", p.deviceName);
    const char *why = lacking(gpu->physical);
    if (why)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "Vulkan device %d (%s) lacks %s", i, gpu->name, why);
    uint32_t tick_bits = 0;
    gpu->family = compute_family(gpu->physical, &tick_bits);
    if (gpu->family == UINT32_MAX)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "Vulkan device %d (%s) has no compute queue", i, gpu->name);
    gpu->ns_per_tick = tick_bits ? (double)p.limits.timestampPeriod : 0.0;
    gpu->tick_mask = tick_bits >= 64 ? UINT64_MAX : (UINT64_C(1) << tick_bits) - 1;
    vkGetPhysicalDeviceMemoryProperties(gpu->physical, &gpu->memory);
    for (uint32_t h = 0; h < gpu->memory.memoryHeapCount; h++)
        if ((gpu->memory.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) &&
            gpu->memory.memoryHeaps[h].size > gpu->device_memory)
            gpu->device_memory = gpu->memory.memoryHeaps[h].size;
    VkPhysicalDeviceMaintenance3Properties m3 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceMaintenance4Properties m4 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_4_PROPERTIES};
    if (p.apiVersion >= VK_API_VERSION_1_3)
        m3.pNext = &m4;
    VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &m3};
    vkGetPhysicalDeviceProperties2(gpu->physical, &p2);
    gpu->most_allocation = m3.maxMemoryAllocationSize;
    gpu->most_buffer = m4.maxBufferSize ? m4.maxBufferSize : m3.maxMemoryAllocationSize;
    return SDFT_OK;
}

static sdft_error open_device(sdft_gpu *gpu, char *msg, size_t msg_len)
{
    const float priority = 1.0f;
    const VkDeviceQueueCreateInfo queue = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                                           .queueFamilyIndex = gpu->family,
                                           .queueCount = 1,
                                           .pQueuePriorities = &priority};
    VkPhysicalDeviceVulkan12Features v12 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
                                            .bufferDeviceAddress = VK_TRUE,
                                            .scalarBlockLayout = VK_TRUE};
    VkPhysicalDeviceFeatures2 features = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &v12, .features = {.shaderFloat64 = VK_TRUE}};
    const VkDeviceCreateInfo info = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
                                     .pNext = &features,
                                     .queueCreateInfoCount = 1,
                                     .pQueueCreateInfos = &queue};
    VkResult r = vkCreateDevice(gpu->physical, &info, NULL, &gpu->device);
    if (r != VK_SUCCESS)
        return gpu_fail(msg, msg_len, r, "opening the Vulkan device");
    vkGetDeviceQueue(gpu->device, gpu->family, 0, &gpu->queue);
    const VkDescriptorSetLayoutBinding frame = {.binding = 0,
                                                .descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                                                .descriptorCount = 1,
                                                .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT};
    const VkDescriptorSetLayoutCreateInfo set = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO, .bindingCount = 1, .pBindings = &frame};
    if ((r = vkCreateDescriptorSetLayout(gpu->device, &set, NULL, &gpu->set_layout)) != VK_SUCCESS)
        return gpu_fail(msg, msg_len, r, "the frame's descriptor set layout");
    const VkPipelineLayoutCreateInfo layout = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, .setLayoutCount = 1, .pSetLayouts = &gpu->set_layout};
    if ((r = vkCreatePipelineLayout(gpu->device, &layout, NULL, &gpu->layout)) != VK_SUCCESS)
        return gpu_fail(msg, msg_len, r, "the pipeline layout");
    return gpu_module_create(gpu, trace_spirv, sizeof trace_spirv, &gpu->trace_module, msg, msg_len);
}

sdft_error sdft_gpu_create(const sdft_gpu_options *o, sdft_gpu **out, char *msg, size_t msg_len)
{
    if (!out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_gpu_create: no place for the device (out is NULL)");
    *out = NULL;
    if (!o)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_gpu_create: no options (NULL)");
    if (o->device < -1)
        return fail_with(msg, msg_len, SDFT_EINVAL, "Vulkan device %d: an index >= 0, or -1 to choose", o->device);
    sdft_gpu *gpu = calloc(1, sizeof *gpu);
    if (!gpu)
        return fail_with(msg, msg_len, SDFT_ENOMEM, "out of memory for a Vulkan device");
    pthread_mutex_init(&gpu->lock, NULL);
    const VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                                   .pApplicationName = "sdftrace",
                                   .pEngineName = "sdftrace",
                                   .apiVersion = VK_API_VERSION_1_2};
    const VkInstanceCreateInfo info = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, .pApplicationInfo = &app};
    VkResult r = vkCreateInstance(&info, NULL, &gpu->instance);
    sdft_error rc;
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
        rc = fail_with(msg, msg_len, SDFT_ENOTFOUND,
                       "no Vulkan driver (%s; install one: mesa-vulkan-drivers has lavapipe, a CPU device)",
                       result_name(r));
    else if (r != VK_SUCCESS)
        rc = gpu_fail(msg, msg_len, r, "starting Vulkan");
    else if ((rc = pick_device(gpu, o->device, msg, msg_len)) == SDFT_OK)
        rc = open_device(gpu, msg, msg_len);
    if (!rc && o->memory_budget && o->memory_budget < gpu->device_memory)
        gpu->device_memory = o->memory_budget;
    if (rc) {
        sdft_gpu_release(gpu);
        return rc;
    }
    *out = gpu;
    return SDFT_OK;
}

const char *sdft_gpu_device_name(const sdft_gpu *gpu) { return gpu ? gpu->name : ""; }

void sdft_gpu_release(sdft_gpu *gpu)
{
    if (!gpu)
        return;
    if (gpu->device) {
        vkDeviceWaitIdle(gpu->device);
        for (int m = 0; m < SDFT_METHOD_COUNT; m++)
            vkDestroyPipeline(gpu->device, gpu->trace[m], NULL);
        vkDestroyShaderModule(gpu->device, gpu->trace_module, NULL);
        vkDestroyPipelineLayout(gpu->device, gpu->layout, NULL);
        vkDestroyDescriptorSetLayout(gpu->device, gpu->set_layout, NULL);
        vkDestroyDevice(gpu->device, NULL);
    }
    if (gpu->instance)
        vkDestroyInstance(gpu->instance, NULL);
    pthread_mutex_destroy(&gpu->lock);
    free(gpu);
}

/* The first memory type of `bits` with all of `need`, preferring one that
 * has `want` too; UINT32_MAX when none. */
static uint32_t memory_type(const sdft_gpu *gpu, uint32_t bits, VkMemoryPropertyFlags need, VkMemoryPropertyFlags want)
{
    uint32_t found = UINT32_MAX;
    for (uint32_t i = 0; i < gpu->memory.memoryTypeCount; i++) {
        const VkMemoryPropertyFlags f = gpu->memory.memoryTypes[i].propertyFlags;
        if (!(bits & (1u << i)) || (f & need) != need)
            continue;
        if ((f & want) == want)
            return i;
        if (found == UINT32_MAX)
            found = i;
    }
    return found;
}

sdft_error gpu_buffer_create(sdft_gpu *gpu, VkDeviceSize size, VkBufferUsageFlags usage, gpu_place place,
                             gpu_buffer *out, char *msg, size_t msg_len)
{
    *out = (gpu_buffer){.size = size};
    if (size > gpu->most_buffer || size > gpu->most_allocation)
        return fail_with(msg, msg_len, SDFT_ENOMEM, "a buffer of %.1f MiB is more than %s allows in one (%.1f MiB)",
                         (double)size / 1048576.0, gpu->name,
                         (double)(gpu->most_buffer < gpu->most_allocation ? gpu->most_buffer : gpu->most_allocation) /
                             1048576.0);
    const VkBufferCreateInfo info = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                                     .size = size,
                                     .usage = usage | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                     .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
    VkResult r = vkCreateBuffer(gpu->device, &info, NULL, &out->buffer);
    if (r != VK_SUCCESS)
        return gpu_fail(msg, msg_len, r, "creating a buffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(gpu->device, out->buffer, &req);
    const VkMemoryPropertyFlags host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    const uint32_t type = place == GPU_ON_HOST
                              ? memory_type(gpu, req.memoryTypeBits, host, VK_MEMORY_PROPERTY_HOST_CACHED_BIT)
                              : memory_type(gpu, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0);
    if (type == UINT32_MAX) {
        gpu_buffer_free(gpu, out);
        return fail_with(msg, msg_len, SDFT_EINTERNAL, "%s has no memory for such a buffer", gpu->name);
    }
    const VkMemoryAllocateFlagsInfo flags = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO,
                                             .flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT};
    const VkMemoryAllocateInfo alloc = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                        .pNext = &flags,
                                        .allocationSize = req.size,
                                        .memoryTypeIndex = type};
    if ((r = vkAllocateMemory(gpu->device, &alloc, NULL, &out->memory)) != VK_SUCCESS) {
        gpu_buffer_free(gpu, out);
        return gpu_fail(msg, msg_len, r, "allocating a buffer's memory");
    }
    if ((r = vkBindBufferMemory(gpu->device, out->buffer, out->memory, 0)) != VK_SUCCESS ||
        (place == GPU_ON_HOST && (r = vkMapMemory(gpu->device, out->memory, 0, VK_WHOLE_SIZE, 0, &out->mapped)))) {
        gpu_buffer_free(gpu, out);
        return gpu_fail(msg, msg_len, r, "binding a buffer's memory");
    }
    const VkBufferDeviceAddressInfo at = {.sType = VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO, .buffer = out->buffer};
    out->address = vkGetBufferDeviceAddress(gpu->device, &at);
    return SDFT_OK;
}

void gpu_buffer_free(sdft_gpu *gpu, gpu_buffer *b)
{
    if (b->mapped)
        vkUnmapMemory(gpu->device, b->memory);
    vkDestroyBuffer(gpu->device, b->buffer, NULL);
    vkFreeMemory(gpu->device, b->memory, NULL);
    *b = (gpu_buffer){0};
}

sdft_error gpu_commands_begin(sdft_gpu *gpu, gpu_commands *c, char *msg, size_t msg_len)
{
    *c = (gpu_commands){0};
    const VkCommandPoolCreateInfo pool = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                          .flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT,
                                          .queueFamilyIndex = gpu->family};
    VkResult r = vkCreateCommandPool(gpu->device, &pool, NULL, &c->pool);
    if (r != VK_SUCCESS)
        return gpu_fail(msg, msg_len, r, "creating a command pool");
    const VkCommandBufferAllocateInfo alloc = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                               .commandPool = c->pool,
                                               .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                               .commandBufferCount = 1};
    const VkCommandBufferBeginInfo begin = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                            .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    if ((r = vkAllocateCommandBuffers(gpu->device, &alloc, &c->buffer)) != VK_SUCCESS ||
        (r = vkBeginCommandBuffer(c->buffer, &begin)) != VK_SUCCESS) {
        vkDestroyCommandPool(gpu->device, c->pool, NULL);
        return gpu_fail(msg, msg_len, r, "starting a command buffer");
    }
    return SDFT_OK;
}

sdft_error gpu_commands_run(sdft_gpu *gpu, gpu_commands *c, char *msg, size_t msg_len)
{
    VkResult r = vkEndCommandBuffer(c->buffer);
    VkFence fence = VK_NULL_HANDLE;
    const VkFenceCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    if (r == VK_SUCCESS)
        r = vkCreateFence(gpu->device, &fi, NULL, &fence);
    if (r == VK_SUCCESS) {
        const VkSubmitInfo submit = {
            .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &c->buffer};
        pthread_mutex_lock(&gpu->lock);
        r = vkQueueSubmit(gpu->queue, 1, &submit, fence);
        pthread_mutex_unlock(&gpu->lock);
    }
    if (r == VK_SUCCESS)
        r = vkWaitForFences(gpu->device, 1, &fence, VK_TRUE, UINT64_MAX);
    vkDestroyFence(gpu->device, fence, NULL);
    vkDestroyCommandPool(gpu->device, c->pool, NULL);
    *c = (gpu_commands){0};
    return r == VK_SUCCESS ? SDFT_OK : gpu_fail(msg, msg_len, r, "running commands on the device");
}

/* Host memory in pieces of this many bytes carries an upload. */
#define UPLOAD_PIECE ((VkDeviceSize)64 << 20)

sdft_error gpu_buffer_upload(sdft_gpu *gpu, const void *data, VkDeviceSize size, gpu_buffer *out, char *msg,
                             size_t msg_len)
{
    const VkDeviceSize bytes = size < 4 ? 4 : size;
    sdft_error rc = gpu_buffer_create(gpu, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      GPU_ON_DEVICE, out, msg, msg_len);
    if (rc || size == 0)
        return rc;
    gpu_buffer stage;
    const VkDeviceSize piece = size < UPLOAD_PIECE ? size : UPLOAD_PIECE;
    if ((rc = gpu_buffer_create(gpu, piece, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GPU_ON_HOST, &stage, msg, msg_len))) {
        gpu_buffer_free(gpu, out);
        return rc;
    }
    for (VkDeviceSize at = 0; at < size && !rc; at += piece) {
        const VkDeviceSize n = size - at < piece ? size - at : piece;
        memcpy(stage.mapped, (const unsigned char *)data + at, n);
        gpu_commands c;
        if ((rc = gpu_commands_begin(gpu, &c, msg, msg_len)))
            break;
        const VkBufferCopy copy = {.srcOffset = 0, .dstOffset = at, .size = n};
        vkCmdCopyBuffer(c.buffer, stage.buffer, out->buffer, 1, &copy);
        rc = gpu_commands_run(gpu, &c, msg, msg_len);
    }
    gpu_buffer_free(gpu, &stage);
    if (rc)
        gpu_buffer_free(gpu, out);
    return rc;
}

sdft_error gpu_module_create(sdft_gpu *gpu, const uint32_t *code, size_t bytes, VkShaderModule *out, char *msg,
                             size_t msg_len)
{
    const VkShaderModuleCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO, .codeSize = bytes, .pCode = code};
    const VkResult r = vkCreateShaderModule(gpu->device, &info, NULL, out);
    return r == VK_SUCCESS ? SDFT_OK : gpu_fail(msg, msg_len, r, "loading the compute shader");
}

sdft_error gpu_pipeline_create(sdft_gpu *gpu, VkShaderModule module, int32_t constant, VkPipeline *out, char *msg,
                               size_t msg_len)
{
    const VkSpecializationMapEntry entry = {.constantID = 0, .offset = 0, .size = sizeof constant};
    const VkSpecializationInfo spec = {
        .mapEntryCount = 1, .pMapEntries = &entry, .dataSize = sizeof constant, .pData = &constant};
    const VkComputePipelineCreateInfo info = {.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
                                              .stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                                                        .stage = VK_SHADER_STAGE_COMPUTE_BIT,
                                                        .module = module,
                                                        .pName = "main",
                                                        .pSpecializationInfo = &spec},
                                              .layout = gpu->layout};
    const VkResult r = vkCreateComputePipelines(gpu->device, VK_NULL_HANDLE, 1, &info, NULL, out);
    return r == VK_SUCCESS ? SDFT_OK : gpu_fail(msg, msg_len, r, "compiling the compute shader");
}

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return 1e3 * (double)t.tv_sec + 1e-6 * (double)t.tv_nsec;
}

/* The frame's uniform buffer, bound through a descriptor set of its own. */
typedef struct frame_binding {
    gpu_buffer uniform;
    VkDescriptorPool pool;
    VkDescriptorSet set;
} frame_binding;

static sdft_error bind_frame(sdft_gpu *gpu, const void *frame, size_t bytes, frame_binding *b, char *msg,
                             size_t msg_len)
{
    sdft_error rc =
        gpu_buffer_create(gpu, bytes, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, GPU_ON_HOST, &b->uniform, msg, msg_len);
    if (rc)
        return rc;
    memcpy(b->uniform.mapped, frame, bytes);
    const VkDescriptorPoolSize size = {.type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, .descriptorCount = 1};
    const VkDescriptorPoolCreateInfo pool = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO, .maxSets = 1, .poolSizeCount = 1, .pPoolSizes = &size};
    VkResult r = vkCreateDescriptorPool(gpu->device, &pool, NULL, &b->pool);
    if (r != VK_SUCCESS)
        return gpu_fail(msg, msg_len, r, "creating a descriptor pool");
    const VkDescriptorSetAllocateInfo alloc = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
                                               .descriptorPool = b->pool,
                                               .descriptorSetCount = 1,
                                               .pSetLayouts = &gpu->set_layout};
    if ((r = vkAllocateDescriptorSets(gpu->device, &alloc, &b->set)) != VK_SUCCESS)
        return gpu_fail(msg, msg_len, r, "allocating a descriptor set");
    const VkDescriptorBufferInfo buffer = {.buffer = b->uniform.buffer, .offset = 0, .range = bytes};
    const VkWriteDescriptorSet write = {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                                        .dstSet = b->set,
                                        .dstBinding = 0,
                                        .descriptorCount = 1,
                                        .descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                                        .pBufferInfo = &buffer};
    vkUpdateDescriptorSets(gpu->device, 1, &write, 0, NULL);
    return SDFT_OK;
}

static void unbind_frame(sdft_gpu *gpu, frame_binding *b)
{
    vkDestroyDescriptorPool(gpu->device, b->pool, NULL);
    gpu_buffer_free(gpu, &b->uniform);
}

sdft_error gpu_dispatch_run(sdft_gpu *gpu, const gpu_dispatch *d, double *ms, char *msg, size_t msg_len)
{
    frame_binding b = {0};
    VkQueryPool queries = VK_NULL_HANDLE;
    gpu_commands c = {0};
    sdft_error rc = bind_frame(gpu, d->frame, d->frame_bytes, &b, msg, msg_len);
    if (!rc && gpu->ns_per_tick > 0.0) {
        const VkQueryPoolCreateInfo qi = {
            .sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO, .queryType = VK_QUERY_TYPE_TIMESTAMP, .queryCount = 2};
        const VkResult r = vkCreateQueryPool(gpu->device, &qi, NULL, &queries);
        if (r != VK_SUCCESS)
            rc = gpu_fail(msg, msg_len, r, "creating a timestamp query pool");
    }
    if (!rc)
        rc = gpu_commands_begin(gpu, &c, msg, msg_len);
    double t0 = 0.0;
    if (!rc) {
        VkCommandBuffer cb = c.buffer;
        if (queries) {
            vkCmdResetQueryPool(cb, queries, 0, 2);
            vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries, 0);
        }
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, d->pipeline);
        vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, gpu->layout, 0, 1, &b.set, 0, NULL);
        vkCmdDispatch(cb, (uint32_t)(d->width + 7) / 8, (uint32_t)(d->height + 7) / 8, 1);
        if (queries)
            vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries, 1);
        const VkMemoryBarrier written = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                                         .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                                         .dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT};
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &written,
                             0, NULL, 0, NULL);
        const VkBufferCopy copy = {.size = d->pixels->size};
        vkCmdCopyBuffer(cb, d->pixels->buffer, d->readback->buffer, 1, &copy);
        const VkMemoryBarrier to_host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                                         .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                         .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0, NULL, 0,
                             NULL);
        t0 = now_ms();
        rc = gpu_commands_run(gpu, &c, msg, msg_len);
    }
    if (!rc) {
        *ms = now_ms() - t0;
        uint64_t ticks[2];
        if (queries && vkGetQueryPoolResults(gpu->device, queries, 0, 2, sizeof ticks, ticks, sizeof ticks[0],
                                             VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) == VK_SUCCESS)
            *ms = (double)((ticks[1] - ticks[0]) & gpu->tick_mask) * gpu->ns_per_tick * 1e-6;
    }
    if (queries)
        vkDestroyQueryPool(gpu->device, queries, NULL);
    unbind_frame(gpu, &b);
    return rc;
}
