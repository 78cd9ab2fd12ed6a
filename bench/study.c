/* study — procedural against discrete, method by method, in one process.
 *
 * Bán and Valasek's auto-relaxation paper (Section 4, Figs. 1-3) measures six
 * method settings on procedural scenes and on 1024^3 discrete versions of
 * them; Keinert et al. measure over-relaxation on their city. This program
 * renders every configuration of that study through the library's own
 * sdft_render, exactly as `sdftrace render` does (the same parameters; each
 * row's command line is written beside it and reproduces its counts), and
 * writes what the paper reports and more:
 *
 *   results.csv   one row per configuration: time (median, min, max of the
 *                 repeats), ratios, exact counts, agreement with the
 *                 procedural image, and the `sdftrace render` command line;
 *   table.md      the paper's table and the other groups as Markdown;
 *   fig1-*.u32    per-pixel steps and fallbacks of three methods (Fig. 1),
 *   fig1.txt      their shared scales, fig2.dat (Fig. 2), fig3.dat (Fig. 3):
 *                 data for bench/fig*.gp.
 *
 * Method: every configuration renders once as a warm-up (its counts are
 * kept, and must be the same in every repeat), then REPEATS passes render
 * each once more. Within a pass, the configurations that are compared with
 * each other (same scene, representation, shadows, step cap and options)
 * run back to back; the order of those sets and of the rows in each is
 * shuffled anew every pass, so drift on a shared machine hits all alike.
 * A ratio is the median over passes of the two rows' times in that pass.
 *
 * usage: study --out DIR [options]      (study --help lists them)
 * Grids come from `sdftrace bake` (bench/study.sh bakes them): DIR/SCENE-band-RES.nvdb
 * and DIR/SCENE-full-RES.nvdb. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "atomic_file.h" /* src/common: atomic_file_check_writable */
#include "cmdline.h"     /* src/common: the option table */
#include "parse.h"       /* src/common: parse_integer, parse_number */
#include "sdftrace/grid.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "stats.h" /* bench_load_average */
#include "study.h"

/* ---- what is measured -------------------------------------------------- */

/* The paper's six method settings, in its table's order. Its REL is its
 * Algorithm 2 (relaxed again after each fallback): `relaxed-bv`. */
const study_method STUDY_TABLE_METHODS[STUDY_TABLE_ROWS] = {
    {SDFT_SPHERE, "", "ST"},
    {SDFT_ENHANCED, "0.88", "ENH"},
    {SDFT_RELAXED_BV, "1.2", "REL 1.2"},
    {SDFT_RELAXED_BV, "1.5", "REL 1.5"},
    {SDFT_AUTO, "0.3", "AR 0.3"},
    {SDFT_AUTO, "0.2", "AR 0.2"},
};

const char *const STUDY_REP_NAMES[STUDY_REPS] = {"procedural", "band", "full"};

static const char EPS_TEXT[] = "0.0001";                        /* the papers' constant epsilon, world units */
static const int KEINERT_CAPS[] = {80, 64};                     /* his timings (80) and his Fig. 8 (64) */
static const char *const KEINERT_OMEGAS[] = {"", "1.2", "1.5"}; /* "": sphere tracing */

