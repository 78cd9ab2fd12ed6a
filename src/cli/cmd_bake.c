/* sdftrace bake — a procedural scene sampled into an OpenVDB level set
 * (.vdb) or a NanoVDB grid (.nvdb): parse, check, bake, report one line. */
#include <stdio.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "progress_bar.h"
#include "sdftrace/scene.h"
#include "sdftrace/vdb.h"

/* The bake's progress, drawn as the shared progress bar. */
static int show_progress(void *user, float done)
{
    sdft_progress_bar_show(user, "baking", (int)(100.0f * done));
    return 0;
}

void cmd_bake_help(FILE *out)
{
    sdft_bake_params d = sdft_bake_defaults();
    fprintf(out,
            "usage: sdftrace bake --scene NAME --res N -o OUT.vdb|OUT.nvdb [options]\n"
            "  --scene NAME      procedural scene (sdftrace scenes lists them); required\n"
            "  --res N           voxels along the scene box's longest edge, 1..%d (default %d)\n"
            "  -o OUT            .vdb: OpenVDB level set; .nvdb: NanoVDB grid; required\n"
            "  --band W          narrow-band half-width in voxels, also the background (default %g)\n"
            "  --full            store every voxel of the box instead of a narrow band (default off)\n"
            "  --fp16            Fp16 leaves in .nvdb, half floats in .vdb (default float)\n"
            "  --grid-name NAME  name of the grid in the file (default sdf)\n"
            "  --threads N       worker threads, 0 = all cores (default 0)\n"
            "  --quiet           no progress bar and no summary line (errors still go to stderr)\n"
            "Progress goes to stderr when it is a terminal; one summary line to stdout.\n",
            SDFT_BAKE_MAX_RES, d.res, d.band);
}

int cmd_bake(int argc, char **argv)
{
    char msg[512] = "";
    sdft_bake_params p = sdft_bake_defaults();
    const char *scene_name = NULL, *out = NULL;
    int band_set = 0, quiet = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        long n = 0;
        int rc = 0;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            cmd_bake_help(stdout);
            return 0;
        } else if (!strcmp(a, "--full")) {
            p.full = 1;
            continue;
        } else if (!strcmp(a, "--fp16")) {
            p.fp16 = 1;
            continue;
        } else if (!strcmp(a, "--quiet")) {
            quiet = 1;
            continue;
        }
        int known = !strcmp(a, "--scene") || !strcmp(a, "--res") || !strcmp(a, "-o") || !strcmp(a, "--band") ||
                    !strcmp(a, "--grid-name") || !strcmp(a, "--threads");
        if (!known) {
            snprintf(msg, sizeof msg, "unknown option '%s' (try: sdftrace bake --help)", a);
            cli_error("bake", msg);
            return 2;
        }
        if (i + 1 >= argc) {
            snprintf(msg, sizeof msg, "%s needs a value", a);
            cli_error("bake", msg);
            return 2;
        }
        const char *v = argv[++i];
        if (!strcmp(a, "--scene"))
            scene_name = v;
        else if (!strcmp(a, "-o"))
            out = v;
        else if (!strcmp(a, "--grid-name"))
            p.grid_name = v;
        else if (!strcmp(a, "--res")) {
            rc = arg_long(a, v, 1, SDFT_BAKE_MAX_RES, &n, msg, sizeof msg);
            p.res = (int)n;
        } else if (!strcmp(a, "--band")) {
            rc = arg_float(a, v, 1e-3f, 1000.0f, &p.band, msg, sizeof msg);
            band_set = 1;
        } else if (!strcmp(a, "--threads")) {
            rc = arg_long(a, v, 0, 1024, &n, msg, sizeof msg);
            p.threads = (int)n;
        }
        if (rc) {
            cli_error("bake", msg);
            return 2;
        }
    }
    const sdft_scene *scene = scene_name ? sdft_scene_find(scene_name) : NULL;
    const char *ext = out ? strrchr(out, '.') : NULL;
    if (!scene_name)
        snprintf(msg, sizeof msg, "--scene is required (sdftrace scenes lists them)");
    else if (!scene)
        snprintf(msg, sizeof msg, "unknown scene '%s' (sdftrace scenes lists them)", scene_name);
    else if (!out)
        snprintf(msg, sizeof msg, "-o OUT.vdb or OUT.nvdb is required");
    else if (!ext || (strcmp(ext, ".vdb") && strcmp(ext, ".nvdb")))
        snprintf(msg, sizeof msg, "%s: the output must end in .vdb or .nvdb", out);
    else if (band_set && p.full)
        snprintf(msg, sizeof msg, "--band and --full exclude each other");
    else if (p.grid_name && !*p.grid_name)
        snprintf(msg, sizeof msg, "--grid-name must not be empty");
    if (*msg) {
        cli_error("bake", msg);
        return 2;
    }
    sdft_bake_stats st;
    sdft_progress_bar bar;
    sdft_progress_bar_init(&bar, !quiet);
    p.progress = show_progress;
    p.progress_user = &bar;
    const sdft_error rc = sdft_bake(&scene->field, &p, out, NULL, &st, msg, sizeof msg);
    sdft_progress_bar_clear(&bar);
    if (rc) {
        cli_error("bake", msg);
        return 1;
    }
    if (!quiet)
        printf("baked %s: %dx%dx%d voxels of %g, %llu active in %llu leaves, %llu evaluations, %.0f ms -> %s\n",
               scene->name, st.dims[0], st.dims[1], st.dims[2], st.voxel_size, (unsigned long long)st.active_voxels,
               (unsigned long long)st.leaves, (unsigned long long)st.evaluations, st.ms, out);
    return 0;
}
