/* study — what a row is: its render parameters and the `sdftrace render`
 * command line that reproduces its counts, its names, and what it reports
 * (its times' medians and intervals, its counts per pixel). The lowest
 * layer of the study: bench/study.c measures rows and bench/study_write.c
 * writes them, and both stand on this file. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "parse.h" /* src/common: parse_number, as sdftrace's options */
#include "study.h"

/* The paper's six method settings, in its table's order; its REL is its
 * Algorithm 2 (relaxed again after each fallback: `relaxed-bv`), and
 * beside it Keinert et al.'s own Listing 2 (plain sphere tracing after the
 * first fallback: `relaxed`), REL-K. */
const study_method STUDY_TABLE_METHODS[STUDY_TABLE_ROWS] = {
    {SDFT_SPHERE, "", "ST"},
    {SDFT_ENHANCED, "0.88", "ENH"},
    {SDFT_RELAXED_BV, "1.2", "REL 1.2"},
    {SDFT_RELAXED_BV, "1.5", "REL 1.5"},
    {SDFT_RELAXED, "1.2", "REL-K 1.2"},
    {SDFT_RELAXED, "1.5", "REL-K 1.5"},
    {SDFT_AUTO, "0.3", "AR 0.3"},
    {SDFT_AUTO, "0.2", "AR 0.2"},
};

const char *const STUDY_REP_NAMES[STUDY_REPS] = {"procedural", "band", "full", "vdb_tool", "mesh2sdf"};
const char *const STUDY_GROUP_NAMES[STUDY_GROUPS] = {"table", "sweep", "keinert", "beyond", "res", "caps"};

static const char EPS_TEXT[] = "0.0001"; /* the papers' constant epsilon, world units */

int study_rep_parse(const char *name)
{
    for (int r = 0; r < STUDY_REPS; r++)
        if (!strcmp(name, STUDY_REP_NAMES[r]))
            return r;
    return -1;
}

int study_rep_of_mesh(int rep) { return rep == STUDY_VDB_TOOL || rep == STUDY_MESH2SDF; }

const char *study_source_path(const study_options *o, const sdft_scene *scene, int rep, int res, char *buf, size_t len)
{
    snprintf(buf, len, "%s/%s-%s-%d.nvdb", o->grids, scene->name, STUDY_REP_NAMES[rep], res);
    return buf;
}

/* src/cli/cmd_render.c, open_grid: a grid without --scene is seen from
 * sdft_camera_front at 40 degrees, lit from above and in front. */
void study_front_view(sdft_aabb bounds, int width, int height, sdft_camera *camera, sdft_vec3 *light)
{
    *camera = sdft_camera_front(bounds, width, height, 40.0f);
    const sdft_vec3 c = camera->at;
    const float dist = camera->from.z - c.z;
    *light = sdft_v3(c.x, c.y + 2.0f * dist, c.z + dist);
}

/* A number as `sdftrace render` parses it (a CMDLINE_FLOAT row, src/common/cmdline.c):
 * the shared strict parser, then float. The study's own texts always parse. */
static float cli_float(const char *text)
{
    double v = NAN;
    (void)parse_number(text, &v);
    return (float)v;
}

/* Whether a method's parameter is omega (the relaxed forms, enhanced). */
static int takes_omega(sdft_method m) { return m == SDFT_RELAXED || m == SDFT_RELAXED_BV || m == SDFT_ENHANCED; }

/* What `sdftrace render` makes of the command line study_command writes
 * (src/cli/cmd_render.c, make_params): the same defaults, the same parsing
 * of the numbers. */
sdft_render_params study_params(const study_options *o, const study_config *c)
{
    sdft_render_params p = sdft_render_defaults();
    p.trace.method = c->method;
    p.trace.omega = takes_omega(c->method) ? cli_float(c->param) : sdft_default_omega(c->method);
    if (c->method == SDFT_AUTO)
        p.trace.beta = cli_float(c->param);
    p.trace.eps = cli_float(EPS_TEXT);
    p.trace.max_steps = (uint32_t)c->cap;
    p.width = o->width, p.height = o->height;
    p.camera = c->camera;
    p.light = c->light;
    p.shadows = c->shadows;
    p.screen_space = c->screen_space;
    sdft_render_papers(&p); /* every step to eps, as the papers count; cones only where the row asks */
    p.cones = c->cones;
    p.depth_only = 0;
    p.threads = 0;
    return p;
}

void study_command(const study_options *o, const study_config *c, char *buf, size_t len)
{
    char grid[4200] = "", scene[64] = "";
    if (c->rep != STUDY_PROCEDURAL) {
        char path[4096];
        snprintf(grid, sizeof grid, " --grid %s", study_source_path(o, c->scene, c->rep, c->res, path, sizeof path));
    }
    if (!study_rep_of_mesh(c->rep)) /* a mesh's grid is seen from its front view */
        snprintf(scene, sizeof scene, " --scene %s", c->scene->name);
    char param[48] = "";
    if (takes_omega(c->method))
        snprintf(param, sizeof param, " --omega %s", c->param);
    else if (c->method == SDFT_AUTO)
        snprintf(param, sizeof param, " --beta %s", c->param);
    snprintf(buf, len,
             "%s render%s%s --method %s%s --eps %s --max-steps %d --width %d --height %d%s%s%s --threads 0 "
             "-o %s --json",
             o->cli, scene, grid, sdft_method_name(c->method), param, EPS_TEXT, c->cap, o->width, o->height,
             c->shadows ? "" : " --no-shadows", c->screen_space ? " --screen-space" : "",
             c->cones ? " --no-exact-root" : " --papers", o->row_exr);
}

