/* gpu_bench — one grid on one Vulkan device, in one process (bench/gpu.sh
 * runs it per grid): sdftrace's frame (sdft_gpu_render) beside NanoVDB's
 * own level-set ray caster in the same program (bench/hdda.comp, PNanoVDB's
 * GLSL pnanovdb_hdda_zero_crossing) on the same uploaded grid, and the
 * study's Table rows (Bán and Valasek's methods, the papers' counting,
 * hard shadows, 1000 steps) in GPU milliseconds. Every time is the median
 * of --frames frames after one warm-up frame and its 95% bootstrap
 * interval (bench/stats.h, as every page has them), the rows of a group
 * taken in turn, frame by frame (A B C A B C ...), each frame's time the
 * GPU's own (vkCmdWriteTimestamp around the dispatch); a ratio is the
 * median of the frames' ratios. Prints markdown table rows; gpu.sh writes
 * the page around them.
 *
 *   gpu_bench [options] GRID.vdb|GRID.nvdb SCENE|front
 *
 * --rows peer: | grid | HDDA ms | ours, depth ms | ours/HDDA | ours, shaded ms | depth within 1.5 voxels of
 *              HDDA's % | hit masks differ from the CPU's % | largest depth difference from the CPU's, voxels |
 * --rows study: | grid | method | ms [95%] | rel to ENH | evaluations/px |   one row per method */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmdline.h"
#include "gpu_grid.h"
#include "render_pixel.h"
#include "sdftrace/gpu.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/vdb.h"
#include "stats.h"

/* NanoVDB's caster, compiled by glslc at build time (bench/CMakeLists.txt). */
static const uint32_t hdda_spirv[] =
#include "hdda.spv.inc"
    ;

enum { MOST_FRAMES = 64 };

/* The study's Table rows (bench/study.c's STUDY_TABLE_METHODS: the paper's
 * REL is its Algorithm 2, relaxed-bv); gpu.sh prints Bán and Valasek's
 * RX 5700 frame times beside them. */
static const struct {
    sdft_method method;
    float param; /* omega or beta; 0 for sphere */
    const char *label;
} METHODS[] = {
    {SDFT_SPHERE, 0.0f, "ST"},       {SDFT_ENHANCED, 0.88f, "ENH"}, {SDFT_RELAXED, 1.2f, "REL 1.2"},
    {SDFT_RELAXED, 1.5f, "REL 1.5"}, {SDFT_AUTO, 0.3f, "AR 0.3"},   {SDFT_AUTO, 0.2f, "AR 0.2"},
};
enum { METHOD_ROWS = sizeof METHODS / sizeof METHODS[0], ENH_ROW = 1 };

typedef struct options {
    const char *grid, *view, *rows, *label;
    int device, width, height, frames;
} options;

static int take_operand(void *target, const char *value, char *msg, size_t len)
{
    options *o = target;
    if (!o->grid)
        o->grid = value;
    else if (!o->view)
        o->view = value;
    else {
        snprintf(msg, len, "one grid and one view, not '%s' too", value);
        return -1;
    }
    return 0;
}

static void fail(const char *what, const char *msg)
{
    fprintf(stderr, "gpu_bench: %s: %s\n", what, msg);
    exit(1);
}

/* The frames' times v[0..n) as the page shows them: "median [lo–hi]". */
static const char *summary(const double *v, int n, char *buf, unsigned long len)
{
    bench_summary s;
    bench_summarize(v, n, 0.95, &s);
    return bench_summary_text(&s, 2, buf, len);
}

/* The median over frames of a[f] / b[f]. */
static double median_ratio(const double *a, const double *b, int n)
{
    double r[MOST_FRAMES];
    for (int f = 0; f < n; f++)
        r[f] = a[f] / b[f];
    return bench_median(r, n);
}

/* NanoVDB's caster over the frame of p: its GPU time, and its depths into
 * depth (width x height). */
typedef struct caster {
    sdft_gpu *gpu;
    sdft_gpu_grid *gg;
    VkShaderModule module;
    VkPipeline pipeline;
    gpu_buffer pixels, readback;
} caster;

static double caster_frame(caster *c, const sdft_render_params *p, float *depth)
{
    char msg[512];
    const sdft_view view = sdft_camera_view(&p->camera, p->width, p->height);
    gpu_frame fr;
    memset(&fr, 0, sizeof fr);
    fr.grid = c->gg->shape;
    fr.from = view.from, fr.right_per_px = view.right_per_px, fr.down_per_px = view.down_per_px;
    fr.top_left = view.top_left;
    fr.width = p->width, fr.height = p->height;
    fr.pixels = c->pixels.address;
    const gpu_dispatch d = {.pipeline = c->pipeline,
                            .frame = &fr,
                            .frame_bytes = sizeof fr,
                            .width = p->width,
                            .height = p->height,
                            .pixels = &c->pixels,
                            .readback = &c->readback};
    double ms;
    if (gpu_dispatch_run(c->gpu, &d, &ms, msg, sizeof msg))
        fail("NanoVDB's caster", msg);
    const gpu_pixel *px = c->readback.mapped;
    for (size_t i = 0; i < (size_t)p->width * (size_t)p->height; i++)
        depth[i] = px[i].depth;
    return ms;
}

