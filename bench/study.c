/* study — procedural against discrete, method by method, in one process.
 *
 * Bán and Valasek's auto-relaxation paper (Section 4, Figs. 1-5) measures six
 * method settings on procedural scenes and on 1024^3 discrete versions of
 * them; Keinert et al. measure over-relaxation on their city. This program
 * renders every configuration of that study through the library's own
 * sdft_render, exactly as `sdftrace render` does (the same parameters; each
 * row's command line is written beside it and reproduces its counts), and
 * writes what the paper reports and more (bench/study_write.c): the table
 * with each time's median and 95% bootstrap interval, the counts, what the
 * frame would cost a GPU, Figs. 1, 2, 3 and 5's data, the hyperparameters'
 * transfer between scenes, the grids' resolution and the step cap swept,
 * and a mesh's level sets by two tools as a fourth representation.
 *
 * Method: the sources (a procedural scene, a grid) are measured one at a
 * time, the procedural ones first, so that only one grid is in memory (the
 * figure's full grid alone is 3.6 GiB). For each, every configuration on it
 * renders once as a warm-up (its counts are kept, and must be the same in
 * every repeat; the figures' data come from it); then the rows whose time a
 * page shows are timed: REPEATS passes render each once more. Within a
 * pass, the configurations that are compared with each other (same scene,
 * representation, resolution, shadows, step cap and options: always one
 * source) run back to back; the order of those sets and of the rows in
 * each is shuffled anew every pass, so drift on a shared machine hits all
 * alike. A time is the median of the passes' processor times with its
 * bootstrap interval (bench/stats.h); a ratio the median of the two rows'
 * ratio in each pass, with its own.
 *
 * usage: study --out DIR [options]      (study --help lists them)
 * Grids come from `sdftrace bake`, `vdb_tool -mesh2ls` and mesh2sdf
 * (bench/study.sh makes them): DIR/NAME-REP-RES.nvdb. */
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
#include "parse.h"       /* src/common: parse_integer */
#include "sdftrace/grid.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "stats.h"
#include "study.h"
#include "study_write.h"

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
    static char buf[128];
    study_options *o = target;
    char *items[STUDY_REPS * 2];
    const int n = split_list("--reps", value, buf, sizeof buf, items, STUDY_REPS * 2, msg, len);
    memset(o->reps, 0, sizeof o->reps);
    for (int k = 0; k < n; k++) {
        const int r = study_rep_parse(items[k]);
        if (r < 0) {
            snprintf(msg, len, "--reps: unknown representation '%s' (procedural, band, full, vdb_tool or mesh2sdf)",
                     items[k]);
            return -1;
        }
        o->reps[r] = 1;
    }
    return n < 0 ? -1 : 0;
}

/* A list of step caps, each parsed strictly (src/common/parse.h). */
static int set_cap_list(const char *flag, const char *value, int *caps, int *ncaps, char *msg, size_t len)
{
    char buf[128];
    char *items[STUDY_MAX_CAPS];
    const int n = split_list(flag, value, buf, sizeof buf, items, STUDY_MAX_CAPS, msg, len);
    *ncaps = n < 0 ? 0 : n;
    for (int k = 0; k < n; k++) {
        long v;
        if (parse_integer(items[k], &v) || v < 1 || v > 10000000) {
            snprintf(msg, len, "%s must be integers in [1, 10000000], got '%s'", flag, items[k]);
            return -1;
        }
        caps[k] = (int)v;
    }
    return n < 0 ? -1 : 0;
}

static int set_caps(void *target, const char *value, char *msg, size_t len)
{
    study_options *o = target;
    return set_cap_list("--caps", value, o->caps, &o->ncaps, msg, len);
}

static int set_cap_sweep(void *target, const char *value, char *msg, size_t len)
{
    study_options *o = target;
    return set_cap_list("--cap-sweep", value, o->cap_sweep, &o->ncap_sweep, msg, len);
}

