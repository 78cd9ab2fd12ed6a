/* sdftrace render — a field (today a procedural scene) through the renderer
 * to OpenEXR, with an optional PNG preview, count heatmaps and a JSON line
 * of statistics. The steps: parse the options, check them, open the field,
 * check the outputs can be written, render, write, report. */
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cmdline.h"
#include "commands.h"
#include "image_io.h"
#include "json.h"
#include "peak_memory.h"
#include "progress_bar.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/vdb.h"
#if defined(SDFT_WITH_VULKAN)
#include "sdftrace/gpu.h"
#endif

enum { MAX_SIDE = 16384, MAX_STEPS = 10000000, MAX_THREADS = 1024, MAX_REPEAT = 100000 };
static const long MAX_PIXELS = 64l * 1024 * 1024;

typedef struct render_opts {
    const char *scene;            /* --scene NAME */
    const char *grid, *grid_name; /* --grid FILE, --grid-name NAME */
    sdft_method method;           /* --method */
    int omega_set;                /* --omega given; else the method's default */
    float omega, beta, eps;
    int max_steps, width, height, threads;
    int heatmap_max;         /* --heatmap-max: the scale's top; 0: the largest count, rounded up */
    int camera_set, fov_set; /* override the scene's view */
    float camera[6], fov;
    int shadows, screen_space, cones, exact_root, depth_only, json, quiet, fp16;
    int materials;     /* --materials 1, --no-materials 0; -1: the scene's own choice */
    int material_set;  /* --material given */
    float material[5]; /* R, G, B, reflectance, index of refraction */
    int bounces[2];    /* --bounces R,T */
    float eps_min, soft_shadows;
    int smooth_iters, convex, ao;
    int repeat; /* --repeat N: frames traced in one process */
    const char *out, *png;
    const char *heatmap[2]; /* --heatmap KIND FILE */
    int vulkan;             /* --device vulkan */
    int vulkan_device;      /* --vulkan-device N; -1: the first GPU */
} render_opts;

/* What is rendered: a field, its default view and light, and whatever must
 * be released afterwards (a grid's buffer, later). */
typedef struct render_source {
    sdft_field field;
    sdft_camera camera;
    sdft_vec3 light;
    const char *name; /* for the JSON report */
    sdft_grid *grid;  /* --grid: owned, freed by close_field */
    sdft_grid *ids;   /* the grid's material indices, when its file has them: owned, freed by close_field */
    int materials;    /* the scene is made to be seen with its materials */
    char device[256]; /* what rendered it: "cpu", or the Vulkan device's name */
} render_source;

/* Where one call's time went, phase by phase (--json), in wall ms. */
typedef struct render_timing {
    double open_ms;           /* the field opened: a grid read, checked and its acceleration structures built */
    sdft_grid_phases grid;    /* a grid's parts of that (sdftrace/grid.h) */
    double image_ms;          /* the image allocated */
    double first_ms, best_ms; /* the first frame's trace, the fastest frame's (of --repeat) */
    double warm_ms;           /* the fastest frame after the first; NAN with one frame */
    int frames;
    double write_ms; /* the outputs written */
} render_timing;

static render_opts default_opts(void)
{
    sdft_render_params d = sdft_render_defaults();
    return (render_opts){
        .method = d.trace.method,
        .beta = d.trace.beta,
        .eps = d.trace.eps,
        .max_steps = (int)d.trace.max_steps,
        .width = d.width,
        .height = d.height,
        .threads = 0,
        .shadows = 1,
        .cones = d.cones,
        .exact_root = d.trace.exact_root,
        .materials = -1,
        .material = {d.material.colour.x, d.material.colour.y, d.material.colour.z, d.material.reflectance,
                     d.material.ior},
        .bounces = {d.reflect_bounces, d.refract_bounces},
        .eps_min = d.eps_min,
        .soft_shadows = d.soft_shadows,
        .smooth_iters = d.smooth_iters,
        .convex = d.convex,
        .ao = d.ao,
        .repeat = 1,
        .vulkan_device = -1,
    };
}

/* --bounces R,T: two whole numbers in [0, SDFT_MAX_BOUNCES]. */
static int set_bounces(void *target, const char *value, char *msg, size_t len)
{
    int *b = target, used = 0;
    if (!value || sscanf(value, "%d,%d%n", &b[0], &b[1], &used) != 2 || value[used] != '\0' || b[0] < 0 ||
        b[0] > SDFT_MAX_BOUNCES || b[1] < 0 || b[1] > SDFT_MAX_BOUNCES) {
        snprintf(msg, len, "--bounces needs R,T, two whole numbers in [0, %d] (reflections, refractions), got '%s'",
                 SDFT_MAX_BOUNCES, value ? value : "");
        return -1;
    }
    return 0;
}