static double our_frame(sdft_gpu_grid *gg, const sdft_render_params *p, sdft_image *img, sdft_render_stats *st)
{
    char msg[512];
    if (sdft_gpu_render(gg, p, img, st, msg, sizeof msg))
        fail("sdft_gpu_render", msg);
    return st->ms;
}

/* The share of pixels both hit whose depths are within tol of each other. */
static double depth_agreement(const float *a, const float *b, size_t n, float tol)
{
    size_t both = 0, near = 0;
    for (size_t i = 0; i < n; i++)
        if (isfinite(a[i]) && isfinite(b[i]))
            both++, near += fabsf(a[i] - b[i]) <= tol;
    return both ? (double)near / (double)both : 0.0;
}

/* The GPU's image against the CPU's: the share of pixels whose hit masks
 * differ, and the largest depth difference where both hit, in voxels. */
static void against_cpu(const sdft_image *g, const sdft_image *c, float voxel, double *differ, double *largest)
{
    const size_t n = (size_t)g->width * (size_t)g->height;
    size_t d = 0;
    *largest = 0.0;
    for (size_t i = 0; i < n; i++) {
        const int hg = g->status[i] == SDFT_HIT, hc = c->status[i] == SDFT_HIT;
        if (hg != hc)
            d++;
        else if (hg)
            *largest = fmax(*largest, fabs((double)g->depth[i] - (double)c->depth[i]) / voxel);
    }
    *differ = (double)d / (double)n;
}

static void peer_rows(const options *o, const sdft_grid *g, caster *c, sdft_render_params p)
{
    char msg[512];
    const size_t n = (size_t)p.width * (size_t)p.height;
    sdft_render_params depth_only = p;
    depth_only.depth_only = 1;
    sdft_image ours, shaded, cpu;
    float *hdda = malloc(n * sizeof *hdda);
    if (!hdda || sdft_image_alloc(&ours, p.width, p.height, msg, sizeof msg) ||
        sdft_image_alloc(&shaded, p.width, p.height, msg, sizeof msg) ||
        sdft_image_alloc(&cpu, p.width, p.height, msg, sizeof msg))
        fail("images", "out of memory");
    double t[3][MOST_FRAMES];
    sdft_render_stats st;
    for (int f = -1; f < o->frames; f++) { /* frame -1: the warm-up, untimed */
        const double a = caster_frame(c, &p, hdda), b = our_frame(c->gg, &depth_only, &ours, &st);
        const double s = our_frame(c->gg, &p, &shaded, &st);
        if (f >= 0)
            t[0][f] = a, t[1][f] = b, t[2][f] = s;
    }
    const sdft_field field = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_render_stats cs;
    if (sdft_render(&field, &p, &cpu, &cs, msg, sizeof msg))
        fail("sdft_render", msg);
    const float voxel = sdft_grid_voxel_size(g).x;
    double differ, largest;
    against_cpu(&shaded, &cpu, voxel, &differ, &largest);
    char h[64], d[64], s[64];
    printf("| %s | %s | %s | %.2f | %s | %.2f | %.3f | %.2g |\n", o->label, summary(t[0], o->frames, h, sizeof h),
           summary(t[1], o->frames, d, sizeof d), median_ratio(t[1], t[0], o->frames),
           summary(t[2], o->frames, s, sizeof s), 100.0 * depth_agreement(ours.depth, hdda, n, 1.5f * voxel),
           100.0 * differ, largest);
    sdft_image_free(&ours), sdft_image_free(&shaded), sdft_image_free(&cpu);
    free(hdda);
}

static void study_rows(const options *o, sdft_gpu_grid *gg, sdft_render_params p)
{
    char msg[512];
    sdft_render_papers(&p);
    p.trace.max_steps = 1000;
    sdft_render_params rows[METHOD_ROWS];
    for (int m = 0; m < METHOD_ROWS; m++) {
        rows[m] = p;
        rows[m].trace.method = METHODS[m].method;
        rows[m].trace.omega =
            METHODS[m].method == SDFT_AUTO || METHODS[m].method == SDFT_SPHERE ? 1.0f : METHODS[m].param;
        if (METHODS[m].method == SDFT_AUTO)
            rows[m].trace.beta = METHODS[m].param;
    }
    sdft_image img;
    if (sdft_image_alloc(&img, p.width, p.height, msg, sizeof msg))
        fail("image", msg);
    double t[METHOD_ROWS][MOST_FRAMES], steps[METHOD_ROWS];
    for (int f = -1; f < o->frames; f++)
        for (int m = 0; m < METHOD_ROWS; m++) {
            sdft_render_stats st;
            const double ms = our_frame(gg, &rows[m], &img, &st);
            steps[m] = (double)st.steps / (double)st.primary_rays;
            if (f >= 0)
                t[m][f] = ms;
        }
    for (int m = 0; m < METHOD_ROWS; m++) {
        char ms[64];
        printf("| %s | %s | %s | %.0f%% | %.2f |\n", o->label, METHODS[m].label,
               summary(t[m], o->frames, ms, sizeof ms), 100.0 * median_ratio(t[m], t[ENH_ROW], o->frames), steps[m]);
    }
    sdft_image_free(&img);
}