static void fail(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("study: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

/* ---- options ----------------------------------------------------------- */

/* Splits a comma-separated list into at most `most` items (pointers into
 * `buf`, a copy). Returns the count, or -1 with msg when empty or too long. */
static int split_list(const char *flag, const char *text, char *buf, size_t len, char **items, int most, char *msg,
                      size_t msg_len)
{
    if (!text || !*text || strlen(text) >= len) {
        snprintf(msg, msg_len, "%s needs a comma-separated list, got '%s'", flag, text ? text : "");
        return -1;
    }
    strcpy(buf, text);
    int n = 0;
    for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
        if (n == most) {
            snprintf(msg, msg_len, "%s: at most %d items", flag, most);
            return -1;
        }
        items[n++] = tok;
    }
    if (n == 0)
        snprintf(msg, msg_len, "%s needs a comma-separated list, got '%s'", flag, text);
    return n ? n : -1;
}

/* --reps LIST: the representations measured. */
static int set_reps(void *target, const char *value, char *msg, size_t len)
{
    static char buf[64];
    study_options *o = target;
    char *items[STUDY_REPS * 2];
    const int n = split_list("--reps", value, buf, sizeof buf, items, STUDY_REPS * 2, msg, len);
    memset(o->reps, 0, sizeof o->reps);
    for (int k = 0; k < n; k++) {
        const int r = study_rep_parse(items[k]);
        if (r < 0) {
            snprintf(msg, len, "--reps: unknown representation '%s' (procedural, band or full)", items[k]);
            return -1;
        }
        o->reps[r] = 1;
    }
    return n < 0 ? -1 : 0;
}

/* --caps LIST: the table's step caps, each parsed strictly (src/common/parse.h). */
static int set_caps(void *target, const char *value, char *msg, size_t len)
{
    static char buf[64];
    study_options *o = target;
    char *items[STUDY_MAX_CAPS];
    const int n = split_list("--caps", value, buf, sizeof buf, items, STUDY_MAX_CAPS, msg, len);
    o->ncaps = n < 0 ? 0 : n;
    for (int k = 0; k < n; k++) {
        long v;
        if (parse_integer(items[k], &v) || v < 1 || v > 10000000) {
            snprintf(msg, len, "--caps must be integers in [1, 10000000], got '%s'", items[k]);
            return -1;
        }
        o->caps[k] = (int)v;
    }
    return n < 0 ? -1 : 0;
}

/* --parts LIST: which groups of rows are measured. */
static int set_parts(void *target, const char *value, char *msg, size_t len)
{
    static const char *const names[] = {"table", "sweep", "keinert", "beyond"};
    static char buf[64];
    study_options *o = target;
    char *items[8];
    const int n = split_list("--parts", value, buf, sizeof buf, items, 8, msg, len);
    o->parts = 0;
    for (int k = 0; k < n; k++) {
        unsigned bit = 0;
        for (unsigned b = 0; b < 4; b++)
            if (!strcmp(items[k], names[b]))
                bit = 1u << b;
        if (!bit) {
            snprintf(msg, len, "--parts: unknown part '%s' (table, sweep, keinert or beyond)", items[k]);
            return -1;
        }
        o->parts |= bit;
    }
    return n < 0 ? -1 : 0;
}

enum { STUDY_OPTION_ROWS = 18 };

/* The options of study, over o (for the help, over the defaults), in rows,
 * and the command line they make; *scenes: the --scenes list, resolved
 * after parsing. */
static cmdline_spec study_option_rows(study_options *o, const char **scenes, cmdline_option rows[STUDY_OPTION_ROWS])
{
    const cmdline_option t[STUDY_OPTION_ROWS] = {
        {"out", 0, "DIR", "where results.csv, table.md and the figures' data go; must be writable", CMDLINE_TEXT,
         &o->out, .def = ""},
        {"grids", 0, "DIR", "the baked grids, DIR/SCENE-band-RES.nvdb and DIR/SCENE-full-RES.nvdb\n", CMDLINE_TEXT,
         &o->grids, .value = 1},
        {"res", 0, "N", "the grids' resolution, 1..1024", CMDLINE_INT, &o->res, .lo = 1, .hi = 1024},
        {"width", 0, "W", "image width, 1..16384", CMDLINE_INT, &o->width, .lo = 1, .hi = 16384},
        {"height", 0, "H", "image height, 1..16384", CMDLINE_INT, &o->height, .lo = 1, .hi = 16384},
        {"repeats", 0, "R", "timed frames per configuration after the warm-up, 1..100", CMDLINE_INT, &o->repeats,
         .lo = 1, .hi = 100},
        {"sweep", 0, "N", "values per method in the hyperparameter sweep, 0..40 (0: none)", CMDLINE_INT, &o->sweep,
         .lo = 0, .hi = 40},
        {"scenes", 0, "LIST", "the table's scenes, comma-separated", CMDLINE_TEXT, scenes, .value = 1},
        {"reps", 0, "LIST", "representations: procedural,band,full", CMDLINE_CALL, o, .def = "all three",
         .handle = set_reps},
        {"caps", 0, "LIST", "step caps of the table, comma-separated", CMDLINE_CALL, o, .def = "1000,32",
         .handle = set_caps},
        {"parts", 0, "LIST", "table,sweep,keinert,beyond", CMDLINE_CALL, o, .def = "all", .handle = set_parts},
        {"cli", 0, "PATH", "the sdftrace binary named in the command lines", CMDLINE_TEXT, &o->cli, .value = 1},
        {"row-exr", 0, "PATH", "the -o of those command lines", CMDLINE_TEXT, &o->row_exr, .value = 1},
        {"quiet", 0, NULL, "no progress on stderr", CMDLINE_SET, &o->quiet, .value = 1, .def = ""},
        {"dry-run", 0, NULL, "check the options, count the configurations, touch no grid", CMDLINE_SET, &o->dry_run,
         .value = 1, .def = ""},
        {"help", 'h', NULL, NULL, CMDLINE_HELP, NULL, .def = ""},
        {0},
    };
    memcpy(rows, t, sizeof t);
    return (cmdline_spec){
        .program = "study",
        .usage = "usage: study --out DIR [options]\n",
        .rows = rows,
        .column = 18,
    };
}

static study_options default_options(const char **scenes)
{
    *scenes = "temple,figure";
    return (study_options){.grids = "build/study-grids",
                           .cli = "build/sdftrace",
                           .row_exr = "/tmp/study-row.exr",
                           .res = 1024,
                           .width = 1280,
                           .height = 720,
                           .repeats = 5,
                           .sweep = 10,
                           .caps = {1000, 32},
                           .ncaps = 2,
                           .parts = STUDY_TABLE | STUDY_SWEEP | STUDY_KEINERT | STUDY_BEYOND,
                           .reps = {1, 1, 1}};
}

static void usage(FILE *out)
{
    const char *scenes;
    study_options d = default_options(&scenes);
    cmdline_option rows[STUDY_OPTION_ROWS];
    const cmdline_spec spec = study_option_rows(&d, &scenes, rows);
    cmdline_help(&spec, out);
}

/* The checks that need all the options at once, and the scenes by name. */
static int check_options(study_options *o, const char *scenes, char *msg, size_t len)
{
    static char buf[256];
    char *items[STUDY_MAX_SCENES];
    const int n = split_list("--scenes", scenes, buf, sizeof buf, items, STUDY_MAX_SCENES, msg, len);
    if (n < 0)
        return -1;
    for (int k = 0; k < n; k++) {
        o->scenes[k] = sdft_scene_find(items[k]);
        if (!o->scenes[k]) {
            snprintf(msg, len, "unknown scene '%s' (sdftrace scenes lists them)", items[k]);
            return -1;
        }
    }
    o->nscenes = n;
    if (!o->out)
        snprintf(msg, len, "--out DIR is required (try: study --help)");
    else if (!o->reps[STUDY_PROCEDURAL] && (o->parts & (STUDY_TABLE | STUDY_BEYOND)))
        snprintf(msg, len,
                 "--reps: the table and the beyond rows compare with the procedural scene; include procedural");
    else
        return 0;
    return -1;
}

/* 0: options read; 1: the help was asked for (and printed); -1: an error (printed). */
static int parse_options(int argc, char **argv, study_options *o)
{
    const char *scenes;
    char msg[512];
    *o = default_options(&scenes);
    cmdline_option rows[STUDY_OPTION_ROWS];
    const cmdline_spec spec = study_option_rows(o, &scenes, rows);
    const int parsed = cmdline_parse(&spec, argc, argv, msg, sizeof msg);
    if (parsed == CMDLINE_HELP_ASKED) {
        usage(stdout);
        return 1;
    }
    if (parsed != CMDLINE_OK || check_options(o, scenes, msg, sizeof msg)) {
        fail("%s", msg);
        return -1;
    }
    return 0;
}

/* The output folder exists and takes files: the atomic writer's temporary
 * file for results.csv is made there and removed, touching nothing else. */
static int check_out_dir(const char *dir)
{
    char probe[4096], msg[512];
    if (snprintf(probe, sizeof probe, "%s/results.csv", dir) >= (int)sizeof probe) {
        fail("--out: path too long");
        return -1;
    }
    if (atomic_file_check_writable(probe, msg, sizeof msg)) {
        fail("--out %s: %s", dir, msg);
        return -1;
    }
    return 0;
}

/* ---- configurations ---------------------------------------------------- */

static int same_setting(const study_config *a, const study_config *b)
{
    return a->scene == b->scene && a->rep == b->rep && a->shadows == b->shadows && a->cap == b->cap &&
           a->screen_space == b->screen_space && a->cones == b->cones;
}

static int same_config(const study_config *a, const study_config *b)
{
    return same_setting(a, b) && a->method == b->method && !strcmp(a->param, b->param);
}

/* Adds a configuration to the list, or the groups to an equal one already there. */
static void add_config(study_run *run, study_config c)
{
    for (size_t i = 0; i < run->n; i++)
        if (same_config(&run->configs[i], &c)) {
            run->configs[i].groups |= c.groups;
            return;
        }
    if (run->n == run->cap) {
        run->cap = run->cap ? 2 * run->cap : 256;
        study_config *grown = realloc(run->configs, run->cap * sizeof *grown);
        if (!grown) {
            fail("out of memory for %zu configurations", run->cap);
            exit(1);
        }
        run->configs = grown;
    }
    run->configs[run->n++] = c;
}

static study_config make_config(const sdft_scene *scene, int rep, sdft_method m, const char *param, int shadows,
                                int cap, unsigned groups)
{
    study_config c = {.scene = scene, .rep = rep, .method = m, .shadows = shadows, .cap = cap, .groups = groups};
    snprintf(c.param, sizeof c.param, "%s", param);
    return c;
}

/* A parameter as the command line carries it: %.4g, so that the value the
 * CLI parses from it is the value measured. */
static void param_text(char *buf, size_t len, double v) { snprintf(buf, len, "%.4g", v); }

static void build_configs(const study_options *o, study_run *run)
{
    const sdft_scene *temple = sdft_scene_find("temple"), *city = sdft_scene_find("city");
    for (int s = 0; s < o->nscenes && (o->parts & STUDY_TABLE); s++)
        for (int rep = 0; rep < STUDY_REPS; rep++)
            for (int shadows = 1; shadows >= 0 && o->reps[rep]; shadows--)
                for (int k = 0; k < o->ncaps; k++)
                    for (int m = 0; m < STUDY_TABLE_ROWS; m++)
                        add_config(run, make_config(o->scenes[s], rep, STUDY_TABLE_METHODS[m].method,
                                                    STUDY_TABLE_METHODS[m].param, shadows, o->caps[k], STUDY_TABLE));
    /* Fig. 3: temple, the paper's cap, beta in (0, 1/2], enhanced omega in
     * [1/2, 1], relaxed omega in [1, 2), and the table's values among them. */
    int has_temple = 0;
    for (int s = 0; s < o->nscenes; s++)
        has_temple |= o->scenes[s] == temple;
    if ((o->parts & STUDY_SWEEP) && o->sweep > 0 && has_temple) {
        char text[16];
        for (int rep = 0; rep < STUDY_REPS; rep++)
            for (int shadows = 1; shadows >= 0 && o->reps[rep]; shadows--) {
                add_config(run, make_config(temple, rep, SDFT_SPHERE, "", shadows, 1000, STUDY_SWEEP));
                for (int k = 0; k < o->sweep; k++) {
                    const int n = o->sweep;
                    param_text(text, sizeof text, 0.5 * (k + 1) / n);
                    add_config(run, make_config(temple, rep, SDFT_AUTO, text, shadows, 1000, STUDY_SWEEP));
                    param_text(text, sizeof text, n > 1 ? 0.5 + 0.5 * k / (n - 1) : 1.0);
                    add_config(run, make_config(temple, rep, SDFT_ENHANCED, text, shadows, 1000, STUDY_SWEEP));
                    param_text(text, sizeof text, 1.0 + (double)k / n);
                    add_config(run, make_config(temple, rep, SDFT_RELAXED_BV, text, shadows, 1000, STUDY_SWEEP));
                }
                for (int m = 1; m < STUDY_TABLE_ROWS; m++)
                    add_config(run, make_config(temple, rep, STUDY_TABLE_METHODS[m].method,
                                                STUDY_TABLE_METHODS[m].param, shadows, 1000, STUDY_SWEEP));
            }
    }
    /* Keinert et al.: ray casting the city (no shadows) at his step caps,
     * constant epsilon and his screen-space criterion, relaxed as his
     * Listing 2 has it. */
    if (o->parts & STUDY_KEINERT)
        for (size_t k = 0; k < sizeof KEINERT_CAPS / sizeof KEINERT_CAPS[0]; k++)
            for (int ss = 0; ss < 2; ss++)
                for (size_t m = 0; m < sizeof KEINERT_OMEGAS / sizeof KEINERT_OMEGAS[0]; m++) {
                    study_config c =
                        make_config(city, STUDY_PROCEDURAL, *KEINERT_OMEGAS[m] ? SDFT_RELAXED : SDFT_SPHERE,
                                    KEINERT_OMEGAS[m], 0, KEINERT_CAPS[k], STUDY_KEINERT);
                    c.screen_space = ss;
                    add_config(run, c);
                }
    /* Beyond the paper: the best variant with cones and the screen-space
     * criterion, on every representation. */
    for (int s = 0; s < o->nscenes && (o->parts & STUDY_BEYOND); s++)
        for (int rep = 0; rep < STUDY_REPS; rep++)
            for (int v = 0; v < 4 && o->reps[rep]; v++) {
                study_config c = make_config(o->scenes[s], rep, STUDY_TABLE_METHODS[STUDY_BEST_ROW].method,
                                             STUDY_TABLE_METHODS[STUDY_BEST_ROW].param, 1, 1000, STUDY_BEYOND);
                c.cones = v & 1, c.screen_space = v >> 1;
                add_config(run, c);
            }
}

/* Each row's partners: the same setting's enhanced 0.88 and sphere rows,
 * the same setting without cones or screen-space, the same row on the
 * procedural scene; and its comparison set (same setting). */
static void link_configs(study_run *run)
{
    for (size_t i = 0; i < run->n; i++) {
        study_config *c = &run->configs[i];
        c->ref_enhanced = c->ref_sphere = c->ref_plain = c->ref_procedural = -1;
        c->set = (int)i;
        for (size_t j = 0; j < run->n; j++) {
            const study_config *d = &run->configs[j];
            if (same_setting(c, d) && (int)j < c->set)
                c->set = (int)j;
            if (same_setting(c, d) && d->method == SDFT_ENHANCED && !strcmp(d->param, "0.88"))
                c->ref_enhanced = (int)j;
            if (same_setting(c, d) && d->method == SDFT_SPHERE)
                c->ref_sphere = (int)j;
            if (d->scene == c->scene && d->rep == c->rep && d->shadows == c->shadows && d->cap == c->cap &&
                d->method == c->method && !strcmp(d->param, c->param) && !d->cones && !d->screen_space)
                c->ref_plain = (int)j;
            if (c->rep != STUDY_PROCEDURAL && d->rep == STUDY_PROCEDURAL && d->scene == c->scene &&
                d->shadows == c->shadows && d->cap == c->cap && d->screen_space == c->screen_space &&
                d->cones == c->cones && d->method == c->method && !strcmp(d->param, c->param))
                c->ref_procedural = (int)j;
        }
    }
}

/* ---- sources: the procedural scenes and their grids --------------------- */

static const char *source_path(const study_options *o, const sdft_scene *scene, int rep, char *buf, size_t len)
{
    snprintf(buf, len, "%s/%s-%s-%d.nvdb", o->grids, scene->name, STUDY_REP_NAMES[rep], o->res);
    return buf;
}

/* Opens every source some configuration uses; one line and -1 on failure. */
static int open_sources(const study_options *o, study_run *run)
{
    for (size_t i = 0; i < run->n; i++) {
        const study_config *c = &run->configs[i];
        int found = 0;
        for (int k = 0; k < run->nsources && !found; k++)
            found = run->sources[k].scene == c->scene && run->sources[k].rep == c->rep;
        if (found)
            continue;
        if (run->nsources == STUDY_MAX_SOURCES) {
            fail("too many sources");
            return -1;
        }
        study_source *src = &run->sources[run->nsources++];
        *src = (study_source){.scene = c->scene, .rep = c->rep, .field = c->scene->field};
        if (c->rep == STUDY_PROCEDURAL)
            continue;
        source_path(o, c->scene, c->rep, src->path, sizeof src->path);
        char msg[512];
        if (!o->quiet)
            fprintf(stderr, "study: loading %s\n", src->path);
        sdft_grid_options go = sdft_grid_options_defaults();
        go.path = src->path;
        if (sdft_grid_open(&go, &src->grid, msg, sizeof msg)) {
            fail("%s (bench/study.sh bakes the grids)", msg);
            return -1;
        }
        src->field = sdft_grid_field(src->grid, SDFT_GRID_BOUND_FAR);
        src->voxel = sdft_grid_voxel_size(src->grid).x;
    }
    for (size_t i = 0; i < run->n; i++)
        for (int k = 0; k < run->nsources; k++)
            if (run->sources[k].scene == run->configs[i].scene && run->sources[k].rep == run->configs[i].rep)
                run->configs[i].source = k;
    return 0;
}

/* ---- one configuration: its parameters and its command line ------------- */

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
    p.camera = c->scene->camera;
    p.light = c->scene->light;
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
    char grid[4200] = "";
    if (c->rep != STUDY_PROCEDURAL) {
        char path[4096];
        snprintf(grid, sizeof grid, " --grid %s", source_path(o, c->scene, c->rep, path, sizeof path));
    }
    char param[48] = "";
    if (takes_omega(c->method))
        snprintf(param, sizeof param, " --omega %s", c->param);
    else if (c->method == SDFT_AUTO)
        snprintf(param, sizeof param, " --beta %s", c->param);
    snprintf(buf, len,
             "%s render --scene %s%s --method %s%s --eps %s --max-steps %d --width %d --height %d%s%s%s --threads 0 "
             "-o %s --json",
             o->cli, c->scene->name, grid, sdft_method_name(c->method), param, EPS_TEXT, c->cap, o->width, o->height,
             c->shadows ? "" : " --no-shadows", c->screen_space ? " --screen-space" : "",
             c->cones ? " --no-exact-root" : " --papers", o->row_exr);
}