/* --device cpu|vulkan. */
static int set_device(void *target, const char *value, char *msg, size_t len)
{
    int *vulkan = target;
    if (value && strcmp(value, "cpu") == 0) {
        *vulkan = 0;
        return 0;
    }
    if (value && strcmp(value, "vulkan") == 0) {
        *vulkan = 1;
        return 0;
    }
    snprintf(msg, len, "--device needs cpu or vulkan, got '%s'", value ? value : "");
    return -1;
}

static int set_method(void *target, const char *value, char *msg, size_t len)
{
    return sdft_method_parse(value, target, msg, len) ? -1 : 0;
}

/* --papers: the papers' way of counting, every ray from the eye, every step to eps. */
static int set_papers(void *target, const char *value, char *msg, size_t len)
{
    (void)value, (void)msg, (void)len;
    render_opts *o = target;
    o->cones = 0, o->exact_root = 0;
    return 0;
}

enum { RENDER_ROWS = 47 };

/* The options of `sdftrace render`, over o (for the help, over the
 * defaults), in rows; and the command line they make. */
static cmdline_spec render_options(render_opts *o, cmdline_option rows[RENDER_ROWS])
{
    static char omega_def[64];
    snprintf(omega_def, sizeof omega_def, "relaxed, relaxed-bv %g; enhanced %g", sdft_default_omega(SDFT_RELAXED),
             sdft_default_omega(SDFT_ENHANCED));
    const double inf = INFINITY;
    const cmdline_option t[RENDER_ROWS] = {
        {"scene", 0, "NAME", "procedural scene (sdftrace scenes lists them); required without --grid", CMDLINE_TEXT,
         &o->scene, .def = ""},
        {"grid", 0, "FILE", "render a level set (.vdb or .nvdb); with --scene, from that scene's camera and light",
         CMDLINE_TEXT, &o->grid, .def = ""},
        {"grid-name", 0, "NAME", "the grid of FILE to render", CMDLINE_TEXT, &o->grid_name,
         .def = "the first scalar level set"},
        {NULL, 'o', "OUT.exr", "OpenEXR output: R,G,B, Z, N.X,N.Y,N.Z, steps, fallbacks; required", CMDLINE_TEXT,
         &o->out, .def = ""},
        {"method", 0, "M", "sphere | relaxed (Keinert) | relaxed-bv (Ban-Valasek Alg. 2) | enhanced | auto",
         CMDLINE_CALL, &o->method, .def = sdft_method_name(o->method), .handle = set_method},
        {"omega", 0, "W", "relaxed, relaxed-bv: [1, 2); enhanced: (0, 1]", CMDLINE_FLOAT, &o->omega, .lo = -inf,
         .hi = inf, .def = omega_def, .seen = &o->omega_set},
        {"beta", 0, "B", "auto: (0, 1)", CMDLINE_FLOAT, &o->beta, .lo = -inf, .hi = inf},
        {"eps", 0, "E", "convergence radius, world units", CMDLINE_FLOAT, &o->eps, .lo = 0.0, .hi = inf},
        {"max-steps", 0, "N", "most SDF evaluations per ray", CMDLINE_INT, &o->max_steps, .lo = 1, .hi = MAX_STEPS},
        {"width", 0, "W", "image width, pixels", CMDLINE_INT, &o->width, .lo = 1, .hi = MAX_SIDE},
        {"height", 0, "H", "image height, pixels", CMDLINE_INT, &o->height, .lo = 1, .hi = MAX_SIDE},
        {"camera", 0, "FX,FY,FZ,AX,AY,AZ", "eye and look-at point", CMDLINE_FLOATS, o->camera, .value = 6,
         .def = "the scene's", .seen = &o->camera_set},
        {"fov", 0, "DEG", "vertical field of view, (0, 180)", CMDLINE_FLOAT, &o->fov, .lo = 0.0, .hi = 180.0,
         .open = CMDLINE_OPEN_LO | CMDLINE_OPEN_HI, .def = "the scene's", .seen = &o->fov_set},
        {"no-shadows", 0, NULL, "no shadow rays", CMDLINE_SET, &o->shadows, .value = 0,
         .def = "a shadow ray per lit hit"},
        {"screen-space", 0, NULL, "Keinert's screen-space criterion: eps grows by half a pixel per unit t", CMDLINE_SET,
         &o->screen_space, .value = 1, .def = "off"},
        {"cones", 0, NULL, NULL, CMDLINE_SET, &o->cones, .value = 1}, /* the default; kept so that older scripts run */
        {"no-cones", 0, NULL,
         "every primary ray from the eye. Default: on a grid, each primary ray is traced\n"
         "only where it crosses the grid's hull (boxes around the cells the surface\n"
         "crosses, each cut to a slab along the surface, found by ray-box and ray-slab\n"
         "tests, no evaluation; boxes whose surface faces away from the eye left out);\n"
         "on a scene, the rays of each 16x16 tile, then of each 4x4 block, first march\n"
         "together as one cone, then each on its own from there (the cones' steps\n"
         "counted apart: cone_steps). Faster, the same picture",
         CMDLINE_SET, &o->cones, .value = 0, .def = ""},
        {"no-exact-root", 0, NULL,
         "sphere steps to eps to the end. Default: near the surface of a grid, the exact\n"
         "first root of its trilinear interpolant, cell by cell (each cell read counts\n"
         "as one evaluation); procedural scenes always step to eps",
         CMDLINE_SET, &o->exact_root, .value = 0, .def = ""},
        {"papers", 0, NULL,
         "the papers' way of counting: --no-cones --no-exact-root (every ray from the\n"
         "eye, every step to eps); what the method comparisons use",
         CMDLINE_CALL, o, .def = "", .handle = set_papers},
        {"depth-only", 0, NULL, "primary rays only: depth (Z), status and counts; no normals, shading or shadows",
         CMDLINE_SET, &o->depth_only, .value = 1, .def = ""},
        {"materials", 0, NULL,
         "the scene's materials: colours, a checker floor, mirrors and glass, with\n"
         "reflections and refractions (Whitted); on for scenes made for them (jewel)",
         CMDLINE_SET, &o->materials, .value = 1, .def = "the scene's"},
        {"no-materials", 0, NULL, "one grey, opaque surface", CMDLINE_SET, &o->materials, .value = 0, .def = ""},
        {"material", 0, "R,G,B,REFL,IOR",
         "the one material of a field without its own (a grid): colour in [0, 1],\n"
         "reflectance in [0, 1], index of refraction (0 opaque, else >= 1; glass 1.5)",
         CMDLINE_FLOATS, o->material, .value = 5, .def = "grey, opaque", .seen = &o->material_set},
        {"bounces", 0, "R,T", "most reflections and refractions along a path, each in [0, 16]", CMDLINE_CALL,
         o->bounces, .def = "2,8", .handle = set_bounces},
        {"eps-min", 0, "E",
         "secondary rays leave a hit p by 2 max(E, |f(p)|) along the normal (Keinert's\n"
         "dynamic epsilon), world units",
         CMDLINE_FLOAT, &o->eps_min, .lo = 0.0, .hi = inf, .def = "the field's feature size, the normal's step"},
        {"smooth-iters", 0, "K", "discontinuity reduction: K fixed-point iterations per hit (the paper: 3)",
         CMDLINE_INT, &o->smooth_iters, .lo = 0, .hi = SDFT_MAX_SMOOTH_ITERS},
        {"no-convex", 0, NULL, "rays inside a convex part march through it, not back from its bounding sphere",
         CMDLINE_SET, &o->convex, .value = 0, .def = "from the sphere's far side"},
        {"soft-shadows", 0, "K", "soft shadows, the penumbra min K d / t (sharper as K grows; 8 is soft)",
         CMDLINE_FLOAT, &o->soft_shadows, .lo = 0.0, .hi = inf, .open = CMDLINE_OPEN_LO, .def = "hard shadows"},
        {"ao", 0, NULL, "ambient occlusion, five samples along the normal", CMDLINE_SET, &o->ao, .value = 1,
         .def = "off"},
        {"fp16", 0, NULL, "load a .vdb grid as NanoVDB Fp16 (half the memory; values within 1/2048 of the band)",
         CMDLINE_SET, &o->fp16, .value = 1, .def = ""},
        {"quiet", 0, NULL, "no progress line while loading, no summary line when done (both on stderr)", CMDLINE_SET,
         &o->quiet, .value = 1, .def = ""},
        {"threads", 0, "N", "OpenMP threads, 0 = all cores", CMDLINE_INT, &o->threads, .lo = 0, .hi = MAX_THREADS},
        {"repeat", 0, "N",
         "trace the frame N times in one process, the same picture each time; the\n"
         "summary and --json time the first and the best (the file written is the last)",
         CMDLINE_INT, &o->repeat, .lo = 1, .hi = MAX_REPEAT},
        {"device", 0, "cpu|vulkan",
         "vulkan: trace a grid (--grid) on a GPU, one invocation a pixel, with the same\n"
         "trace code; hard shadows on the grey surface (no materials, soft shadows or\n"
         "occlusion); ms is the GPU's time for the frame",
         CMDLINE_CALL, &o->vulkan, .def = "cpu", .handle = set_device},
        {"vulkan-device", 0, "N", "the Vulkan device, as vulkaninfo lists them (-1: the first GPU, else any)",
         CMDLINE_INT, &o->vulkan_device, .lo = -1, .hi = 1024},
        {"png", 0, "OUT.png", "sRGB preview", CMDLINE_TEXT, &o->png, .value = 1},
        {"heatmap", 0, "steps|fallbacks OUT.png", "false-colour map of the per-pixel counts", CMDLINE_TEXT, o->heatmap,
         .value = 2, .def = "none"},
        {"heatmap-max", 0, "N", "the heatmap's scale runs 0..N, larger counts are red, so that maps share a scale\n",
         CMDLINE_INT, &o->heatmap_max, .lo = 1, .hi = MAX_STEPS,
         .def = "the largest count, rounded up to a multiple of 4"},
        {"json", 0, NULL, "print one JSON object of statistics on stdout", CMDLINE_SET, &o->json, .value = 1,
         .def = "off"},
        {"help", 'h', NULL, NULL, CMDLINE_HELP, NULL, .def = ""},
        {0},
    };
    memcpy(rows, t, sizeof t);
    return (cmdline_spec){
        .program = "sdftrace render",
        .usage = "usage: sdftrace render --scene NAME | --grid FILE -o OUT.exr [options]\n",
        .rows = rows,
        .column = 24,
    };
}