/* Figs. 1, 2 and 5 use the no-shadow rows at the paper's cap: the primary rays. */
int study_fig_row(const study_config *c)
{
    return (c->groups & STUDY_TABLE) && !c->shadows && c->cap == 1000 && !c->cones && !c->screen_space;
}

int study_fig1_method(const study_config *c)
{
    return (c->method == SDFT_ENHANCED && !strcmp(c->param, "0.88")) ||
           (c->method == SDFT_RELAXED_BV && !strcmp(c->param, "1.5")) ||
           (c->method == SDFT_AUTO && !strcmp(c->param, "0.3"));
}

int study_fig5_method(const study_config *c)
{
    return c->method == STUDY_TABLE_METHODS[STUDY_BEST_ROW].method &&
           !strcmp(c->param, STUDY_TABLE_METHODS[STUDY_BEST_ROW].param);
}

int study_sweep_timed(const sdft_scene *scene, int rep) { return !strcmp(scene->name, "temple") && rep == STUDY_FULL; }

const char *study_method_label(const study_config *c, char *buf, size_t len)
{
    if (*c->param)
        snprintf(buf, len, "%s %s", sdft_method_name(c->method), c->param);
    else
        snprintf(buf, len, "%s", sdft_method_name(c->method));
    return buf;
}

/* ---- what each row reports ---------------------------------------------- */

/* Row i's processor time over row ref's, pass by pass: the samples of its
 * ratio (n 0 when either was not timed, or there is no partner). */
static bench_summary ratio_to(const study_options *o, const study_run *run, size_t i, int ref)
{
    bench_summary s = {NAN, NAN, NAN, 0};
    if (ref < 0 || !run->configs[i].timed || !run->configs[ref].timed)
        return s;
    double r[STUDY_MAX_REPEATS];
    for (int p = 0; p < o->repeats; p++)
        r[p] = run->configs[i].cpu_ms[p] / run->configs[ref].cpu_ms[p];
    bench_summarize(r, o->repeats, 0.95, &s);
    return s;
}

static study_summary summarize(const study_options *o, const study_run *run, size_t i)
{
    const study_config *c = &run->configs[i];
    study_summary s = {.cpu = {NAN, NAN, NAN, 0}, .ms = {NAN, NAN, NAN, 0}};
    if (c->timed) {
        bench_summarize(c->cpu_ms, o->repeats, 0.95, &s.cpu);
        bench_summarize(c->ms, o->repeats, 0.95, &s.ms);
    }
    s.rel_enhanced = ratio_to(o, run, i, c->ref_enhanced);
    s.rel_sphere = ratio_to(o, run, i, c->ref_sphere);
    s.rel_plain = ratio_to(o, run, i, c->ref_plain);
    const double px = (double)c->stats.primary_rays;
    s.steps = (double)c->stats.steps / px;
    s.primary = (double)c->stats.primary_steps / px;
    s.shadow = (double)(c->stats.steps - c->stats.primary_steps) / px;
    s.cone = (double)c->stats.cone_steps / px;
    s.fallbacks = (double)c->stats.fallbacks / px;
    s.primary_fallbacks = (double)c->stats.primary_fallbacks / px;
    s.nonconverged = (double)c->stats.nonconverged / px;
    s.hits = (double)c->stats.hits / px;
    s.gpu = c->gpu_cost;
    return s;
}

int study_summarize_all(const study_options *o, study_run *run)
{
    free(run->summaries);
    run->summaries = malloc(run->n * sizeof *run->summaries);
    if (!run->summaries)
        return -1;
    for (size_t i = 0; i < run->n; i++)
        run->summaries[i] = summarize(o, run, i);
    return 0;
}

/* ---- housekeeping ------------------------------------------------------- */

double study_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double study_cpu_now(void) { return (double)clock() / CLOCKS_PER_SEC; }

study_fig1 *study_fig1_of(study_run *run, const sdft_scene *scene)
{
    for (int k = 0; k < run->nfig1; k++)
        if (run->fig1[k]->scene == scene)
            return run->fig1[k];
    study_fig1 *f = run->nfig1 < STUDY_MAX_SCENES ? calloc(1, sizeof *f) : NULL;
    if (!f) {
        fprintf(stderr, "study: out of memory\n");
        exit(1);
    }
    f->scene = scene;
    run->fig1[run->nfig1++] = f;
    return f;
}

void study_run_free(study_run *run)
{
    for (size_t i = 0; i < run->n; i++) {
        free(run->configs[i].ms);
        free(run->configs[i].cpu_ms);
        free(run->configs[i].hist);
    }
    free(run->configs);
    free(run->summaries);
    for (int k = 0; k < run->nsources; k++)
        sdft_grid_free(run->sources[k].grid);
    for (size_t k = 0; k < run->ndepths; k++)
        free(run->depths[k]);
    for (int k = 0; k < run->nfig1; k++)
        free(run->fig1[k]);
}