/* ---- measuring ---------------------------------------------------------- */

static uint64_t rng_next(uint64_t *s)
{
    *s ^= *s >> 12, *s ^= *s << 25, *s ^= *s >> 27;
    return *s * 0x2545F4914F6CDD1Dull;
}

/* This pass's order: sets shuffled, each set's rows together, shuffled. */
static void pass_order(const study_run *run, int pass, size_t *order)
{
    uint64_t seed = 0x9E3779B97F4A7C15ull * (uint64_t)(pass + 1) + 1;
    uint64_t *set_key = malloc(run->n * sizeof *set_key), *row_key = malloc(run->n * sizeof *row_key);
    if (!set_key || !row_key) {
        fail("out of memory");
        exit(1);
    }
    for (size_t i = 0; i < run->n; i++)
        set_key[i] = rng_next(&seed), row_key[i] = rng_next(&seed);
    for (size_t i = 0; i < run->n; i++)
        order[i] = i;
    /* Insertion sort by (the set's key, the row's key): n is a few hundred. */
    for (size_t i = 1; i < run->n; i++) {
        size_t v = order[i], j = i;
        const uint64_t ks = set_key[run->configs[v].set], kr = row_key[v];
        while (j > 0) {
            const size_t u = order[j - 1];
            const uint64_t us = set_key[run->configs[u].set];
            if (us < ks || (us == ks && row_key[u] <= kr))
                break;
            order[j] = u;
            j--;
        }
        order[j] = v;
    }
    free(set_key);
    free(row_key);
}

