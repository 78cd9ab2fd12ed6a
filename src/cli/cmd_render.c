/* sdftrace render — a field (today a procedural scene) through the renderer
 * to OpenEXR, with an optional PNG preview, count heatmaps and a JSON line
 * of statistics. The steps: parse the options, check them, open the field,
 * check the outputs can be written, render, write, report. */
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "image_io.h"
#include "json.h"
#include "progress_bar.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/vdb.h"

enum { MAX_SIDE = 16384, MAX_STEPS = 10000000, MAX_THREADS = 1024 };
static const long MAX_PIXELS = 64l * 1024 * 1024;

typedef struct render_opts {
    const char *scene;            /* --scene NAME */
    const char *grid, *grid_name; /* --grid FILE, --grid-name NAME */
    sdft_method method;           /* --method */
    int omega_set;                /* --omega given; else the method's default */
    float omega, beta, eps;
    long max_steps, width, height, threads;
    long heatmap_max;        /* --heatmap-max: the scale's top; 0: the largest count, rounded up */
    int camera_set, fov_set; /* override the scene's view */
    float camera[6], fov;
    int shadows, screen_space, cones, exact_root, depth_only, json, quiet, fp16;
    const char *out, *png, *heatmap;
    sdft_heatmap_kind heatmap_kind;
} render_opts;

/* What is rendered: a field, its default view and light, and whatever must
 * be released afterwards (a grid's buffer, later). */
typedef struct render_source {
    sdft_field field;
    sdft_camera camera;
    sdft_vec3 light;
    const char *name; /* for the JSON report */
    sdft_grid *grid;  /* --grid: owned, freed by close_field */
} render_source;

void cmd_render_help(FILE *out)
{
    sdft_render_params d = sdft_render_defaults();
    fprintf(
        out,
        "usage: sdftrace render --scene NAME | --grid FILE -o OUT.exr [options]\n"
        "  --scene NAME          procedural scene (sdftrace scenes lists them); required without --grid\n"
        "  --grid FILE           render a level set (.vdb or .nvdb); with --scene, from that scene's camera and light\n"
        "  --grid-name NAME      the grid of FILE to render (default: the first scalar level set)\n"
        "  -o OUT.exr            OpenEXR output: R,G,B, Z, N.X,N.Y,N.Z, steps, fallbacks; required\n"
        "  --method M            sphere | relaxed | enhanced | auto (default %s)\n"
        "  --omega W             relaxed: [1, 2), default %g; enhanced: (0, 1], default %g\n"
        "  --beta B              auto: (0, 1) (default %g)\n"
        "  --eps E               convergence radius, world units (default %g)\n"
        "  --max-steps N         most SDF evaluations per ray (default %u)\n"
        "  --width W             image width, pixels (default %d)\n"
        "  --height H            image height, pixels (default %d)\n"
        "  --camera FX,FY,FZ,AX,AY,AZ  eye and look-at point (default: the scene's)\n"
        "  --fov DEG             vertical field of view, (0, 180) (default: the scene's)\n"
        "  --no-shadows          no shadow rays (default: a shadow ray per lit hit)\n"
        "  --screen-space        Keinert's screen-space criterion: eps grows by half a pixel per unit t (default off)\n"
        "  --no-cones            every primary ray from the eye. Default: on a grid, each primary ray is traced\n"
        "                        only where it crosses the grid's hull (boxes around the cells the surface\n"
        "                        crosses, each cut to a slab along the surface, found by ray-box and ray-slab\n"
        "                        tests, no evaluation; boxes whose surface faces away from the eye left out);\n"
        "                        on a scene, the rays of each 16x16 tile, then of each 4x4 block, first march\n"
        "                        together as one cone, then each on its own from there (the cones' steps\n"
        "                        counted apart: cone_steps). Faster, the same picture\n"
        "  --no-exact-root       sphere steps to eps to the end. Default: near the surface of a grid, the exact\n"
        "                        first root of its trilinear interpolant, cell by cell (each cell read counts\n"
        "                        as one evaluation); procedural scenes always step to eps\n"
        "  --papers              the papers' way of counting: --no-cones --no-exact-root (every ray from the\n"
        "                        eye, every step to eps); what the method comparisons use\n"
        "  --depth-only          primary rays only: depth (Z), status and counts; no normals, shading or shadows\n"
        "  --fp16                load a .vdb grid as NanoVDB Fp16 (half the memory; values within 1/2048 of the band)\n"
        "  --quiet               no progress line while loading, no summary line when done (both on stderr)\n"
        "  --threads N           OpenMP threads, 0 = all cores (default 0)\n"
        "  --png OUT.png         sRGB preview (default none)\n"
        "  --heatmap steps|fallbacks OUT.png  false-colour map of the per-pixel counts (default none)\n"
        "  --heatmap-max N       the heatmap's scale runs 0..N, larger counts are red, so that maps share a scale\n"
        "                        (default: the largest count, rounded up to a multiple of 4)\n"
        "  --json                print one JSON object of statistics on stdout (default off)\n",
        sdft_method_name(d.trace.method), sdft_default_omega(SDFT_RELAXED), sdft_default_omega(SDFT_ENHANCED),
        d.trace.beta, d.trace.eps, d.trace.max_steps, d.width, d.height);
}

