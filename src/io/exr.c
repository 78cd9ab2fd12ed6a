/* sdftrace io — OpenEXR output through OpenEXRCore, OpenEXR's C API:
 * one scanline part, ZIP compressed, every plane of the image as a channel.
 * The encode pipeline is OpenEXR's own; we hand it planar rows. */
#include <openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "atomic_file.h"
#include "image_io.h"

enum { EXR_CHANNELS = 9 };

/* OpenEXR reports errors through a callback; keep the first for msg. */
typedef struct exr_errors {
    char text[256];
} exr_errors;

static void exr_error_cb(exr_const_context_t ctxt, exr_result_t code, const char *text)
{
    void *user = NULL;
    if (exr_get_user_data(ctxt, &user) == EXR_ERR_SUCCESS && user) {
        exr_errors *e = user;
        if (!e->text[0])
            snprintf(e->text, sizeof e->text, "%s", text ? text : exr_get_default_error_message(code));
    }
}

/* One plane per channel, row-major, 4 bytes per sample. */
typedef struct exr_plane {
    const char *name;
    exr_pixel_type_t type;
    const void *data;
} exr_plane;

/* Writes the planes; returns an OpenEXR result code. */
static exr_result_t exr_write_planes(exr_context_t ctx, int part, const exr_plane *planes, int width, int height)
{
    exr_result_t rc = EXR_ERR_SUCCESS;
    for (int c = 0; c < EXR_CHANNELS && rc == EXR_ERR_SUCCESS; c++)
        rc = exr_add_channel(ctx, part, planes[c].name, planes[c].type, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_write_header(ctx);
    int lines = 1;
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_get_scanlines_per_chunk(ctx, part, &lines);

    exr_encode_pipeline_t encoder = EXR_ENCODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int y = 0; y < height && rc == EXR_ERR_SUCCESS; y += lines) {
        exr_chunk_info_t chunk;
        rc = exr_write_scanline_chunk_info(ctx, part, y, &chunk);
        if (rc != EXR_ERR_SUCCESS)
            break;
        rc = started ? exr_encoding_update(ctx, part, &chunk, &encoder)
                     : exr_encoding_initialize(ctx, part, &chunk, &encoder);
        if (rc != EXR_ERR_SUCCESS)
            break;
        /* The pipeline lists channels in the file's (sorted) order. */
        for (int k = 0; k < encoder.channel_count; k++) {
            exr_coding_channel_info_t *ch = &encoder.channels[k];
            for (int c = 0; c < EXR_CHANNELS; c++) {
                if (strcmp(ch->channel_name, planes[c].name) != 0)
                    continue;
                ch->user_bytes_per_element = 4;
                ch->user_data_type = (uint16_t)planes[c].type;
                ch->user_pixel_stride = 4;
                ch->user_line_stride = 4 * width;
                ch->encode_from_ptr = (const uint8_t *)planes[c].data + (size_t)4 * (size_t)width * (size_t)y;
            }
        }
        if (!started) {
            rc = exr_encoding_choose_default_routines(ctx, part, &encoder);
            started = 1;
        }
        if (rc == EXR_ERR_SUCCESS)
            rc = exr_encoding_run(ctx, part, &encoder);
    }
    if (started)
        exr_encoding_destroy(ctx, &encoder);
    return rc;
}

int sdft_write_exr(const char *path, const sdft_image *img, char *msg, size_t msg_len)
{
    const int w = img->width, h = img->height;
    const size_t n = (size_t)w * (size_t)h;
    float *split = malloc(6 * n * sizeof *split); /* R, G, B, N.X, N.Y, N.Z planes */
    if (!split) {
        snprintf(msg, msg_len, "out of memory writing %s", path);
        return -1;
    }
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            split[k * n + i] = img->rgb[3 * i + k];
            split[(3 + k) * n + i] = img->normal[3 * i + k];
        }
    const exr_plane planes[EXR_CHANNELS] = {
        {"R", EXR_PIXEL_FLOAT, split},
        {"G", EXR_PIXEL_FLOAT, split + n},
        {"B", EXR_PIXEL_FLOAT, split + 2 * n},
        {"Z", EXR_PIXEL_FLOAT, img->depth},
        {"N.X", EXR_PIXEL_FLOAT, split + 3 * n},
        {"N.Y", EXR_PIXEL_FLOAT, split + 4 * n},
        {"N.Z", EXR_PIXEL_FLOAT, split + 5 * n},
        {"steps", EXR_PIXEL_UINT, img->steps},
        {"fallbacks", EXR_PIXEL_UINT, img->fallbacks},
    };

    sdft_atomic_file af;
    if (sdft_atomic_begin(&af, path, msg, msg_len)) {
        free(split);
        return -1;
    }
    exr_errors errors = {{0}};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_error_cb;
    init.user_data = &errors;
    exr_context_t ctx = NULL;
    int part = 0;
    exr_result_t rc = exr_start_write(&ctx, af.tmp_path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_add_part(ctx, "sdftrace", EXR_STORAGE_SCANLINE, &part);
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_initialize_required_attr_simple(ctx, part, w, h, EXR_COMPRESSION_ZIP);
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_write_planes(ctx, part, planes, w, h);
    exr_result_t fin = ctx ? exr_finish(&ctx) : EXR_ERR_SUCCESS;
    free(split);
    if (rc == EXR_ERR_SUCCESS)
        rc = fin;
    if (rc != EXR_ERR_SUCCESS) {
        snprintf(msg, msg_len, "cannot write %s: %s", path,
                 errors.text[0] ? errors.text : exr_get_default_error_message(rc));
        sdft_atomic_abort(&af);
        return -1;
    }
    return sdft_atomic_commit(&af, msg, msg_len);
}