/* --parts LIST: which groups of rows are measured. */
static int set_parts(void *target, const char *value, char *msg, size_t len)
{
    static char buf[128];
    study_options *o = target;
    char *items[16];
    const int n = split_list("--parts", value, buf, sizeof buf, items, 16, msg, len);
    o->parts = 0;
    for (int k = 0; k < n; k++) {
        unsigned bit = 0;
        for (unsigned b = 0; b < STUDY_GROUPS; b++)
            if (!strcmp(items[k], STUDY_GROUP_NAMES[b]))
                bit = 1u << b;
        if (!bit) {
            snprintf(msg, len, "--parts: unknown part '%s' (table, sweep, keinert, beyond, res or caps)", items[k]);
            return -1;
        }
        o->parts |= bit;
    }
    return n < 0 ? -1 : 0;
}

enum { STUDY_OPTION_ROWS = 21 };

/* The options of study, over o (for the help, over the defaults), in rows,
 * and the command line they make; *scenes, *meshes: the lists, resolved
 * after parsing. */
static cmdline_spec study_option_rows(study_options *o, const char **scenes, const char **meshes,
                                      cmdline_option rows[STUDY_OPTION_ROWS])
{
    const cmdline_option t[STUDY_OPTION_ROWS] = {
        {"out", 0, "DIR", "where results.csv, table.md and the figures' data go; must be writable", CMDLINE_TEXT,
         &o->out, .def = ""},
        {"grids", 0, "DIR",
         "the grids, DIR/NAME-REP-RES.nvdb: REP band and full (sdftrace bake; RES the\n"
         "resolution and, for --parts res, a half and a quarter of it), vdb_tool and mesh2sdf",
         CMDLINE_TEXT, &o->grids, .value = 1},
        {"res", 0, "N", "the grids' resolution, 4..1024", CMDLINE_INT, &o->res, .lo = 4, .hi = 1024},
        {"width", 0, "W", "image width, 1..16384", CMDLINE_INT, &o->width, .lo = 1, .hi = 16384},
        {"height", 0, "H", "image height, 1..16384", CMDLINE_INT, &o->height, .lo = 1, .hi = 16384},
        {"repeats", 0, "R", "timed frames per timed configuration after the warm-up, 1..100", CMDLINE_INT, &o->repeats,
         .lo = 1, .hi = STUDY_MAX_REPEATS},
        {"sweep", 0, "N", "values per method in the hyperparameter sweep, 0..40 (0: none)", CMDLINE_INT, &o->sweep,
         .lo = 0, .hi = 40},
        {"scenes", 0, "LIST", "the procedural scenes, comma-separated", CMDLINE_TEXT, scenes, .value = 1},
        {"meshes", 0, "LIST",
         "meshes whose level sets are measured (DIR/NAME-vdb_tool-RES.nvdb,\n"
         "DIR/NAME-mesh2sdf-RES.nvdb), comma-separated",
         CMDLINE_TEXT, meshes, .value = 1, .def = "none"},
        {"reps", 0, "LIST", "representations: procedural,band,full,vdb_tool,mesh2sdf", CMDLINE_CALL, o, .def = "all",
         .handle = set_reps},
        {"caps", 0, "LIST", "step caps of the table, comma-separated", CMDLINE_CALL, o, .def = "1000,32",
         .handle = set_caps},
        {"cap-sweep", 0, "LIST", "step caps of the cap sweep beside the table's, comma-separated", CMDLINE_CALL, o,
         .def = "16,64,128", .handle = set_cap_sweep},
        {"parts", 0, "LIST", "table,sweep,keinert,beyond,res,caps", CMDLINE_CALL, o, .def = "all", .handle = set_parts},
        {"cli", 0, "PATH", "the sdftrace binary named in the command lines", CMDLINE_TEXT, &o->cli, .value = 1},
        {"row-exr", 0, "PATH", "the -o of those command lines", CMDLINE_TEXT, &o->row_exr, .value = 1},
        {"quiet", 0, NULL, "no progress on stderr", CMDLINE_SET, &o->quiet, .value = 1, .def = ""},
        {"dry-run", 0, NULL, "check the options, count the configurations and frames, touch no grid", CMDLINE_SET,
         &o->dry_run, .value = 1, .def = ""},
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

static study_options default_options(const char **scenes, const char **meshes)
{
    *scenes = "temple,figure";
    *meshes = NULL;
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
                           .cap_sweep = {16, 64, 128},
                           .ncap_sweep = 3,
                           .parts = (1u << STUDY_GROUPS) - 1,
                           .reps = {1, 1, 1, 1, 1}};
}

static void usage(FILE *out)
{
    const char *scenes, *meshes;
    study_options d = default_options(&scenes, &meshes);
    cmdline_option rows[STUDY_OPTION_ROWS];
    const cmdline_spec spec = study_option_rows(&d, &scenes, &meshes, rows);
    cmdline_help(&spec, out);
}

/* A mesh's name becomes part of file names: letters, digits, '-' and '_'. */
static int plain_name(const char *s)
{
    for (const char *p = s; *p; p++)
        if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '-' ||
              *p == '_'))
            return 0;
    return *s != '\0' && strlen(s) < 64;
}