static render_opts default_opts(void)
{
    sdft_render_params d = sdft_render_defaults();
    return (render_opts){
        .method = d.trace.method,
        .beta = d.trace.beta,
        .eps = d.trace.eps,
        .max_steps = d.trace.max_steps,
        .width = d.width,
        .height = d.height,
        .threads = 0,
        .shadows = 1,
        .cones = d.cones,
        .exact_root = d.trace.exact_root,
    };
}

/* Fills opts from argv; 0, 1 (--help printed), or -1 with msg. */
static int parse_opts(int argc, char **argv, render_opts *o, char *msg, size_t len)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
            return 1;
        if (strcmp(a, "--no-shadows") == 0) {
            o->shadows = 0;
            continue;
        }
        if (strcmp(a, "--screen-space") == 0) {
            o->screen_space = 1;
            continue;
        }
        if (strcmp(a, "--cones") == 0) { /* the default; kept so that older scripts run */
            o->cones = 1;
            continue;
        }
        if (strcmp(a, "--no-cones") == 0) {
            o->cones = 0;
            continue;
        }
        if (strcmp(a, "--no-exact-root") == 0) {
            o->exact_root = 0;
            continue;
        }
        if (strcmp(a, "--papers") == 0) {
            o->cones = 0, o->exact_root = 0;
            continue;
        }
        if (strcmp(a, "--fp16") == 0) {
            o->fp16 = 1;
            continue;
        }
        if (strcmp(a, "--quiet") == 0) {
            o->quiet = 1;
            continue;
        }
        if (strcmp(a, "--depth-only") == 0) {
            o->depth_only = 1;
            continue;
        }
        if (strcmp(a, "--json") == 0) {
            o->json = 1;
            continue;
        }
        int known = !strcmp(a, "--scene") || !strcmp(a, "-o") || !strcmp(a, "--method") || !strcmp(a, "--omega") ||
                    !strcmp(a, "--beta") || !strcmp(a, "--eps") || !strcmp(a, "--max-steps") || !strcmp(a, "--width") ||
                    !strcmp(a, "--height") || !strcmp(a, "--camera") || !strcmp(a, "--fov") ||
                    !strcmp(a, "--threads") || !strcmp(a, "--png") || !strcmp(a, "--heatmap") || !strcmp(a, "--grid") ||
                    !strcmp(a, "--grid-name") || !strcmp(a, "--heatmap-max");
        if (!known) {
            snprintf(msg, len, "unknown option '%s' (try: sdftrace render --help)", a);
            return -1;
        }
        int needs = !strcmp(a, "--heatmap") ? 2 : 1;
        if (i + needs >= argc) {
            snprintf(msg, len, "%s needs %s", a, needs == 2 ? "a kind and a file" : "a value");
            return -1;
        }
        const char *v = argv[++i];
        long n = 0;
        int rc = 0;
        if (!strcmp(a, "--scene"))
            o->scene = v;
        else if (!strcmp(a, "-o"))
            o->out = v;
        else if (!strcmp(a, "--grid"))
            o->grid = v;
        else if (!strcmp(a, "--grid-name"))
            o->grid_name = v;
        else if (!strcmp(a, "--png"))
            o->png = v;
        else if (!strcmp(a, "--method"))
            rc = sdft_method_parse(v, &o->method, msg, len) ? -1 : 0;
        else if (!strcmp(a, "--omega")) {
            rc = arg_float(a, v, -1e30f, 1e30f, &o->omega, msg, len);
            o->omega_set = 1;
        } else if (!strcmp(a, "--beta"))
            rc = arg_float(a, v, -1e30f, 1e30f, &o->beta, msg, len);
        else if (!strcmp(a, "--eps"))
            rc = arg_float(a, v, 0.0f, 1e30f, &o->eps, msg, len);
        else if (!strcmp(a, "--fov")) {
            rc = arg_float(a, v, 0.0f, 180.0f, &o->fov, msg, len);
            if (!rc && !(o->fov > 0.0f && o->fov < 180.0f)) {
                snprintf(msg, len, "--fov must be in (0, 180) degrees, got %s", v);
                rc = -1;
            }
            o->fov_set = 1;
        } else if (!strcmp(a, "--camera")) {
            rc = arg_floats(a, v, 6, o->camera, msg, len);
            o->camera_set = 1;
        } else if (!strcmp(a, "--max-steps")) {
            rc = arg_long(a, v, 1, MAX_STEPS, &n, msg, len);
            o->max_steps = n;
        } else if (!strcmp(a, "--width")) {
            rc = arg_long(a, v, 1, MAX_SIDE, &n, msg, len);
            o->width = n;
        } else if (!strcmp(a, "--height")) {
            rc = arg_long(a, v, 1, MAX_SIDE, &n, msg, len);
            o->height = n;
        } else if (!strcmp(a, "--heatmap-max")) {
            rc = arg_long(a, v, 1, MAX_STEPS, &n, msg, len);
            o->heatmap_max = n;
        } else if (!strcmp(a, "--threads")) {
            rc = arg_long(a, v, 0, MAX_THREADS, &n, msg, len);
            o->threads = n;
        } else if (!strcmp(a, "--heatmap")) {
            if (strcmp(v, "steps") && strcmp(v, "fallbacks")) {
                snprintf(msg, len, "--heatmap needs 'steps' or 'fallbacks', got '%s'", v);
                return -1;
            }
            o->heatmap_kind = strcmp(v, "steps") ? SDFT_HEATMAP_FALLBACKS : SDFT_HEATMAP_STEPS;
            o->heatmap = argv[++i];
        }
        if (rc)
            return -1;
    }
    return 0;
}

