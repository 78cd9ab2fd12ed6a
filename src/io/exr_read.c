/* sdftrace io — reading float planes back from a scanline OpenEXR file
 * through OpenEXRCore: named channels of part 0, each converted to 32-bit
 * float by OpenEXR's own unpacking (half and float channels). Used to
 * compare other renderers' output (vdb_render's positions) with ours. */
#include <openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image_io.h"

/* Points each wanted channel of the chunk at its rows in the planes. */
static int aim_channels(exr_decode_pipeline_t *dec, int n, const char *const names[], float *const planes[], int width,
                        int row)
{
    int found = 0;
    for (int k = 0; k < dec->channel_count; k++) {
        exr_coding_channel_info_t *ch = &dec->channels[k];
        ch->decode_to_ptr = NULL; /* channels nobody asked for are skipped */
        for (int c = 0; c < n; c++) {
            if (strcmp(ch->channel_name, names[c]) != 0)
                continue;
            ch->user_bytes_per_element = 4;
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_pixel_stride = 4;
            ch->user_line_stride = 4 * width;
            ch->decode_to_ptr = (uint8_t *)(planes[c] + (size_t)width * (size_t)row);
            found++;
        }
    }
    return found;
}

/* OpenEXRCore's default handler prints; the one line we return says it. */
static void quiet(exr_const_context_t ctxt, exr_result_t code, const char *text) { (void)ctxt, (void)code, (void)text; }

int io_read_exr_floats(const char *path, int n, const char *const names[], float *planes[], int *width, int *height,
                       char *msg, size_t msg_len)
{
    for (int c = 0; c < n; c++)
        planes[c] = NULL;
    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet;
    exr_result_t rc = exr_start_read(&ctx, path, &init);
    const char *why = NULL;
    char missing[128];
    exr_attr_box2i_t dw;
    dw.min.x = dw.min.y = 0, dw.max.x = dw.max.y = -1;
    exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_get_storage(ctx, 0, &storage);
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_get_data_window(ctx, 0, &dw);
    const long w = (long)dw.max.x - dw.min.x + 1, h = (long)dw.max.y - dw.min.y + 1;
    if (rc == EXR_ERR_SUCCESS && storage != EXR_STORAGE_SCANLINE)
        why = "not a scanline image";
    else if (rc == EXR_ERR_SUCCESS && (w < 1 || h < 1 || w > 65536 || h > 65536))
        why = "absurd data window";
    const exr_attr_chlist_t *chl = NULL;
    if (rc == EXR_ERR_SUCCESS && !why)
        rc = exr_get_channels(ctx, 0, &chl);
    for (int c = 0; rc == EXR_ERR_SUCCESS && !why && c < n; c++) {
        int present = 0;
        for (int k = 0; k < chl->num_channels; k++)
            present |= strcmp(chl->entries[k].name.str, names[c]) == 0;
        if (!present) {
            snprintf(missing, sizeof missing, "no channel '%s'", names[c]);
            why = missing;
            break;
        }
        planes[c] = calloc((size_t)w * (size_t)h, sizeof(float));
        if (!planes[c])
            why = "out of memory";
    }
    int lines = 0;
    if (rc == EXR_ERR_SUCCESS && !why)
        rc = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int y = dw.min.y; rc == EXR_ERR_SUCCESS && !why && y <= dw.max.y; y += lines) {
        exr_chunk_info_t chunk;
        rc = exr_read_scanline_chunk_info(ctx, 0, y, &chunk);
        if (rc == EXR_ERR_SUCCESS)
            rc = started ? exr_decoding_update(ctx, 0, &chunk, &dec) : exr_decoding_initialize(ctx, 0, &chunk, &dec);
        if (rc != EXR_ERR_SUCCESS)
            break;
        aim_channels(&dec, n, names, planes, (int)w, chunk.start_y - dw.min.y);
        if (!started)
            rc = exr_decoding_choose_default_routines(ctx, 0, &dec);
        started = 1;
        if (rc == EXR_ERR_SUCCESS)
            rc = exr_decoding_run(ctx, 0, &dec);
    }
    if (started)
        exr_decoding_destroy(ctx, &dec);
    if (ctx)
        exr_finish(&ctx);
    if (rc != EXR_ERR_SUCCESS || why) {
        if (msg && msg_len)
            snprintf(msg, msg_len, "%s: %s", path, why ? why : exr_get_default_error_message(rc));
        for (int c = 0; c < n; c++) {
            free(planes[c]);
            planes[c] = NULL;
        }
        return -1;
    }
    *width = (int)w, *height = (int)h;
    return 0;
}
