/* sdftrace — a frame on the device: the parameters sdft_render would use,
 * checked as it checks them, into the shader's gpu_frame; the hull's boxes
 * binned to the image's tiles on the host, as sdft_render bins them
 * (render_hull.c); one dispatch, one invocation a pixel; and its pixels
 * back into the image's planes and the counts. */
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "fail.h"
#include "gpu_grid.h"
#include "render_hull.h"
#include "render_pixel.h"

/* What the GPU does not render: anything that would have sdft_render shade
 * the Whitted way (render_whitted_wanted). */
static const char *gpu_cannot(const sdft_render_params *p)
{
    if (p->depth_only)
        return NULL;
    if (p->materials)
        return "materials";
    if (p->eps_min > 0.0f)
        return "dynamic eps (eps_min)";
    if (p->smooth_iters > 0)
        return "discontinuity reduction (smooth_iters)";
    if (p->soft_shadows > 0.0f)
        return "soft shadows";
    if (p->ao)
        return "ambient occlusion";
    return NULL;
}

/* The pipeline of `method`, made on first use. */
static sdft_error trace_pipeline(sdft_gpu *gpu, sdft_method method, VkPipeline *out, char *msg, size_t msg_len)
{
    sdft_error rc = SDFT_OK;
    pthread_mutex_lock(&gpu->lock);
    if (!gpu->trace[method])
        rc = gpu_pipeline_create(gpu, gpu->trace_module, (int32_t)method, &gpu->trace[method], msg, msg_len);
    *out = gpu->trace[method];
    pthread_mutex_unlock(&gpu->lock);
    return rc;
}

/* The frame's hull bins on the device (render_hull_bin's, uploaded):
 * first, box and rect. */
typedef struct frame_bins {
    gpu_buffer first, box, rect;
    int used;
} frame_bins;

static sdft_error bin_hull(sdft_gpu_grid *gg, const sdft_render_params *p, const sdft_view *view, float tnear,
                           frame_bins *fb, char *msg, size_t msg_len)
{
    const sdft_field *f = &gg->field;
    *fb = (frame_bins){0};
    if (!p->cones || !f->accel || !f->accel->hull_count || !render_eye_outside(f, p->camera.from, tnear))
        return SDFT_OK;
    hull_bins bins = {0};
    const int threads = p->threads > 0 ? p->threads : omp_get_max_threads();
    if (render_hull_bin(f->accel, view, p->width, p->height, threads, &bins)) {
        render_hull_bins_free(&bins);
        return fail_with(msg, msg_len, SDFT_ENOMEM, "out of memory for the hull's bins");
    }
    const size_t tiles = (size_t)((p->width + TILE - 1) / TILE) * (size_t)((p->height + TILE - 1) / TILE);
    sdft_error rc = gpu_buffer_upload(gg->gpu, bins.first, (tiles + 1) * sizeof *bins.first, &fb->first, msg, msg_len);
    if (!rc)
        rc = gpu_buffer_upload(gg->gpu, bins.box, (size_t)bins.first[tiles] * sizeof *bins.box, &fb->box, msg, msg_len);
    if (!rc)
        rc = gpu_buffer_upload(gg->gpu, bins.rect, 4 * f->accel->hull_count * sizeof *bins.rect, &fb->rect, msg,
                               msg_len);
    render_hull_bins_free(&bins);
    fb->used = 1;
    return rc;
}

static void unbin_hull(sdft_gpu *gpu, frame_bins *fb)
{
    gpu_buffer *b[3] = {&fb->first, &fb->box, &fb->rect};
    for (int k = 0; k < 3; k++)
        if (b[k]->buffer)
            gpu_buffer_free(gpu, b[k]);
}

/* The shader's frame for params. */
static gpu_frame frame_of(const sdft_gpu_grid *gg, const sdft_render_params *p, const sdft_view *view, float tnear,
                          const frame_bins *fb)
{
    gpu_frame fr;
    memset(&fr, 0, sizeof fr);
    fr.grid = gg->shape;
    fr.trace = p->trace;
    if (p->screen_space)
        fr.trace.pixel_radius = sdft_camera_pixel_radius(&p->camera, p->height);
    fr.bounds = gg->field.bounds;
    fr.from = view->from, fr.right_per_px = view->right_per_px;
    fr.down_per_px = view->down_per_px, fr.top_left = view->top_left;
    fr.light = p->light;
    fr.feature = sdft_field_feature_size(&gg->field);
    fr.cone_tnear = tnear;
    fr.root_reach = gg->field.accel->root_reach;
    fr.width = p->width, fr.height = p->height, fr.tiles_x = (p->width + TILE - 1) / TILE;
    fr.shadows = p->shadows, fr.depth_only = p->depth_only, fr.bound = SDFT_GRID_BOUND_FAR;
    fr.has_bins = fb->used;
    fr.bin_first = fb->first.address, fr.bin_box = fb->box.address, fr.bin_rect = fb->rect.address;
    fr.hull = gg->hull, fr.hull_slabs = gg->slabs, fr.has_slabs = gg->slabs != 0;
    return fr;
}