/* The checks that need all the options at once. */
static int check_opts(const render_opts *o, char *msg, size_t len)
{
    if (!o->out)
        snprintf(msg, len, "-o OUT.exr is required");
    else if (o->width * o->height > MAX_PIXELS)
        snprintf(msg, len, "%ldx%ld is more than %ld pixels", o->width, o->height, MAX_PIXELS);
    else if (o->heatmap_max && !o->heatmap)
        snprintf(msg, len, "--heatmap-max needs --heatmap");
    else if (o->fp16 && !o->grid)
        snprintf(msg, len, "--fp16 applies to a --grid .vdb file");
    else if (o->camera_set && o->camera[0] == o->camera[3] && o->camera[1] == o->camera[4] &&
             o->camera[2] == o->camera[5])
        snprintf(msg, len, "--camera: the eye and the look-at point must differ");
    else
        return 0;
    return -1;
}

/* The field to render, with its default camera and light: the one place a
 * new kind of source (a grid file) comes in, with its release in close_field. */
static int open_grid(const render_opts *o, render_source *src, char *msg, size_t len);

static int open_field(const render_opts *o, render_source *src, char *msg, size_t len)
{
    if (o->grid)
        return open_grid(o, src, msg, len);
    if (!o->scene) {
        snprintf(msg, len, "--scene is required (sdftrace scenes lists them)");
        return -1;
    }
    const sdft_scene *scene = sdft_scene_find(o->scene);
    if (!scene) {
        snprintf(msg, len, "unknown scene '%s' (sdftrace scenes lists them)", o->scene);
        return -1;
    }
    *src = (render_source){.field = scene->field, .camera = scene->camera, .light = scene->light, .name = scene->name};
    return 0;
}