/* Renders configuration i into img; the time goes to its pass's slot
 * (pass 0 is the warm-up, whose counts every later pass must repeat). */
static int render_one(const study_options *o, study_run *run, size_t i, int pass, sdft_image *img)
{
    study_config *c = &run->configs[i];
    const sdft_render_params p = study_params(o, c);
    sdft_render_stats st;
    char msg[512];
    if (sdft_render(&run->sources[c->source].field, &p, img, &st, msg, sizeof msg)) {
        fail("%s", msg);
        return -1;
    }
    if (pass == 0) {
        c->stats = st;
        return 0;
    }
    c->ms[pass - 1] = st.ms;
    if (st.steps != c->stats.steps || st.primary_steps != c->stats.primary_steps ||
        st.fallbacks != c->stats.fallbacks || st.hits != c->stats.hits || st.cone_steps != c->stats.cone_steps) {
        char cmd[8192];
        study_command(o, c, cmd, sizeof cmd);
        fail("counts differ between two frames of one configuration (a bug): %s", cmd);
        return -1;
    }
    return 0;
}

/* ---- the warm-up's by-products: agreement, Figs. 1 and 2 --------------- */

/* The procedural depth map a discrete row compares with: kept from the
 * procedural row's warm-up frame, shared by rows that differ only in
 * shadows (the primary rays are the same). */