/* The pixels into img's planes and st's counts. */
static void read_pixels(const gpu_pixel *px, sdft_image *img, sdft_render_stats *st)
{
    const size_t n = (size_t)img->width * (size_t)img->height;
    for (size_t i = 0; i < n; i++) {
        const gpu_pixel *p = &px[i];
        for (int k = 0; k < 3; k++)
            img->rgb[3 * i + k] = p->rgb[k], img->normal[3 * i + k] = p->normal[k];
        img->depth[i] = p->depth;
        img->steps[i] = p->steps;
        img->fallbacks[i] = p->fallbacks;
        img->primary_steps[i] = p->primary_steps;
        img->status[i] = (uint8_t)p->status;
        st->rays += p->rays;
        st->steps += p->steps;
        st->primary_steps += p->primary_steps;
        st->fallbacks += p->fallbacks;
        st->primary_fallbacks += p->primary_fallbacks;
        st->shadow_steps += p->shadow_steps;
        st->hits += p->status == SDFT_HIT;
        st->nonconverged += p->status == SDFT_NOT_CONVERGED;
    }
    st->primary_rays = n;
}

sdft_error sdft_gpu_render(sdft_gpu_grid *gg, const sdft_render_params *params, sdft_image *img,
                           sdft_render_stats *stats, char *msg, size_t msg_len)
{
    if (!gg)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_gpu_render: no grid (NULL)");
    sdft_error rc = sdft_render_params_check(&gg->field, params, msg, msg_len);
    if (rc)
        return rc;
    if (!img || img->width != params->width || img->height != params->height || !img->rgb)
        return fail_with(msg, msg_len, SDFT_EINVAL, "the image is not allocated at the render size");
    const char *cannot = gpu_cannot(params);
    if (cannot)
        return fail_with(msg, msg_len, SDFT_EINVAL, "the GPU renders hard shadows on one grey surface, not %s", cannot);
    sdft_gpu *gpu = gg->gpu;
    VkPipeline pipeline;
    if ((rc = trace_pipeline(gpu, params->trace.method, &pipeline, msg, msg_len)))
        return rc;
    const sdft_view view = sdft_camera_view(&params->camera, params->width, params->height);
    const float tnear = render_box_distance(gg->field.bounds, params->camera.from);
    frame_bins fb;
    gpu_buffer pixels = {0}, readback = {0};
    const VkDeviceSize bytes = (VkDeviceSize)params->width * (VkDeviceSize)params->height * sizeof(gpu_pixel);
    rc = bin_hull(gg, params, &view, tnear, &fb, msg, msg_len);
    if (!rc)
        rc = gpu_buffer_create(gpu, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               GPU_ON_DEVICE, &pixels, msg, msg_len);
    if (!rc)
        rc = gpu_buffer_create(gpu, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GPU_ON_HOST, &readback, msg, msg_len);
    double ms = 0.0;
    if (!rc) {
        gpu_frame fr = frame_of(gg, params, &view, tnear, &fb);
        fr.pixels = pixels.address;
        const gpu_dispatch d = {.pipeline = pipeline,
                                .frame = &fr,
                                .frame_bytes = sizeof fr,
                                .width = params->width,
                                .height = params->height,
                                .pixels = &pixels,
                                .readback = &readback};
        rc = gpu_dispatch_run(gpu, &d, &ms, msg, msg_len);
    }
    if (!rc) {
        sdft_render_stats st = {.ms = ms};
        read_pixels(readback.mapped, img, &st);
        if (stats)
            *stats = st;
    }
    if (readback.buffer)
        gpu_buffer_free(gpu, &readback);
    if (pixels.buffer)
        gpu_buffer_free(gpu, &pixels);
    unbin_hull(gpu, &fb);
    return rc;
}