/* A .vdb file's loading, drawn as the shared progress bar. */
static int show_loading(void *user, float done)
{
    sdft_progress_bar_show(user, "loading", (int)(100.0f * done));
    return 0;
}

/* A grid file as the field. Its view: the scene's, given --scene, else a
 * camera in front of (+z) the active bounding box framing it, a light above. */
static int open_grid(const render_opts *o, render_source *src, char *msg, size_t len)
{
    const sdft_scene *scene = NULL;
    if (o->scene && !(scene = sdft_scene_find(o->scene))) {
        snprintf(msg, len, "unknown scene '%s' (sdftrace scenes lists them)", o->scene);
        return -1;
    }
    sdft_grid *g = NULL;
    const char *dot = strrchr(o->grid, '.');
    const int vdb = dot && strcmp(dot, ".vdb") == 0;
    if (o->fp16 && !vdb) {
        snprintf(msg, len, "--fp16 converts a .vdb file; %s is loaded as it is stored", o->grid);
        return -1;
    }
    sdft_progress_bar bar;
    sdft_progress_bar_init(&bar, !o->quiet);
    sdft_vdb_options vo = sdft_vdb_options_defaults();
    vo.quant = o->fp16 ? SDFT_QUANT_FP16 : SDFT_QUANT_NONE;
    vo.progress = show_loading;
    vo.defer = 1; /* leaves read as rays reach them: the first image sooner, memory for what it shows */
    vo.progress_user = &bar;
    const sdft_error rc = vdb ? sdft_vdb_open(o->grid, o->grid_name, &vo, &g, msg, len)
                              : sdft_grid_open(o->grid, o->grid_name, &g, msg, len);
    sdft_progress_bar_clear(&bar);
    if (rc)
        return -1;
    *src = (render_source){.field = sdft_grid_field(g), .name = sdft_grid_name(g), .grid = g};
    if (scene) {
        src->camera = scene->camera, src->light = scene->light;
        return 0;
    }
    src->camera = sdft_camera_front(sdft_grid_world_bounds(g), (int)o->width, (int)o->height, 40.0f);
    const sdft_vec3 c = src->camera.at;
    const float dist = src->camera.from.z - c.z;
    src->light = sdft_v3(c.x, c.y + 2.0f * dist, c.z + dist);
    return 0;
}

static void close_field(render_source *src) { sdft_grid_free(src->grid); }

/* Whether render frees its field before the process exits. Not in a
 * release build: once the image is written the process ends, and the
 * kernel takes its memory back at once, where freeing a big grid piece by
 * piece does not come cheap (a deferred 4096^3 grid keeps OpenVDB's tree,
 * a million leaves each with its own file reference: 0.1 to 0.2 s of a 1.8 s run
 * on two cores), the way compilers skip freeing at exit. Sanitizer builds
 * free it, so that LeakSanitizer accounts for every allocation. */
#if defined(__SANITIZE_ADDRESS__)
enum { FREE_AT_EXIT = 1 };
#else
enum { FREE_AT_EXIT = 0 };
#endif