/* The checks that need all the options at once, and the scenes by name. */
static int check_options(study_options *o, const char *scenes, const char *meshes, char *msg, size_t len)
{
    static char buf[256], mesh_buf[256];
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
    o->nmeshes = 0;
    if (meshes) {
        char *names[STUDY_MAX_MESHES];
        const int m = split_list("--meshes", meshes, mesh_buf, sizeof mesh_buf, names, STUDY_MAX_MESHES, msg, len);
        if (m < 0)
            return -1;
        for (int k = 0; k < m; k++) {
            if (!plain_name(names[k])) {
                snprintf(msg, len, "--meshes: '%s' is not a name of letters, digits, '-' and '_'", names[k]);
                return -1;
            }
            o->meshes[k] = (sdft_scene){.name = names[k]}; /* its view: once its grid is open */
        }
        o->nmeshes = m;
    }
    if (!o->out)
        snprintf(msg, len, "--out DIR is required (try: study --help)");
    else if (!o->reps[STUDY_PROCEDURAL] && (o->parts & (STUDY_TABLE | STUDY_BEYOND)) && o->nscenes)
        snprintf(msg, len,
                 "--reps: the table and the beyond rows compare with the procedural scene; include procedural");
    else
        return 0;
    return -1;
}

/* 0: options read; 1: the help was asked for (and printed); -1: an error (printed). */
static int parse_options(int argc, char **argv, study_options *o)
{
    const char *scenes, *meshes;
    char msg[512];
    *o = default_options(&scenes, &meshes);
    cmdline_option rows[STUDY_OPTION_ROWS];
    const cmdline_spec spec = study_option_rows(o, &scenes, &meshes, rows);
    const int parsed = cmdline_parse(&spec, argc, argv, msg, sizeof msg);
    if (parsed == CMDLINE_HELP_ASKED) {
        usage(stdout);
        return 1;
    }
    if (parsed != CMDLINE_OK || check_options(o, scenes, meshes, msg, sizeof msg)) {
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
    return a->scene == b->scene && a->rep == b->rep && a->res == b->res && a->shadows == b->shadows &&
           a->cap == b->cap && a->screen_space == b->screen_space && a->cones == b->cones;
}

static int same_config(const study_config *a, const study_config *b)
{
    return same_setting(a, b) && a->method == b->method && !strcmp(a->param, b->param);
}

/* Adds a configuration to the list, or its groups and timing to an equal
 * one already there. */
static void add_config(study_run *run, study_config c)
{
    for (size_t i = 0; i < run->n; i++)
        if (same_config(&run->configs[i], &c)) {
            run->configs[i].groups |= c.groups;
            run->configs[i].timed |= c.timed;
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

static study_config make_config(const sdft_scene *scene, int rep, int res, const study_method *m, int shadows, int cap,
                                unsigned groups, int timed)
{
    study_config c = {.scene = scene,
                      .rep = rep,
                      .res = rep == STUDY_PROCEDURAL ? 0 : res,
                      .method = m->method,
                      .shadows = shadows,
                      .cap = cap,
                      .groups = groups,
                      .timed = timed};
    snprintf(c.param, sizeof c.param, "%s", m->param);
    return c;
}

/* A parameter as the command line carries it: %.4g, so that the value the
 * CLI parses from it is the value measured. */
static study_method swept(sdft_method m, double v, char *text, size_t len)
{
    snprintf(text, len, "%.4g", v);
    return (study_method){m, text, ""};
}

/* The representations a subject has: a scene its function and two bakes,
 * a mesh its two tools' level sets. */
static int rep_of(const study_options *o, const sdft_scene *subject, int rep)
{
    const int mesh = subject >= o->meshes && subject < o->meshes + STUDY_MAX_MESHES;
    return o->reps[rep] && mesh == study_rep_of_mesh(rep);
}

/* Fig. 3: each scene at the paper's cap, beta in (0, 1/2], enhanced omega
 * in [1/2, 1], relaxed omega in [1, 2) in both forms (the paper's
 * Algorithm 2 and Keinert's Listing 2), and the table's values among them.
 * Timed on the paper's own panel (the temple's discrete version, our full
 * grid), counted everywhere. */
static void add_sweep(const study_options *o, study_run *run, const sdft_scene *scene, int rep, int shadows)
{
    const int n = o->sweep, timed = study_sweep_timed(scene, rep);
    char text[16];
    const study_method sphere = {SDFT_SPHERE, "", ""};
    add_config(run, make_config(scene, rep, o->res, &sphere, shadows, 1000, STUDY_SWEEP, timed));
    for (int k = 0; k < n; k++) {
        study_method m = swept(SDFT_AUTO, 0.5 * (k + 1) / n, text, sizeof text);
        add_config(run, make_config(scene, rep, o->res, &m, shadows, 1000, STUDY_SWEEP, timed));
        m = swept(SDFT_ENHANCED, n > 1 ? 0.5 + 0.5 * k / (n - 1) : 1.0, text, sizeof text);
        add_config(run, make_config(scene, rep, o->res, &m, shadows, 1000, STUDY_SWEEP, timed));
        for (int form = 0; form < 2; form++) {
            m = swept(form ? SDFT_RELAXED : SDFT_RELAXED_BV, 1.0 + (double)k / n, text, sizeof text);
            add_config(run, make_config(scene, rep, o->res, &m, shadows, 1000, STUDY_SWEEP, timed));
        }
    }
    for (int m = 1; m < STUDY_TABLE_ROWS; m++)
        add_config(run, make_config(scene, rep, o->res, &STUDY_TABLE_METHODS[m], shadows, 1000, STUDY_SWEEP, timed));
}

static void build_configs(const study_options *o, study_run *run)
{
    const sdft_scene *subjects[STUDY_MAX_SUBJECTS];
    int nsubjects = 0;
    for (int s = 0; s < o->nscenes; s++)
        subjects[nsubjects++] = o->scenes[s];
    for (int s = 0; s < o->nmeshes; s++)
        subjects[nsubjects++] = &o->meshes[s];
    /* The paper's table: its time with the shadow ray; without it, at the
     * paper's cap, the primary rays of Figs. 1, 2 and 5, counted. */
    for (int s = 0; s < nsubjects && (o->parts & STUDY_TABLE); s++)
        for (int rep = 0; rep < STUDY_REPS; rep++)
            for (int shadows = 1; shadows >= 0 && rep_of(o, subjects[s], rep); shadows--)
                for (int k = 0; k < o->ncaps; k++)
                    for (int m = 0; m < STUDY_TABLE_ROWS && (shadows || o->caps[k] == 1000); m++)
                        add_config(run, make_config(subjects[s], rep, o->res, &STUDY_TABLE_METHODS[m], shadows,
                                                    o->caps[k], STUDY_TABLE, shadows));
    /* Fig. 3: with the shadow ray everywhere; without it where it is timed,
     * as the paper shows both. */
    for (int s = 0; s < o->nscenes && (o->parts & STUDY_SWEEP) && o->sweep > 0; s++)
        for (int rep = 0; rep <= STUDY_FULL; rep++)
            for (int shadows = 1; shadows >= 0 && o->reps[rep]; shadows--)
                if (shadows || study_sweep_timed(o->scenes[s], rep))
                    add_sweep(o, run, o->scenes[s], rep, shadows);
    /* Keinert et al.: ray casting the city (no shadows), constant epsilon and
     * his screen-space criterion, at his step caps, relaxed as his Listing 2
     * has it; timed. */
    const sdft_scene *city = sdft_scene_find("city");
    if (o->parts & STUDY_KEINERT)
        for (size_t k = 0; k < sizeof KEINERT_CAPS / sizeof KEINERT_CAPS[0]; k++)
            for (int ss = 0; ss < 2; ss++)
                for (size_t m = 0; m < sizeof KEINERT_OMEGAS / sizeof KEINERT_OMEGAS[0]; m++) {
                    const study_method km = {*KEINERT_OMEGAS[m] ? SDFT_RELAXED : SDFT_SPHERE, KEINERT_OMEGAS[m], ""};
                    study_config c = make_config(city, STUDY_PROCEDURAL, 0, &km, 0, KEINERT_CAPS[k], STUDY_KEINERT, 1);
                    c.screen_space = ss;
                    add_config(run, c);
                }
    /* Beyond the paper: the best variant with cones and the screen-space
     * criterion, on every representation; timed. */
    for (int s = 0; s < o->nscenes && (o->parts & STUDY_BEYOND); s++)
        for (int rep = 0; rep <= STUDY_FULL; rep++)
            for (int v = 0; v < 4 && o->reps[rep]; v++) {
                study_config c = make_config(o->scenes[s], rep, o->res, &STUDY_TABLE_METHODS[STUDY_BEST_ROW], 1, 1000,
                                             STUDY_BEYOND, 1);
                c.cones = v & 1, c.screen_space = v >> 1;
                add_config(run, c);
            }
    /* The grids at a quarter and a half of the resolution (the whole is
     * the table's), and the cap sweep: counted. */
    for (int s = 0; s < o->nscenes && (o->parts & STUDY_RES); s++)
        for (int rep = STUDY_BAND; rep <= STUDY_FULL; rep++)
            for (int div = 4; div >= 1 && o->reps[rep]; div /= 2)
                for (int m = 0; m < STUDY_TABLE_ROWS; m++)
                    add_config(run, make_config(o->scenes[s], rep, o->res / div, &STUDY_TABLE_METHODS[m], 1, 1000,
                                                STUDY_RES, 0));
    for (int s = 0; s < o->nscenes && (o->parts & STUDY_CAPS); s++)
        for (int rep = 0; rep <= STUDY_FULL; rep++)
            for (int k = 0; k < o->ncap_sweep && o->reps[rep]; k++)
                for (int m = 0; m < STUDY_TABLE_ROWS; m++)
                    add_config(run, make_config(o->scenes[s], rep, o->res, &STUDY_TABLE_METHODS[m], 1, o->cap_sweep[k],
                                                STUDY_CAPS, 0));
}

/* Each row's partners: the same setting's enhanced 0.88 and sphere rows,
 * the same setting without cones or screen-space, the same row on the
 * procedural scene (at any resolution); and its comparison set (same
 * setting). */
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
            if (d->scene == c->scene && d->rep == c->rep && d->res == c->res && d->shadows == c->shadows &&
                d->cap == c->cap && d->method == c->method && !strcmp(d->param, c->param) && !d->cones &&
                !d->screen_space)
                c->ref_plain = (int)j;
            if (c->rep != STUDY_PROCEDURAL && d->rep == STUDY_PROCEDURAL && d->scene == c->scene &&
                d->shadows == c->shadows && d->cap == c->cap && d->screen_space == c->screen_space &&
                d->cones == c->cones && d->method == c->method && !strcmp(d->param, c->param))
                c->ref_procedural = (int)j;
        }
    }
}