void cmd_render_help(FILE *out)
{
    render_opts d = default_opts();
    cmdline_option rows[RENDER_ROWS];
    const cmdline_spec spec = render_options(&d, rows);
    cmdline_help(&spec, out);
}

/* Fills opts from argv; CMDLINE_OK, _HELP_ASKED, or _ERROR with msg. */
static int parse_opts(int argc, char **argv, render_opts *o, char *msg, size_t len)
{
    cmdline_option rows[RENDER_ROWS];
    const cmdline_spec spec = render_options(o, rows);
    return cmdline_parse(&spec, argc, argv, msg, len);
}

/* The checks that need all the options at once. */
static int check_opts(const render_opts *o, char *msg, size_t len)
{
    const char *kind = o->heatmap[0];
    if (kind && strcmp(kind, "steps") && strcmp(kind, "fallbacks"))
        snprintf(msg, len, "--heatmap needs 'steps' or 'fallbacks', got '%s'", kind);
    else if (!o->out)
        snprintf(msg, len, "-o OUT.exr is required");
    else if ((long)o->width * o->height > MAX_PIXELS)
        snprintf(msg, len, "%dx%d is more than %ld pixels", o->width, o->height, MAX_PIXELS);
    else if (o->heatmap_max && !o->heatmap[1])
        snprintf(msg, len, "--heatmap-max needs --heatmap");
    else if (o->fp16 && !o->grid)
        snprintf(msg, len, "--fp16 applies to a --grid .vdb file");
    else if (o->vulkan && !o->grid)
        snprintf(msg, len, "--device vulkan renders grids: give --grid FILE");
    else if (o->vulkan && o->fp16)
        snprintf(msg, len, "--device vulkan renders float grids: leave out --fp16");
    else if (o->camera_set && o->camera[0] == o->camera[3] && o->camera[1] == o->camera[4] &&
             o->camera[2] == o->camera[5])
        snprintf(msg, len, "--camera: the eye and the look-at point must differ");
    else if (render_memory_check(o->width, o->height, msg, len) == 0)
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
    *src = (render_source){.field = scene->field,
                           .camera = scene->camera,
                           .light = scene->light,
                           .name = scene->name,
                           .materials = scene->materials};
    return 0;
}