static float *kept_depth(study_run *run, size_t proc, int create, size_t n)
{
    const study_config *p = &run->configs[proc];
    for (size_t k = 0; k < run->ndepths; k++) {
        const study_config *q = &run->configs[run->depth_of[k]];
        if (q->scene == p->scene && q->cap == p->cap && q->screen_space == p->screen_space && q->cones == p->cones &&
            q->method == p->method && !strcmp(q->param, p->param))
            return run->depths[k];
    }
    if (!create)
        return NULL;
    if (run->ndepths == STUDY_MAX_DEPTHS) {
        fail("too many kept depth maps");
        exit(1);
    }
    float *d = malloc(n * sizeof *d);
    if (!d) {
        fail("out of memory for a depth map");
        exit(1);
    }
    run->depth_of[run->ndepths] = proc;
    run->depths[run->ndepths++] = d;
    return d;
}

static void measure_agreement(const study_run *run, study_config *c, const sdft_image *img, const float *proc)
{
    const size_t n = (size_t)img->width * (size_t)img->height;
    const float tol = 1.5f * run->sources[c->source].voxel;
    size_t both = 0, near = 0, one = 0;
    for (size_t i = 0; i < n; i++) {
        const int a = isfinite(img->depth[i]), b = isfinite(proc[i]);
        if (a && b) {
            both++;
            near += fabsf(img->depth[i] - proc[i]) <= tol;
        } else {
            one += a != b;
        }
    }
    c->agree = both ? (double)near / (double)both : NAN;
    c->mismatch = (double)one / (double)n;
}