/* ---- sources: the procedural scenes and their grids --------------------- */

/* Lists every source some configuration uses (the procedural ones first,
 * so that their depth maps are kept before any grid's rows compare with
 * them) and points each row at its own; -1 (and one line) when there are
 * too many. Nothing is loaded yet: each grid is opened only while its rows
 * are measured (open_source), so that one grid at a time is in memory. */
static int list_sources(study_run *run)
{
    for (int procedural = 1; procedural >= 0; procedural--)
        for (size_t i = 0; i < run->n; i++) {
            const study_config *c = &run->configs[i];
            int found = (c->rep == STUDY_PROCEDURAL) != procedural;
            for (int k = 0; k < run->nsources && !found; k++)
                found =
                    run->sources[k].scene == c->scene && run->sources[k].rep == c->rep && run->sources[k].res == c->res;
            if (found)
                continue;
            if (run->nsources == STUDY_MAX_SOURCES) {
                fail("too many sources");
                return -1;
            }
            run->sources[run->nsources++] =
                (study_source){.scene = c->scene, .rep = c->rep, .res = c->res, .field = c->scene->field};
        }
    for (size_t i = 0; i < run->n; i++) {
        study_config *c = &run->configs[i];
        for (int k = 0; k < run->nsources; k++)
            if (run->sources[k].scene == c->scene && run->sources[k].rep == c->rep && run->sources[k].res == c->res)
                c->source = k;
    }
    return 0;
}