static sdft_render_params make_params(const render_opts *o, const render_source *src)
{
    sdft_render_params p = sdft_render_defaults();
    p.trace.method = o->method;
    p.trace.omega = o->omega_set ? o->omega : sdft_default_omega(o->method);
    p.trace.beta = o->beta;
    p.trace.eps = o->eps;
    p.trace.max_steps = (uint32_t)o->max_steps;
    p.width = (int)o->width, p.height = (int)o->height;
    p.camera = src->camera;
    if (o->camera_set) {
        p.camera.from = sdft_v3(o->camera[0], o->camera[1], o->camera[2]);
        p.camera.at = sdft_v3(o->camera[3], o->camera[4], o->camera[5]);
    }
    if (o->fov_set)
        p.camera.fov_deg = o->fov;
    p.light = src->light;
    p.shadows = o->shadows;
    p.screen_space = o->screen_space;
    p.cones = o->cones;
    p.trace.exact_root = o->exact_root;
    p.depth_only = o->depth_only;
    p.threads = (int)o->threads;
    return p;
}

/* Writes every requested file; on a failure removes the ones this run
 * already wrote, so the outputs appear together or not at all. */
static int write_outputs(const render_opts *o, const sdft_image *img, char *msg, size_t len)
{
    if (sdft_write_exr(o->out, img, msg, len))
        return -1;
    if (o->png && sdft_write_png(o->png, img, msg, len)) {
        remove(o->out);
        return -1;
    }
    if (o->heatmap && sdft_write_heatmap(o->heatmap, img, o->heatmap_kind, (unsigned long)o->heatmap_max, msg, len)) {
        remove(o->out);
        if (o->png)
            remove(o->png);
        return -1;
    }
    return 0;
}

/* The traced grid's NanoVDB bytes; 0 for a procedural scene. */
static size_t grid_bytes(const render_source *src) { return src->grid ? sdft_grid_size(src->grid) : 0; }

/* The grid's leaves and how many the render read from the file (all of
 * them when it was loaded whole); 0 and 0 for a procedural scene. */
static void grid_leaves(const render_source *src, uint64_t *leaves, uint64_t *filled, uint64_t *failed)
{
    *leaves = *filled = *failed = 0;
    if (src->grid)
        sdft_grid_leaf_counts(src->grid, leaves, filled, failed);
}

static void print_json(const render_source *src, const sdft_render_params *p, const sdft_render_stats *st)
{
    double primary = (double)st->primary_rays;
    uint64_t leaves, filled, failed;
    grid_leaves(src, &leaves, &filled, &failed);
    printf("{\"scene\": ");
    sdft_json_put_string(stdout, src->name);
    printf(", \"method\": \"%s\", \"omega\": %.6g, \"beta\": %.6g, \"eps\": %.6g, \"max_steps\": %u, "
           "\"width\": %d, \"height\": %d, \"shadows\": %s, \"screen_space\": %s, \"cones\": %s, \"exact_root\": %s, "
           "\"threads\": %d, "
           "\"ms\": %.3f, \"rays\": %llu, \"primary_rays\": %llu, \"steps\": %llu, \"primary_steps\": %llu, "
           "\"cone_steps\": %llu, \"fallbacks\": %llu, \"primary_fallbacks\": %llu, \"mean_steps\": %.4f, "
           "\"mean_primary_steps\": %.4f, \"mean_shadow_steps\": %.4f, \"mean_cone_steps\": %.4f, "
           "\"mean_fallbacks\": %.4f, \"mean_primary_fallbacks\": %.4f, \"nonconverged\": %.6f, "
           "\"hit_fraction\": %.6f, \"grid_bytes\": %zu, \"grid_leaves\": %llu, \"grid_leaves_read\": %llu}\n",
           sdft_method_name(p->trace.method), p->trace.omega, p->trace.beta, p->trace.eps, p->trace.max_steps, p->width,
           p->height, p->shadows ? "true" : "false", p->screen_space ? "true" : "false", p->cones ? "true" : "false",
           p->trace.exact_root ? "true" : "false", p->threads, st->ms, (unsigned long long)st->rays,
           (unsigned long long)st->primary_rays, (unsigned long long)st->steps, (unsigned long long)st->primary_steps,
           (unsigned long long)st->cone_steps, (unsigned long long)st->fallbacks,
           (unsigned long long)st->primary_fallbacks, (double)st->steps / primary, (double)st->primary_steps / primary,
           (double)(st->steps - st->primary_steps) / primary, (double)st->cone_steps / primary,
           (double)st->fallbacks / primary, (double)st->primary_fallbacks / primary, (double)st->nonconverged / primary,
           (double)st->hits / primary, grid_bytes(src), (unsigned long long)leaves, (unsigned long long)filled);
}