/* A .vdb file's loading, drawn as the shared progress bar. */
static int show_loading(void *user, float done)
{
    progress_bar_show(user, "loading", (int)(100.0f * done));
    return 0;
}

/* The grid `name` of the --grid file into *out; SDFT_ENOTFOUND quietly
 * when it has none. */
static sdft_error open_beside(const render_opts *o, const char *name, sdft_grid **out, char *msg, size_t len)
{
    sdft_grid_options vo = sdft_grid_options_defaults();
    vo.path = o->grid, vo.name = name;
    return sdft_vdb_open(&vo, out, msg, len);
}

/* The surface's materials, when the file has them beside it (SURFACE.material_ids and
 * SURFACE.material_table, as `sdftrace bake --materials` writes them): set on src->grid,
 * the indices kept in src->ids; without them, nothing. 0, or -1 with msg. */
static int open_grid_materials(const render_opts *o, render_source *src, char *msg, size_t len)
{
    char ids_name[300], table_name[300];
    snprintf(ids_name, sizeof ids_name, "%s.material_ids", src->name);
    snprintf(table_name, sizeof table_name, "%s.material_table", src->name);
    sdft_error rc = open_beside(o, ids_name, &src->ids, msg, len);
    if (rc == SDFT_ENOTFOUND)
        return 0;
    if (rc)
        return -1;
    sdft_grid *t = NULL;
    rc = open_beside(o, table_name, &t, msg, len);
    if (rc == SDFT_ENOTFOUND)
        snprintf(msg, len, "%s: no grid %.100s beside the material indices", o->grid, table_name);
    static sdft_material table[SDFT_GRID_MAX_MATERIALS];
    size_t count = 0;
    if (!rc)
        rc = sdft_grid_material_table(t, table, SDFT_GRID_MAX_MATERIALS, &count, msg, len);
    sdft_grid_free(t);
    if (!rc)
        rc = sdft_grid_set_materials(src->grid, src->ids, table, count, msg, len);
    if (rc) {
        sdft_grid_free(src->ids);
        src->ids = NULL;
        return -1;
    }
    src->materials = 1;
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
    progress_bar bar;
    progress_bar_init(&bar, !o->quiet);
    sdft_grid_options vo = sdft_grid_options_defaults();
    vo.path = o->grid, vo.name = o->grid_name;
    vo.quant = o->fp16 ? SDFT_QUANT_FP16 : SDFT_QUANT_NONE;
    vo.progress = show_loading;
    /* .vdb: leaves read as rays reach them: the first image sooner, memory
     * for what it shows; a GPU takes the grid whole */
    vo.defer = o->vulkan ? SDFT_DEFER_NONE : SDFT_DEFER_WHERE_EXACT;
    vo.progress_user = &bar;
    const sdft_error rc = sdft_vdb_open(&vo, &g, msg, len);
    progress_bar_clear(&bar);
    if (rc)
        return -1;
    *src = (render_source){.name = sdft_grid_name(g), .grid = g};
    if (o->materials != 0 && open_grid_materials(o, src, msg, len)) {
        sdft_grid_free(g);
        return -1;
    }
    src->field = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
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

static void close_field(render_source *src)
{
    sdft_grid_free(src->grid);
    sdft_grid_free(src->ids);
}

/* Whether the field declares convex parts for Keinert's 3.5. */
static int has_convex_parts(const sdft_field *f) { return f->accel && f->accel->convex_count > 0; }

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
    p.materials = o->materials >= 0 ? o->materials : (src->materials || o->material_set);
    if (o->material_set)
        p.material = (sdft_material){.colour = sdft_v3(o->material[0], o->material[1], o->material[2]),
                                     .reflectance = o->material[3],
                                     .ior = o->material[4]};
    p.reflect_bounces = o->bounces[0], p.refract_bounces = o->bounces[1];
    p.eps_min = o->eps_min;
    p.smooth_iters = o->smooth_iters;
    p.convex = o->convex && has_convex_parts(&src->field); /* as applied, for the JSON */
    p.soft_shadows = o->soft_shadows;
    p.ao = o->ao;
    return p;
}