/* Fig. 1 and Fig. 2 use the no-shadow rows at the paper's cap: the primary rays. */
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

static int keep_figure_data(const study_options *o, study_run *run, study_config *c, const sdft_image *img)
{
    const size_t n = (size_t)img->width * (size_t)img->height;
    c->hist_len = (size_t)c->cap + 8; /* refinement may add up to three steps to the cap */
    c->hist = calloc(c->hist_len, sizeof *c->hist);
    if (!c->hist) {
        fail("out of memory");
        return -1;
    }
    for (size_t i = 0; i < n; i++)
        c->hist[img->primary_steps[i] < c->hist_len ? img->primary_steps[i] : c->hist_len - 1]++;
    if (!study_fig1_method(c))
        return 0;
    /* Fig. 1's planes go to files; their scale's histograms stay here. */
    study_fig1 *f = study_fig1_of(run, c->scene);
    for (size_t i = 0; i < n; i++) {
        f->steps_hist[img->steps[i] < STUDY_HIST ? img->steps[i] : STUDY_HIST - 1]++;
        f->fallback_hist[img->fallbacks[i] < STUDY_HIST ? img->fallbacks[i] : STUDY_HIST - 1]++;
    }
    for (int k = 0; k < 2; k++) {
        char path[4200];
        snprintf(path, sizeof path, "%s/fig1-%s-%s-%s%s-%s.u32", o->out, c->scene->name, STUDY_REP_NAMES[c->rep],
                 sdft_method_name(c->method), c->param, k ? "fallbacks" : "steps");
        if (study_write_file(path, k ? img->fallbacks : img->steps, n * sizeof(uint32_t)))
            return -1;
    }
    return 0;
}