/* Opens source k's grid (nothing for a procedural scene) and gives each of
 * its rows its view: the scene's, or for a mesh's grid the front view
 * `sdftrace render --grid` gives that grid (its command line names no
 * scene). 0, or -1 with one line. */
static int open_source(const study_options *o, study_run *run, int k)
{
    study_source *src = &run->sources[k];
    if (src->rep != STUDY_PROCEDURAL) {
        study_source_path(o, src->scene, src->rep, src->res, src->path, sizeof src->path);
        char msg[512];
        if (!o->quiet)
            fprintf(stderr, "study: loading %s\n", src->path);
        sdft_grid_options go = sdft_grid_options_defaults();
        go.path = src->path;
        if (sdft_grid_open(&go, &src->grid, msg, sizeof msg)) {
            fail("%s (bench/study.sh makes the grids)", msg);
            return -1;
        }
        src->field = sdft_grid_field(src->grid, SDFT_GRID_BOUND_FAR);
        src->voxel = sdft_grid_voxel_size(src->grid).x;
    }
    for (size_t i = 0; i < run->n; i++) {
        study_config *c = &run->configs[i];
        if (c->source != k)
            continue;
        c->camera = c->scene->camera, c->light = c->scene->light;
        if (study_rep_of_mesh(c->rep))
            study_front_view(sdft_grid_world_bounds(src->grid), o->width, o->height, &c->camera, &c->light);
    }
    return 0;
}

