/* sdftrace io — OpenEXR output through OpenEXRCore, OpenEXR's C API:
 * one scanline part, ZIP compressed, every plane of the image as a channel.
 * The encode pipeline is OpenEXR's own; we hand it planar rows, and run one
 * per thread (below). */
#include <openexr.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "atomic_file.h"
#include "image_io.h"

enum { EXR_CHANNELS = 10 };

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

/* CHUNKS IN PARALLEL. OpenEXRCore's encode pipeline is meant to run on
 * several threads at once, one pipeline each, as long as the chunks reach
 * the file in order: each thread packs and compresses its chunk (zlib, the
 * bulk of the time), then its yield_until_ready_fn waits for the chunks
 * before it to be written. Chunks are handed out in increasing order, so
 * the lowest unwritten chunk always belongs to a thread that gets to it;
 * a failure anywhere releases every waiter with an error. */
typedef struct exr_turn {
    int next;   /* the chunk whose turn it is to be written (atomic) */
    int failed; /* 1 once any chunk failed (atomic) */
} exr_turn;

typedef struct exr_ordered {
    exr_encode_pipeline_t pipe; /* first: the pipeline's callbacks get its address */
    int chunk;
    exr_turn *turn;
    exr_result_t (*write)(exr_encode_pipeline_t *); /* OpenEXR's own */
} exr_ordered;

static exr_result_t wait_for_turn(exr_encode_pipeline_t *pipe)
{
    const exr_ordered *o = (const exr_ordered *)pipe;
    while (__atomic_load_n(&o->turn->next, __ATOMIC_ACQUIRE) != o->chunk) {
        if (__atomic_load_n(&o->turn->failed, __ATOMIC_RELAXED))
            return EXR_ERR_UNKNOWN;
        sched_yield();
    }
    return EXR_ERR_SUCCESS;
}

static exr_result_t write_in_turn(exr_encode_pipeline_t *pipe)
{
    exr_ordered *o = (exr_ordered *)pipe;
    const exr_result_t rc = o->write(pipe);
    if (rc != EXR_ERR_SUCCESS)
        __atomic_store_n(&o->turn->failed, 1, __ATOMIC_RELAXED);
    __atomic_store_n(&o->turn->next, o->chunk + 1, __ATOMIC_RELEASE);
    return rc;
}

/* Encodes and writes chunk `chunk` (rows from y) with the thread's
 * pipeline `o`, set up on its first chunk. */
static exr_result_t exr_encode_chunk(exr_context_t ctx, int part, exr_ordered *o, int *started, int chunk, int y,
                                     const exr_plane *planes, int width)
{
    exr_chunk_info_t info;
    exr_result_t rc = exr_write_scanline_chunk_info(ctx, part, y, &info);
    if (rc == EXR_ERR_SUCCESS)
        rc = *started ? exr_encoding_update(ctx, part, &info, &o->pipe)
                      : exr_encoding_initialize(ctx, part, &info, &o->pipe);
    if (rc != EXR_ERR_SUCCESS)
        return rc;
    /* The pipeline lists channels in the file's (sorted) order. */
    for (int k = 0; k < o->pipe.channel_count; k++) {
        exr_coding_channel_info_t *ch = &o->pipe.channels[k];
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
    if (!*started) {
        rc = exr_encoding_choose_default_routines(ctx, part, &o->pipe);
        if (rc != EXR_ERR_SUCCESS)
            return rc;
        *started = 1;
        o->write = o->pipe.write_fn;
        o->pipe.yield_until_ready_fn = wait_for_turn;
        o->pipe.write_fn = write_in_turn;
    }
    o->chunk = chunk;
    return exr_encoding_run(ctx, part, &o->pipe);
}

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
    if (rc != EXR_ERR_SUCCESS)
        return rc;
    const int chunks = (height + lines - 1) / lines;
    exr_turn turn = {0, 0};
    exr_result_t first_error = EXR_ERR_SUCCESS;
#pragma omp parallel
    {
        exr_ordered o = {.pipe = EXR_ENCODE_PIPELINE_INITIALIZER, .turn = &turn};
        int started = 0;
#pragma omp for schedule(static, 1)
        for (int chunk = 0; chunk < chunks; chunk++) {
            exr_result_t crc = EXR_ERR_SUCCESS;
            if (!__atomic_load_n(&turn.failed, __ATOMIC_RELAXED))
                crc = exr_encode_chunk(ctx, part, &o, &started, chunk, chunk * lines, planes, width);
            if (crc != EXR_ERR_SUCCESS) {
                __atomic_store_n(&turn.failed, 1, __ATOMIC_RELAXED);
#pragma omp critical(exr_error)
                if (first_error == EXR_ERR_SUCCESS)
                    first_error = crc;
            }
        }
        if (started)
            exr_encoding_destroy(ctx, &o.pipe);
    }
    if (first_error == EXR_ERR_SUCCESS && turn.failed)
        first_error = EXR_ERR_UNKNOWN;
    return first_error;
}

int io_write_exr_into(atomic_file *to, const sdft_image *img, char *msg, size_t msg_len)
{
    const char *path = to->path;
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
        {"primary_steps", EXR_PIXEL_UINT, img->primary_steps},
    };

    exr_errors errors = {{0}};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_error_cb;
    init.user_data = &errors;
    exr_context_t ctx = NULL;
    int part = 0;
    exr_result_t rc = exr_start_write(&ctx, to->tmp_path, EXR_WRITE_FILE_DIRECTLY, &init);
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
        return -1;
    }
    return 0;
}

static int exr_writer(atomic_file *to, const void *img, char *msg, size_t msg_len)
{
    return io_write_exr_into(to, img, msg, msg_len);
}

int io_write_exr(const char *path, const sdft_image *img, char *msg, size_t msg_len)
{
    return io_write_whole(path, exr_writer, img, msg, msg_len);
}