/* Writes every requested file, together: all of them or none
 * (src/common/atomic_file.h's sets). */
static int write_outputs(const render_opts *o, const sdft_image *img, char *msg, size_t len)
{
    const char *paths[3] = {o->out};
    size_t n = 1;
    if (o->png)
        paths[n++] = o->png;
    if (o->heatmap[1])
        paths[n++] = o->heatmap[1];
    atomic_file files[3];
    if (atomic_files_begin(files, paths, n, msg, len))
        return -1;
    const io_heatmap_kind kind =
        o->heatmap[0] && strcmp(o->heatmap[0], "steps") ? SDFT_HEATMAP_FALLBACKS : SDFT_HEATMAP_STEPS;
    if (io_write_exr_into(&files[0], img, msg, len) || (o->png && io_write_png_into(&files[1], img, msg, len)) ||
        (o->heatmap[1] && io_write_heatmap_into(&files[n - 1], img, kind, (unsigned long)o->heatmap_max, msg, len))) {
        atomic_files_abort(files, n);
        return -1;
    }
    return atomic_files_commit(files, n, msg, len) ? -1 : 0;
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

/* The grid rendered on the Vulkan device o asks for (sdftrace/gpu.h): the
 * device opened, the grid uploaded, one frame, all released; the device's
 * name into src->device. */
static sdft_error render_vulkan(const render_opts *o, render_source *src, const sdft_render_params *p, sdft_image *img,
                                sdft_render_stats *st, char *msg, size_t len)
{
#if defined(SDFT_WITH_VULKAN)
    sdft_gpu_options go = sdft_gpu_options_defaults();
    go.device = o->vulkan_device;
    sdft_gpu *gpu = NULL;
    sdft_gpu_grid *gg = NULL;
    sdft_error rc = sdft_gpu_create(&go, &gpu, msg, len);
    if (!rc) {
        snprintf(src->device, sizeof src->device, "%s", sdft_gpu_device_name(gpu));
        rc = sdft_gpu_grid_create(gpu, src->grid, &gg, msg, len);
    }
    if (!rc)
        rc = sdft_gpu_render(gg, p, img, st, msg, len);
    sdft_gpu_grid_release(gg);
    sdft_gpu_release(gpu);
    return rc;
#else
    (void)o, (void)src, (void)p, (void)img, (void)st;
    snprintf(msg, len, "this sdftrace was built without Vulkan (SDFT_WITH_VULKAN: libvulkan-dev and glslc)");
    return SDFT_EINVAL;
#endif
}

/* sdft_render, or with --device vulkan the GPU's, and the processor time
 * its threads took together, in *cpu_ms: on a machine shared with other
 * work it moves less than the wall time (the stats' ms). */
static sdft_error render_timed(const render_opts *o, render_source *src, const sdft_render_params *p, sdft_image *img,
                               sdft_render_stats *st, double *cpu_ms, char *msg, size_t len)
{
    const clock_t c0 = clock();
    snprintf(src->device, sizeof src->device, "cpu");
    const sdft_error rc =
        o->vulkan ? render_vulkan(o, src, p, img, st, msg, len) : sdft_render(&src->field, p, img, st, msg, len);
    *cpu_ms = 1000.0 * (double)(clock() - c0) / CLOCKS_PER_SEC;
    return rc;
}

/* A number of ms, or null where there is none (NAN). */
static void put_ms(const char *key, double ms)
{
    if (isnan(ms))
        printf("\"%s\": null, ", key);
    else
        printf("\"%s\": %.3f, ", key, ms);
}

/* The timing part of the JSON object: each phase of the call, in ms. */
static void print_json_timing(const render_timing *t, double wall_ms)
{
    const sdft_grid_phases *g = &t->grid;
    printf("\"frames\": %d, ", t->frames);
    put_ms("open_ms", t->open_ms);
    put_ms("read_ms", t->open_ms - g->check_ms - g->directory_ms - g->tables_ms - g->far_ms - g->hull_ms);
    put_ms("serial_ms", g->serial_ms);
    put_ms("check_ms", g->check_ms);
    put_ms("directory_ms", g->directory_ms);
    put_ms("tables_ms", g->tables_ms);
    put_ms("far_bound_ms", g->far_ms);
    put_ms("hull_ms", g->hull_ms);
    printf("\"far_bound_stored\": %s, \"hull_stored\": %s, ", g->far_stored ? "true" : "false",
           g->hull_stored ? "true" : "false");
    put_ms("image_ms", t->image_ms);
    put_ms("first_frame_ms", t->first_ms);
    put_ms("best_frame_ms", t->best_ms);
    put_ms("warm_frame_ms", t->warm_ms);
    put_ms("write_ms", t->write_ms);
    put_ms("wall_ms", wall_ms);
}

/* The frame, t->frames times: the first frame's stats and processor time
 * (the later frames repeat its picture and counts), and each frame's
 * trace time into t. */
static sdft_error render_frames(const render_opts *o, render_source *src, const sdft_render_params *p, sdft_image *img,
                                sdft_render_stats *st, double *cpu_ms, render_timing *t, char *msg, size_t len)
{
    sdft_error rc = render_timed(o, src, p, img, st, cpu_ms, msg, len);
    t->first_ms = t->best_ms = st->ms;
    for (int i = 1; i < t->frames && !rc; i++) {
        sdft_render_stats again;
        double cpu;
        rc = render_timed(o, src, p, img, &again, &cpu, msg, len);
        t->best_ms = fmin(t->best_ms, again.ms);
        t->warm_ms = i == 1 ? again.ms : fmin(t->warm_ms, again.ms);
    }
    return rc;
}

static void print_json(const render_source *src, const sdft_render_params *p, const sdft_render_stats *st,
                       double cpu_ms, const render_timing *t, double wall_ms)
{
    double primary = (double)st->primary_rays;
    uint64_t leaves, filled, failed;
    grid_leaves(src, &leaves, &filled, &failed);
    printf("{\"scene\": ");
    json_put_string(stdout, src->name);
    printf(", \"method\": \"%s\", \"omega\": %.6g, \"beta\": %.6g, \"eps\": %.6g, \"max_steps\": %u, "
           "\"width\": %d, \"height\": %d, \"shadows\": %s, \"screen_space\": %s, \"cones\": %s, \"exact_root\": %s, "
           "\"threads\": %d, "
           "\"ms\": %.3f, \"rays\": %llu, \"primary_rays\": %llu, \"steps\": %llu, \"primary_steps\": %llu, "
           "\"cone_steps\": %llu, \"fallbacks\": %llu, \"primary_fallbacks\": %llu, \"mean_steps\": %.4f, "
           "\"mean_primary_steps\": %.4f, \"mean_shadow_steps\": %.4f, \"mean_cone_steps\": %.4f, "
           "\"mean_fallbacks\": %.4f, \"mean_primary_fallbacks\": %.4f, \"nonconverged\": %.6f, "
           "\"hit_fraction\": %.6f, \"grid_bytes\": %zu, \"grid_leaves\": %llu, \"grid_leaves_read\": %llu, ",
           sdft_method_name(p->trace.method), p->trace.omega, p->trace.beta, p->trace.eps, p->trace.max_steps, p->width,
           p->height, p->shadows ? "true" : "false", p->screen_space ? "true" : "false", p->cones ? "true" : "false",
           p->trace.exact_root ? "true" : "false", p->threads, st->ms, (unsigned long long)st->rays,
           (unsigned long long)st->primary_rays, (unsigned long long)st->steps, (unsigned long long)st->primary_steps,
           (unsigned long long)st->cone_steps, (unsigned long long)st->fallbacks,
           (unsigned long long)st->primary_fallbacks, (double)st->steps / primary, (double)st->primary_steps / primary,
           (double)st->shadow_steps / primary, (double)st->cone_steps / primary, (double)st->fallbacks / primary,
           (double)st->primary_fallbacks / primary, (double)st->nonconverged / primary, (double)st->hits / primary,
           grid_bytes(src), (unsigned long long)leaves, (unsigned long long)filled);
    print_json_timing(t, wall_ms);
    printf("\"cpu_ms\": %.3f, \"materials\": %s, \"bounces\": [%d, %d], \"eps_min\": %.6g, \"smooth_iters\": %d, "
           "\"convex\": %s, "
           "\"soft_shadows\": %.6g, \"ao\": %s, \"shadow_steps\": %llu, \"secondary_rays\": %llu, "
           "\"secondary_steps\": %llu, \"mean_secondary_steps\": %.4f, \"dynamic_eps_hits\": %llu, "
           "\"dynamic_eps_from_f\": %llu, \"secondary_self_hits\": %llu, \"device\": ",
           cpu_ms, p->materials ? "true" : "false", p->reflect_bounces, p->refract_bounces,
           p->eps_min > 0.0f ? p->eps_min : sdft_field_feature_size(&src->field), p->smooth_iters,
           p->convex ? "true" : "false", p->soft_shadows, p->ao ? "true" : "false",
           (unsigned long long)st->shadow_steps, (unsigned long long)st->secondary_rays,
           (unsigned long long)st->secondary_steps, (double)st->secondary_steps / primary,
           (unsigned long long)st->dynamic_eps_hits, (unsigned long long)st->dynamic_eps_from_f,
           (unsigned long long)st->secondary_self_hits);
    json_put_string(stdout, src->device);
    printf("}\n");
}

/* The one line on stderr when a render is done: what was made, how much
 * of it hit, how long the trace and the whole command took, where it went. */
static void print_summary(const render_opts *o, const sdft_render_params *p, const sdft_render_stats *st,
                          const render_timing *t, double total_s)
{
    char best[64] = "";
    if (t->frames > 1)
        snprintf(best, sizeof best, " (best of %d: %.0f ms)", t->frames, t->best_ms);
    fprintf(stderr,
            "render: %dx%d, %.1f%% hit, %.1f evaluations per pixel, trace %.0f ms%s, %.2f s in all -> %s%s%s%s%s\n",
            p->width, p->height, 100.0 * (double)st->hits / (double)st->primary_rays,
            (double)(st->steps + st->cone_steps) / (double)st->primary_rays, st->ms, best, total_s, o->out,
            o->png ? ", " : "", o->png ? o->png : "", o->heatmap[1] ? ", " : "", o->heatmap[1] ? o->heatmap[1] : "");
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
    const int parsed = parse_opts(argc, argv, &o, msg, sizeof msg);
    if (parsed == CMDLINE_HELP_ASKED) {
        cmd_render_help(stdout);
        return 0;
    }
    if (parsed || check_opts(&o, msg, sizeof msg)) {
        cli_error("render", msg);
        return 2;
    }
    render_source src;
    render_timing t = {.frames = o.repeat, .warm_ms = NAN};
    double t0 = omp_get_wtime();
    if (open_field(&o, &src, msg, sizeof msg)) {
        cli_error("render", msg);
        return 2;
    }
    t.open_ms = 1e3 * (omp_get_wtime() - t0);
    if (src.grid)
        sdft_grid_load_phases(src.grid, &t.grid);
    if (!o.convex && !has_convex_parts(&src.field)) {
        if (o.grid)
            snprintf(msg, sizeof msg,
                     "--no-convex: a grid declares no convex parts, so the convex optimization (3.5) "
                     "never applies to %s",
                     o.grid);
        else
            snprintf(msg, sizeof msg,
                     "--no-convex: scene '%s' declares no convex parts, so the convex optimization "
                     "(3.5) never applies to it",
                     src.name);
        cli_error("render", msg);
        close_field(&src);
        return 2;
    }
    sdft_render_params p = make_params(&o, &src);
    if (sdft_trace_params_check(&p.trace, msg, sizeof msg) || atomic_file_check_writable(o.out, msg, sizeof msg) ||
        (o.png && atomic_file_check_writable(o.png, msg, sizeof msg)) ||
        (o.heatmap[1] && atomic_file_check_writable(o.heatmap[1], msg, sizeof msg))) {
        cli_error("render", msg);
        close_field(&src);
        return 2;
    }

    sdft_image img;
    sdft_render_stats st;
    double cpu_ms = 0.0;
    int rc = 0;
    t0 = omp_get_wtime();
    const sdft_error allocated = sdft_image_alloc(&img, p.width, p.height, msg, sizeof msg);
    t.image_ms = 1e3 * (omp_get_wtime() - t0);
    if (allocated) {
        rc = 1;
    } else if (render_frames(&o, &src, &p, &img, &st, &cpu_ms, &t, msg, sizeof msg)) {
        rc = 2; /* parameters the renderer rejects, e.g. a degenerate camera; no Vulkan device */
    } else if (leaves_unreadable(&o, &src, msg, sizeof msg)) {
        rc = 1;
    } else {
        t0 = omp_get_wtime();
        rc = write_outputs(&o, &img, msg, sizeof msg) ? 1 : 0;
        t.write_ms = 1e3 * (omp_get_wtime() - t0);
    }
    if (rc)
        cli_error("render", msg);
    else if (o.json)
        print_json(&src, &p, &st, cpu_ms, &t, 1e3 * (omp_get_wtime() - start));
    sdft_image_free(&img);
    if (FREE_AT_EXIT)
        close_field(&src);
    if (!rc && !o.quiet)
        print_summary(&o, &p, &st, &t, omp_get_wtime() - start);
    return rc;
}