int main(int argc, char **argv)
{
    options o = {.rows = "peer", .device = -1, .width = 1280, .height = 720, .frames = 5};
    const cmdline_option rows[] = {
        {"device", 0, "N", "the Vulkan device (-1: the first GPU, else any)", CMDLINE_INT, &o.device, .lo = -1,
         .hi = 1024},
        {"width", 0, "W", "image width", CMDLINE_INT, &o.width, .lo = 1, .hi = 16384},
        {"height", 0, "H", "image height", CMDLINE_INT, &o.height, .lo = 1, .hi = 16384},
        {"frames", 0, "N", "timed frames per row after one warm-up, the median", CMDLINE_INT, &o.frames, .lo = 1,
         .hi = MOST_FRAMES},
        {"rows", 0, "peer|study", "which rows", CMDLINE_TEXT, &o.rows, .def = "peer"},
        {"label", 0, "NAME", "the grid's name in the rows", CMDLINE_TEXT, &o.label, .def = "the file's"},
        {"help", 'h', NULL, NULL, CMDLINE_HELP, NULL, .def = ""},
        {0},
    };
    const cmdline_spec spec = {.program = "gpu_bench",
                               .usage = "usage: gpu_bench [options] GRID.vdb|GRID.nvdb SCENE|front\n",
                               .rows = rows,
                               .column = 20,
                               .operand = take_operand,
                               .operand_target = &o};
    char msg[512] = "";
    const int parsed = cmdline_parse(&spec, argc, argv, msg, sizeof msg);
    if (parsed == CMDLINE_HELP_ASKED) {
        cmdline_help(&spec, stdout);
        return 0;
    }
    if (parsed || !o.view || (strcmp(o.rows, "peer") && strcmp(o.rows, "study")))
        fail("usage", parsed ? msg : "gpu_bench [options] GRID SCENE|front (--rows peer|study)");
    if (!o.label)
        o.label = o.grid;

    sdft_grid_options go = sdft_grid_options_defaults();
    go.path = o.grid;
    sdft_grid *g = NULL;
    if (sdft_vdb_open(&go, &g, msg, sizeof msg))
        fail(o.grid, msg);
    sdft_render_params p = sdft_render_defaults();
    p.width = o.width, p.height = o.height;
    const sdft_scene *scene = strcmp(o.view, "front") ? sdft_scene_find(o.view) : NULL;
    if (scene) {
        p.camera = scene->camera, p.light = scene->light;
    } else if (!strcmp(o.view, "front")) { /* sdftrace render --grid's view and light */
        p.camera = sdft_camera_front(sdft_grid_world_bounds(g), o.width, o.height, 40.0f);
        const float dist = p.camera.from.z - p.camera.at.z;
        p.light = sdft_v3(p.camera.at.x, p.camera.at.y + 2.0f * dist, p.camera.at.z + dist);
    } else {
        fail(o.view, "no such scene (sdftrace scenes), nor front");
    }

    sdft_gpu_options gpo = sdft_gpu_options_defaults();
    gpo.device = o.device;
    caster c = {0};
    if (sdft_gpu_create(&gpo, &c.gpu, msg, sizeof msg) || sdft_gpu_grid_create(c.gpu, g, &c.gg, msg, sizeof msg))
        fail("Vulkan", msg);
    fprintf(stderr, "gpu_bench: %s on %s, %dx%d\n", o.label, sdft_gpu_device_name(c.gpu), o.width, o.height);
    if (!strcmp(o.rows, "peer")) {
        const VkDeviceSize bytes = (VkDeviceSize)o.width * (VkDeviceSize)o.height * sizeof(gpu_pixel);
        if (gpu_module_create(c.gpu, hdda_spirv, sizeof hdda_spirv, &c.module, msg, sizeof msg) ||
            gpu_pipeline_create(c.gpu, c.module, 0, &c.pipeline, msg, sizeof msg) ||
            gpu_buffer_create(c.gpu, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                              GPU_ON_DEVICE, &c.pixels, msg, sizeof msg) ||
            gpu_buffer_create(c.gpu, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GPU_ON_HOST, &c.readback, msg,
                              sizeof msg))
            fail("NanoVDB's caster", msg);
        peer_rows(&o, g, &c, p);
        gpu_buffer_free(c.gpu, &c.pixels), gpu_buffer_free(c.gpu, &c.readback);
        vkDestroyPipeline(c.gpu->device, c.pipeline, NULL);
        vkDestroyShaderModule(c.gpu->device, c.module, NULL);
    } else {
        study_rows(&o, c.gg, p);
    }
    sdft_gpu_grid_release(c.gg);
    sdft_gpu_release(c.gpu);
    sdft_grid_free(g);
    return 0;
}