/* ---- main --------------------------------------------------------------- */

/* A pass's progress: a line that updates itself on a terminal, else one
 * line per pass. */
static void progress(const study_options *o, int pass, size_t done, size_t total, double t0)
{
    static int tty = -1;
    if (tty < 0)
        tty = isatty(2);
    if (o->quiet || (!tty && done < total))
        return;
    double now = study_now(), per = done ? (now - t0) / (double)done : 0.0;
    fprintf(stderr, "%sstudy: %s %d of %d: %zu/%zu frames, %.0f s, about %.0f s left in this pass%s", tty ? "\r" : "",
            pass ? "pass" : "warm-up", pass, o->repeats, done, total, now - t0, per * (double)(total - done),
            done == total ? "\n" : "   ");
}

static int run_passes(const study_options *o, study_run *run)
{
    sdft_image img;
    char msg[512];
    if (sdft_image_alloc(&img, o->width, o->height, msg, sizeof msg)) {
        fail("%s", msg);
        return -1;
    }
    const size_t n = (size_t)o->width * (size_t)o->height;
    size_t *order = malloc(run->n * sizeof *order);
    int rc = order ? 0 : -1;
    /* The warm-up: procedural rows first, so that their depth maps are kept
     * when the discrete rows come. */
    double t0 = study_now();
    size_t done = 0;
    run->load[0] = bench_load_average();
    for (int procedural_first = 1; procedural_first >= 0 && !rc; procedural_first--)
        for (size_t i = 0; i < run->n && !rc; i++) {
            study_config *c = &run->configs[i];
            if ((c->rep == STUDY_PROCEDURAL) != procedural_first)
                continue;
            rc = render_one(o, run, i, 0, &img);
            if (!rc && c->rep == STUDY_PROCEDURAL && (c->groups & (STUDY_TABLE | STUDY_BEYOND)))
                memcpy(kept_depth(run, i, 1, n), img.depth, n * sizeof(float));
            if (!rc && c->ref_procedural >= 0) {
                const float *proc = kept_depth(run, (size_t)c->ref_procedural, 0, n);
                if (proc)
                    measure_agreement(run, c, &img, proc);
            }
            if (!rc && study_fig_row(c))
                rc = keep_figure_data(o, run, c, &img);
            progress(o, 0, ++done, run->n, t0);
        }
    run->warmup_s = study_now() - t0;
    for (int pass = 1; pass <= o->repeats && !rc; pass++) {
        pass_order(run, pass, order);
        run->load[pass] = bench_load_average();
        t0 = study_now();
        for (size_t k = 0; k < run->n && !rc; k++) {
            rc = render_one(o, run, order[k], pass, &img);
            progress(o, pass, k + 1, run->n, t0);
        }
    }
    free(order);
    sdft_image_free(&img);
    return rc;
}

