/* sdftrace bake — a procedural scene sampled into an OpenVDB level set
 * (.vdb) or a NanoVDB grid (.nvdb): parse, check, bake, report one line. */
#include <stdio.h>
#include <string.h>

#include "cmdline.h"
#include "commands.h"
#include "peak_memory.h"
#include "progress_bar.h"
#include "sdftrace/scene.h"
#include "sdftrace/vdb.h"

/* The bake's progress, drawn as the shared progress bar. */
static int show_progress(void *user, float done)
{
    progress_bar_show(user, "baking", (int)(100.0f * done));
    return 0;
}

/* What the command line gives: the bake's parameters and the rest. */
typedef struct bake_opts {
    sdft_bake_params p;
    const char *scene, *out;
    int band_set, quiet;
} bake_opts;

#define STR(x) #x
#define XSTR(x) STR(x)

enum { BAKE_ROWS = 13 };

/* The options of `sdftrace bake`, over o, in rows (room for them and the
 * end); and the command line they make. */
static cmdline_spec bake_options(bake_opts *o, cmdline_option rows[BAKE_ROWS])
{
    const cmdline_option t[BAKE_ROWS] = {
        {"scene", 0, "NAME", "procedural scene (sdftrace scenes lists them); required", CMDLINE_TEXT, &o->scene,
         .def = ""},
        {"res", 0, "N", "voxels along the scene box's longest edge, 1.." XSTR(SDFT_BAKE_MAX_RES), CMDLINE_INT,
         &o->p.res, .lo = 1, .hi = SDFT_BAKE_MAX_RES},
        {NULL, 'o', "OUT", ".vdb: OpenVDB level set; .nvdb: NanoVDB grid; required", CMDLINE_TEXT, &o->out, .def = ""},
        {"band", 0, "W", "narrow-band half-width in voxels, also the background", CMDLINE_FLOAT, &o->p.band, .lo = 1e-3,
         .hi = 1000.0, .seen = &o->band_set},
        {"full", 0, NULL, "store every voxel of the box instead of a narrow band", CMDLINE_SET, &o->p.full, .value = 1,
         .def = "off"},
        {"fp16", 0, NULL, "Fp16 leaves in .nvdb, half floats in .vdb", CMDLINE_SET, &o->p.fp16, .value = 1,
         .def = "float"},
        {"grid-name", 0, "NAME", "name of the grid in the file", CMDLINE_TEXT, &o->p.grid_name, .def = "sdf"},
        {"materials", 0, NULL,
         "the scene's materials too: grids NAME.material_ids and NAME.material_table\n"
         "in the same file, which `sdftrace render --grid` shades with",
         CMDLINE_SET, &o->p.materials, .value = 1, .def = "off"},
        {"threads", 0, "N", "worker threads, 0 = all cores", CMDLINE_INT, &o->p.threads, .lo = 0, .hi = 1024},
        {"quiet", 0, NULL, "no progress bar and no summary line (errors still go to stderr)", CMDLINE_SET, &o->quiet,
         .value = 1, .def = ""},
        {"help", 'h', NULL, NULL, CMDLINE_HELP, NULL, .def = ""},
        {0},
    };
    memcpy(rows, t, sizeof t);
    return (cmdline_spec){
        .program = "sdftrace bake",
        .usage = "usage: sdftrace bake --scene NAME --res N -o OUT.vdb|OUT.nvdb [options]\n",
        .footer = "Progress goes to stderr when it is a terminal; one summary line to stdout.\n",
        .rows = rows,
        .column = 20,
    };
}

void cmd_bake_help(FILE *out)
{
    bake_opts d = {.p = sdft_bake_defaults()};
    cmdline_option rows[BAKE_ROWS];
    const cmdline_spec spec = bake_options(&d, rows);
    cmdline_help(&spec, out);
}

/* The checks that need all the options at once: 0, or -1 with msg. */
static int check_opts(const bake_opts *o, const sdft_scene **scene, char *msg, size_t len)
{
    *scene = o->scene ? sdft_scene_find(o->scene) : NULL;
    const char *ext = o->out ? strrchr(o->out, '.') : NULL;
    if (!o->scene)
        snprintf(msg, len, "--scene is required (sdftrace scenes lists them)");
    else if (!*scene)
        snprintf(msg, len, "unknown scene '%s' (sdftrace scenes lists them)", o->scene);
    else if (!o->out)
        snprintf(msg, len, "-o OUT.vdb or OUT.nvdb is required");
    else if (!ext || (strcmp(ext, ".vdb") && strcmp(ext, ".nvdb")))
        snprintf(msg, len, "%s: the output must end in .vdb or .nvdb", o->out);
    else if (o->band_set && o->p.full)
        snprintf(msg, len, "--band and --full exclude each other");
    else if (o->p.grid_name && !*o->p.grid_name)
        snprintf(msg, len, "--grid-name must not be empty");
    else if (o->p.materials && !(*scene)->field.material)
        snprintf(msg, len, "--materials: scene '%s' has no materials", o->scene);
    else if (!o->p.full || bake_memory_check(&(*scene)->field, o->p.res, strcmp(ext, ".nvdb") == 0, msg, len) == 0)
        return 0;
    return -1;
}

int cmd_bake(int argc, char **argv)
{
    char msg[512] = "";
    bake_opts o = {.p = sdft_bake_defaults()};
    cmdline_option rows[BAKE_ROWS];
    const cmdline_spec spec = bake_options(&o, rows);
    const int parsed = cmdline_parse(&spec, argc, argv, msg, sizeof msg);
    if (parsed == CMDLINE_HELP_ASKED) {
        cmd_bake_help(stdout);
        return 0;
    }
    const sdft_scene *scene = NULL;
    if (parsed != CMDLINE_OK || check_opts(&o, &scene, msg, sizeof msg)) {
        cli_error("bake", msg);
        return 2;
    }
    sdft_bake_stats st;
    progress_bar bar;
    progress_bar_init(&bar, !o.quiet);
    o.p.progress = show_progress;
    o.p.progress_user = &bar;
    const sdft_error rc = sdft_bake(&scene->field, &o.p, o.out, NULL, &st, msg, sizeof msg);
    progress_bar_clear(&bar);
    if (rc) {
        cli_error("bake", msg);
        return 1;
    }
    if (!o.quiet)
        printf("baked %s: %dx%dx%d voxels of %g, %llu active in %llu leaves, %llu evaluations, %.0f ms%s -> %s\n",
               scene->name, st.dims[0], st.dims[1], st.dims[2], st.voxel_size, (unsigned long long)st.active_voxels,
               (unsigned long long)st.leaves, (unsigned long long)st.evaluations, st.ms,
               o.p.materials ? ", with its materials" : "", o.out);
    return 0;
}