static void close_source(study_run *run, int k)
{
    sdft_grid_free(run->sources[k].grid);
    run->sources[k].grid = NULL;
}

/* ---- measuring ---------------------------------------------------------- */

static uint64_t rng_next(uint64_t *s)
{
    *s ^= *s >> 12, *s ^= *s << 25, *s ^= *s >> 27;
    return *s * 0x2545F4914F6CDD1Dull;
}

/* This pass's order of source k's timed rows (*count of them): sets
 * shuffled, each set's rows together, shuffled. */
static void pass_order(const study_run *run, int k, int pass, size_t *order, size_t *count)
{
    uint64_t seed = 0x9E3779B97F4A7C15ull * (uint64_t)(pass + 1) + 1 + 0x632BE59BD9B4E019ull * (uint64_t)k;
    uint64_t *set_key = malloc(run->n * sizeof *set_key), *row_key = malloc(run->n * sizeof *row_key);
    if (!set_key || !row_key) {
        fail("out of memory");
        exit(1);
    }
    for (size_t i = 0; i < run->n; i++)
        set_key[i] = rng_next(&seed), row_key[i] = rng_next(&seed);
    size_t n = 0;
    for (size_t i = 0; i < run->n; i++)
        if (run->configs[i].timed && run->configs[i].source == k)
            order[n++] = i;
    /* Insertion sort by (the set's key, the row's key): n is a few hundred. */
    for (size_t i = 1; i < n; i++) {
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
    *count = n;
    free(set_key);
    free(row_key);
}

/* Renders configuration i into img; a timed pass's times go to its slot
 * (pass 0 is the warm-up, whose counts every later pass must repeat). */
static int render_one(const study_options *o, study_run *run, size_t i, int pass, sdft_image *img)
{
    study_config *c = &run->configs[i];
    const sdft_render_params p = study_params(o, c);
    sdft_render_stats st;
    char msg[512];
    const double cpu0 = study_cpu_now();
    if (sdft_render(&run->sources[c->source].field, &p, img, &st, msg, sizeof msg)) {
        fail("%s", msg);
        return -1;
    }
    const double cpu_ms = 1000.0 * (study_cpu_now() - cpu0);
    if (pass == 0) {
        c->stats = st;
        c->gpu_cost =
            study_wavefront_cost(img->primary_steps, img->steps, img->width, img->height, STUDY_TILE_W, STUDY_TILE_H);
        return 0;
    }
    c->ms[pass - 1] = st.ms;
    c->cpu_ms[pass - 1] = cpu_ms;
    if (st.steps != c->stats.steps || st.primary_steps != c->stats.primary_steps ||
        st.fallbacks != c->stats.fallbacks || st.hits != c->stats.hits || st.cone_steps != c->stats.cone_steps) {
        char cmd[8192];
        study_command(o, c, cmd, sizeof cmd);
        fail("counts differ between two frames of one configuration (a bug): %s", cmd);
        return -1;
    }
    return 0;
}

/* ---- the warm-up's by-products: agreement, Figs. 1, 2 and 5 -------------- */

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
    if (!study_fig1_method(c) || study_rep_of_mesh(c->rep))
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

/* Fig. 5: the map of auto-relaxation's step multipliers (study_multiplier.c),
 * for the primary rays of this frame, and its summary: the median pixel,
 * and the share of pixels whose steps averaged more than 2 (rays leaving a
 * surface behind, where the slope m turns positive and 2 / (1 - m) exceeds 2). */
static int keep_multipliers(const study_options *o, study_run *run, study_config *c, const sdft_image *img)
{
    const sdft_render_params p = study_params(o, c);
    const size_t n = (size_t)img->width * (size_t)img->height;
    float *map = malloc(n * sizeof *map);
    double *values = malloc(n * sizeof *values);
    char msg[512];
    int rc = map && values ? 0 : -1;
    if (rc)
        fail("out of memory for Fig. 5");
    else if ((rc = study_multiplier_map(&run->sources[c->source].field, &p.trace, &p.camera, img->width, img->height,
                                        img->primary_steps, map, NULL, msg, sizeof msg)))
        fail("Fig. 5: %s", msg);
    size_t k = 0, above = 0;
    for (size_t i = 0; !rc && i < n; i++)
        if (isfinite(map[i])) {
            values[k++] = map[i];
            above += map[i] > 2.0f;
        }
    c->multiplier = k ? bench_median(values, (int)k) : NAN;
    c->multiplier_above_2 = k ? (double)above / (double)k : NAN;
    if (!rc) {
        char path[4200];
        snprintf(path, sizeof path, "%s/fig5-%s-%s.f32", o->out, c->scene->name, STUDY_REP_NAMES[c->rep]);
        rc = study_write_file(path, map, n * sizeof *map);
    }
    free(values);
    free(map);
    return rc;
}

/* ---- main --------------------------------------------------------------- */

/* Progress: a line that updates itself on a terminal, else a line every
 * tenth of the frames. */
static void progress(const study_options *o, const char *scene, const char *rep, size_t done, size_t total, double t0)
{
    static int tty = -1;
    if (tty < 0)
        tty = isatty(2);
    if (o->quiet || (!tty && done % (total / 10 + 1) != 0 && done < total))
        return;
    double now = study_now(), per = (now - t0) / (double)done;
    fprintf(stderr, "%sstudy: %s, %s: %zu/%zu frames, %.0f s, about %.0f s left%s", tty ? "\r" : "", scene, rep, done,
            total, now - t0, per * (double)(total - done), tty && done < total ? "   " : "\n");
}

/* The warm-up's by-products of row i, rendered into img. */
static int warm_up_extras(const study_options *o, study_run *run, size_t i, const sdft_image *img)
{
    study_config *c = &run->configs[i];
    const size_t n = (size_t)o->width * (size_t)o->height;
    if (c->rep == STUDY_PROCEDURAL && (c->groups & (STUDY_TABLE | STUDY_BEYOND | STUDY_CAPS)))
        memcpy(kept_depth(run, i, 1, n), img->depth, n * sizeof(float));
    if (c->ref_procedural >= 0) {
        const float *proc = kept_depth(run, (size_t)c->ref_procedural, 0, n);
        if (proc)
            measure_agreement(run, c, img, proc);
    }
    if (!study_fig_row(c))
        return 0;
    if (keep_figure_data(o, run, c, img))
        return -1;
    return study_fig5_method(c) ? keep_multipliers(o, run, c, img) : 0;
}

/* Measures source k's rows: the warm-up, then the timed passes. */
static int measure_source(const study_options *o, study_run *run, int k, sdft_image *img, size_t *order, double t0,
                          size_t *done)
{
    const size_t total = run->n + run->timed_rows * (size_t)o->repeats;
    const double warm = study_now();
    int rc = 0;
    for (size_t i = 0; i < run->n && !rc; i++) {
        if (run->configs[i].source != k)
            continue;
        rc = render_one(o, run, i, 0, img);
        if (!rc)
            rc = warm_up_extras(o, run, i, img);
        progress(o, run->sources[k].scene->name, STUDY_REP_NAMES[run->sources[k].rep], ++*done, total, t0);
    }
    run->warmup_s += study_now() - warm;
    size_t count = 0;
    for (int pass = 1; pass <= o->repeats && !rc; pass++) {
        pass_order(run, k, pass, order, &count);
        for (size_t j = 0; j < count && !rc; j++) {
            rc = render_one(o, run, order[j], pass, img);
            progress(o, run->sources[k].scene->name, STUDY_REP_NAMES[run->sources[k].rep], ++*done, total, t0);
        }
    }
    return rc;
}

/* Every source in turn (the procedural scenes first), its grid in memory
 * only while its rows are measured. */
static int run_sources(const study_options *o, study_run *run)
{
    sdft_image img;
    char msg[512];
    if (sdft_image_alloc(&img, o->width, o->height, msg, sizeof msg)) {
        fail("%s", msg);
        return -1;
    }
    size_t *order = malloc(run->n * sizeof *order), done = 0;
    int rc = order ? 0 : -1;
    const double t0 = study_now();
    run->load_first = bench_load_average();
    run->load_lo = run->load_hi = run->load_first;
    for (int k = 0; k < run->nsources && !rc; k++) {
        const double load = bench_load_average();
        run->load_lo = fmin(run->load_lo, load), run->load_hi = fmax(run->load_hi, load);
        rc = open_source(o, run, k);
        if (!rc)
            rc = measure_source(o, run, k, &img, order, t0, &done);
        close_source(run, k);
    }
    run->load_last = bench_load_average();
    run->load_lo = fmin(run->load_lo, run->load_last), run->load_hi = fmax(run->load_hi, run->load_last);
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
        fail("nothing to measure: --parts, --reps, --scenes and --meshes leave no configuration");
        return 2;
    }
    link_configs(&run);
    for (size_t i = 0; i < run.n; i++)
        run.timed_rows += run.configs[i].timed != 0;
    if (o.dry_run) {
        printf("study: %zu configurations (%zu timed), %zu frames of %dx%d\n", run.n, run.timed_rows,
               run.n + run.timed_rows * (size_t)o.repeats, o.width, o.height);
        free(run.configs);
        return 0;
    }
    for (size_t i = 0; i < run.n; i++) {
        study_config *c = &run.configs[i];
        c->ms = calloc((size_t)o.repeats, sizeof(double));
        c->cpu_ms = calloc((size_t)o.repeats, sizeof(double));
        c->agree = c->mismatch = c->multiplier = c->multiplier_above_2 = NAN;
        if (!c->ms || !c->cpu_ms) {
            fail("out of memory");
            return 1;
        }
    }
    int rc = list_sources(&run) ? 2 : 0;
    if (!rc && !o.quiet)
        fprintf(stderr, "study: %zu configurations, 1 warm-up each, %d timed repeats of %zu, %dx%d\n", run.n, o.repeats,
                run.timed_rows, o.width, o.height);
    run.started = study_now();
    if (!rc)
        rc = run_sources(&o, &run) ? 1 : 0;
    run.total_s = study_now() - run.started;
    if (!rc)
        rc = study_write_results(&o, &run) ? 1 : 0;
    study_run_free(&run);
    return rc;
}