int main(int argc, char **argv)
{
    study_options o;
    int parsed = parse_options(argc, argv, &o);
    if (parsed)
        return parsed > 0 ? 0 : 2;
    if (check_out_dir(o.out))
        return 2;
    study_run run = {0};
    build_configs(&o, &run);
    if (run.n == 0) {
        fail("nothing to measure: --parts and --reps leave no configuration");
        return 2;
    }
    link_configs(&run);
    if (o.dry_run) {
        printf("study: %zu configurations, %zu frames of %dx%d\n", run.n, run.n * (size_t)(o.repeats + 1), o.width,
               o.height);
        free(run.configs);
        return 0;
    }
    for (size_t i = 0; i < run.n; i++) {
        run.configs[i].ms = calloc((size_t)o.repeats, sizeof(double));
        run.configs[i].agree = run.configs[i].mismatch = NAN;
        if (!run.configs[i].ms) {
            fail("out of memory");
            return 1;
        }
    }
    int rc = open_sources(&o, &run) ? 2 : 0;
    if (!rc && !o.quiet)
        fprintf(stderr, "study: %zu configurations, 1 warm-up + %d repeats each, %dx%d\n", run.n, o.repeats, o.width,
                o.height);
    run.started = study_now();
    if (!rc)
        rc = run_passes(&o, &run) ? 1 : 0;
    run.total_s = study_now() - run.started;
    if (!rc)
        rc = study_write_results(&o, &run) ? 1 : 0;
    study_run_free(&run);
    return rc;
}