/* The one line on stderr when a render is done: what was made, how much
 * of it hit, how long the trace and the whole command took, where it went. */
static void print_summary(const render_opts *o, const sdft_render_params *p, const sdft_render_stats *st,
                          double total_s)
{
    fprintf(stderr,
            "render: %dx%d, %.1f%% hit, %.1f evaluations per pixel, trace %.0f ms, %.2f s in all -> %s%s%s%s%s\n",
            p->width, p->height, 100.0 * (double)st->hits / (double)st->primary_rays,
            (double)(st->steps + st->cone_steps) / (double)st->primary_rays, st->ms, total_s, o->out,
            o->png ? ", " : "", o->png ? o->png : "", o->heatmap ? ", " : "", o->heatmap ? o->heatmap : "");
}

/* A deferred grid's leaves that could not be read from its file during the
 * render (it changed or went away): an error, and no output. */
static int leaves_unreadable(const render_opts *o, const render_source *src, char *msg, size_t len)
{
    uint64_t leaves, filled, failed;
    grid_leaves(src, &leaves, &filled, &failed);
    if (!failed)
        return 0;
    snprintf(msg, len, "%s: %llu leaves could not be read while rendering (did the file change?)", o->grid,
             (unsigned long long)failed);
    return 1;
}

int cmd_render(int argc, char **argv)
{
    const double start = omp_get_wtime();
    char msg[512] = "";
    render_opts o = default_opts();
    int parsed = parse_opts(argc, argv, &o, msg, sizeof msg);
    if (parsed == 1) {
        cmd_render_help(stdout);
        return 0;
    }
    if (parsed || check_opts(&o, msg, sizeof msg)) {
        cli_error("render", msg);
        return 2;
    }
    render_source src;
    if (open_field(&o, &src, msg, sizeof msg)) {
        cli_error("render", msg);
        return 2;
    }
    sdft_render_params p = make_params(&o, &src);
    if (sdft_trace_params_check(&p.trace, msg, sizeof msg) || sdft_check_writable(o.out, msg, sizeof msg) ||
        (o.png && sdft_check_writable(o.png, msg, sizeof msg)) ||
        (o.heatmap && sdft_check_writable(o.heatmap, msg, sizeof msg))) {
        cli_error("render", msg);
        close_field(&src);
        return 2;
    }

    sdft_image img;
    sdft_render_stats st;
    int rc = 0;
    if (sdft_image_alloc(&img, p.width, p.height, msg, sizeof msg)) {
        rc = 1;
    } else if (sdft_render(&src.field, &p, &img, &st, msg, sizeof msg)) {
        rc = 2; /* parameters the renderer rejects, e.g. a degenerate camera */
    } else if (leaves_unreadable(&o, &src, msg, sizeof msg) || write_outputs(&o, &img, msg, sizeof msg)) {
        rc = 1;
    }
    if (rc)
        cli_error("render", msg);
    else if (o.json)
        print_json(&src, &p, &st);
    sdft_image_free(&img);
    if (FREE_AT_EXIT)
        close_field(&src);
    if (!rc && !o.quiet)
        print_summary(&o, &p, &st, omp_get_wtime() - start);
    return rc;
}
