/* study — writing what bench/study.c measured: results.csv (every row, with
 * its command line), table.md (the paper's layout and the other groups),
 * and the data of the figures for bench/fig*.gp. Every file goes through
 * sdftrace's atomic writer (src/common/atomic_file.h): a temporary file
 * beside it, flushed and renamed into place, with the umask's mode. It
 * reads the rows through study.h (bench/study_rows.c) alone. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "atomic_file.h"
#include "stats.h"
#include "study.h"
#include "study_write.h"

/* ---- files -------------------------------------------------------------- */

/* A file being written through the atomic writer: a stream on a duplicate
 * of its descriptor, so that closing the stream leaves the writer's own for
 * the commit (as src/io/png.c does). */
typedef struct out_file {
    atomic_file af;
    FILE *f;
} out_file;

static int out_begin(out_file *o, const char *path, const char *mode)
{
    char msg[512];
    o->f = NULL;
    if (atomic_file_begin(&o->af, path, msg, sizeof msg)) {
        fprintf(stderr, "study: %s\n", msg);
        return -1;
    }
    const int fd = dup(o->af.fd);
    o->f = fd < 0 ? NULL : fdopen(fd, mode);
    if (!o->f) {
        if (fd >= 0)
            close(fd);
        atomic_file_abort(&o->af);
        fprintf(stderr, "study: cannot write %s\n", path);
        return -1;
    }
    return 0;
}

static int out_open(out_file *o, const char *dir, const char *name)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return out_begin(o, path, "w");
}

/* Closes the stream and renames the file into place; on a write error (or
 * `failed`) the temporary file goes and the target is left as it was. */
static int out_finish(out_file *o, int failed)
{
    char msg[512];
    int bad = failed || ferror(o->f);
    bad |= fclose(o->f) != 0;
    o->f = NULL;
    if (bad) {
        fprintf(stderr, "study: cannot write %s\n", o->af.path);
        atomic_file_abort(&o->af);
        return -1;
    }
    if (atomic_file_commit(&o->af, msg, sizeof msg)) {
        fprintf(stderr, "study: %s\n", msg);
        return -1;
    }
    return 0;
}

static int out_close(out_file *o) { return out_finish(o, 0); }

int study_write_file(const char *path, const void *data, size_t size)
{
    out_file o;
    if (out_begin(&o, path, "wb"))
        return -1;
    return out_finish(&o, fwrite(data, 1, size, o.f) != size);
}

/* ---- cells -------------------------------------------------------------- */

static const study_summary *sum_of(const study_run *run, int i) { return &run->summaries[i]; }

/* "1234 [1200–1300]": a time's median and interval; "–" when not timed. */
static const char *time_cell(char *buf, size_t len, const bench_summary *s)
{
    if (s->n < 1)
        snprintf(buf, len, "–");
    else
        snprintf(buf, len, "%.0f [%.0f–%.0f]", s->median, s->lo, s->hi);
    return buf;
}

/* "94% [90–97]": a ratio's median and interval, in percent. */
static const char *rel_cell(char *buf, size_t len, const bench_summary *s)
{
    if (s->n < 1)
        snprintf(buf, len, "–");
    else
        snprintf(buf, len, "%.0f%% [%.0f–%.0f]", 100.0 * s->median, 100.0 * s->lo, 100.0 * s->hi);
    return buf;
}

/* "0.94" or "" for a missing number. */
static const char *num(char *buf, size_t len, const char *fmt, double v)
{
    if (isnan(v))
        snprintf(buf, len, "%s", "");
    else
        snprintf(buf, len, fmt, v);
    return buf;
}

/* ---- finding rows ------------------------------------------------------- */

typedef struct row_key {
    const sdft_scene *scene;
    int rep, res; /* res 0: the run's (procedural: none) */
    const study_method *method;
    int shadows, cap, screen_space, cones;
} row_key;

static int find_row(const study_options *o, const study_run *run, row_key k)
{
    const int res = k.rep == STUDY_PROCEDURAL ? 0 : k.res ? k.res : o->res;
    for (size_t i = 0; i < run->n; i++) {
        const study_config *c = &run->configs[i];
        if (c->scene == k.scene && c->rep == k.rep && c->res == res && c->method == k.method->method &&
            !strcmp(c->param, k.method->param) && c->shadows == k.shadows && c->cap == k.cap &&
            c->screen_space == k.screen_space && c->cones == k.cones)
            return (int)i;
    }
    return -1;
}

/* A row of the paper's methods: scene, representation, method, shadows, cap. */
static int find(const study_options *o, const study_run *run, const sdft_scene *scene, int rep, const study_method *m,
                int shadows, int cap)
{
    return find_row(o, run, (row_key){scene, rep, 0, m, shadows, cap, 0, 0});
}

/* The subjects measured (scenes, then meshes) and whether a subject is a mesh. */
static int subjects(const study_options *o, const sdft_scene *out[STUDY_MAX_SUBJECTS])
{
    int n = 0;
    for (int s = 0; s < o->nscenes; s++)
        out[n++] = o->scenes[s];
    for (int s = 0; s < o->nmeshes; s++)
        out[n++] = &o->meshes[s];
    return n;
}

static int is_mesh(const study_options *o, const sdft_scene *s)
{
    return s >= o->meshes && s < o->meshes + STUDY_MAX_MESHES;
}

/* The representations a subject has among those measured. */
static int has_rep(const study_options *o, const sdft_scene *s, int rep)
{
    return o->reps[rep] && is_mesh(o, s) == study_rep_of_mesh(rep);
}

/* ---- results.csv -------------------------------------------------------- */

static int write_csv(const study_options *o, const study_run *run)
{
    out_file f;
    if (out_open(&f, o->out, "results.csv"))
        return -1;
    fprintf(f.f,
            "groups,scene,representation,res,method,param,shadows,max_steps,screen_space,cones,width,height,timed,"
            "repeats,cpu_ms_median,cpu_ms_lo,cpu_ms_hi,ms_median,ms_lo,ms_hi,rel_enhanced,rel_enhanced_lo,"
            "rel_enhanced_hi,rel_sphere,rel_sphere_lo,rel_sphere_hi,rel_plain,rel_plain_lo,rel_plain_hi,mean_steps,"
            "mean_primary_steps,mean_shadow_steps,mean_cone_steps,mean_fallbacks,mean_primary_fallbacks,"
            "nonconverged,hit_fraction,gpu_cost,agree_1p5vox,hit_mismatch,multiplier_median,multiplier_above_2,steps,"
            "command\n");
    for (size_t i = 0; i < run->n; i++) {
        const study_config *c = &run->configs[i];
        const study_summary *s = sum_of(run, (int)i);
        char groups[96] = "", cmd[8192], v[19][32];
        for (unsigned k = 0; k < STUDY_GROUPS; k++)
            if (c->groups & (1u << k))
                snprintf(groups + strlen(groups), sizeof groups - strlen(groups), "%s%s", *groups ? " " : "",
                         STUDY_GROUP_NAMES[k]);
        study_command(o, c, cmd, sizeof cmd);
        const bench_summary *b[5] = {&s->cpu, &s->ms, &s->rel_enhanced, &s->rel_sphere, &s->rel_plain};
        for (int k = 0; k < 5; k++) {
            const char *fmt = k < 2 ? "%.3f" : "%.4f";
            num(v[3 * k], 32, fmt, b[k]->n ? b[k]->median : NAN);
            num(v[3 * k + 1], 32, fmt, b[k]->n ? b[k]->lo : NAN);
            num(v[3 * k + 2], 32, fmt, b[k]->n ? b[k]->hi : NAN);
        }
        num(v[15], 32, "%.6f", c->agree);
        num(v[16], 32, "%.6f", c->mismatch);
        num(v[17], 32, "%.4f", c->multiplier);
        num(v[18], 32, "%.6f", c->multiplier_above_2);
        /* mean_steps as `sdftrace render --json` prints it (%.4f), to compare digit by digit */
        fprintf(f.f,
                "%s,%s,%s,%d,%s,%s,%d,%d,%d,%d,%d,%d,%d,%d,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%.4f,%.4f,%.4f,"
                "%.4f,%.4f,%.4f,%.6f,%.6f,%.4f,%s,%s,%s,%s,%llu,\"%s\"\n",
                groups, c->scene->name, STUDY_REP_NAMES[c->rep], c->res, sdft_method_name(c->method), c->param,
                c->shadows, c->cap, c->screen_space, c->cones, o->width, o->height, c->timed, c->timed ? o->repeats : 0,
                v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9], v[10], v[11], v[12], v[13], v[14], s->steps,
                s->primary, s->shadow, s->cone, s->fallbacks, s->primary_fallbacks, s->nonconverged, s->hits, s->gpu,
                v[15], v[16], v[17], v[18], (unsigned long long)c->stats.steps, cmd);
    }
    return out_close(&f);
}

/* ---- table.md: the paper's table ---------------------------------------- */

/* The paper's rel column (Bán–Valasek, Section 4), in STUDY_TABLE_METHODS'
 * order (0: not in the paper, Keinert's Listing 2); its procedural and its
 * discrete 1024^3 (a dense 3D texture) columns. */
static const int PAPER_REL[2][2][STUDY_TABLE_ROWS] = {
    {{125, 100, 106, 98, 0, 0, 94, 94}, {112, 100, 95, 85, 0, 0, 81, 79}}, /* Temple */
    {{109, 100, 98, 100, 0, 0, 90, 91}, {102, 100, 95, 91, 0, 0, 87, 87}}, /* Girl */
};

static int paper_scene(const sdft_scene *s)
{
    return !strcmp(s->name, "temple") ? 0 : !strcmp(s->name, "figure") ? 1 : -1;
}

static const char *rep_title(const study_options *o, int rep, char *buf, size_t len)
{
    if (rep == STUDY_PROCEDURAL)
        snprintf(buf, len, "procedural");
    else
        snprintf(buf, len, "%s %d³", STUDY_REP_NAMES[rep], o->res);
    return buf;
}

static void table_times(FILE *f, const study_options *o, const study_run *run, const sdft_scene *scene, int cap)
{
    const int ps = paper_scene(scene), paper = ps >= 0 && cap == 1000;
    char t[64];
    fprintf(f, "| %s |", scene->name);
    for (int rep = 0; rep < STUDY_REPS; rep++)
        if (has_rep(o, scene, rep))
            fprintf(f, " %s: cpu ms | rel |%s", rep_title(o, rep, t, sizeof t),
                    paper && (rep == STUDY_PROCEDURAL || rep == STUDY_FULL) ? " paper |" : "");
    fprintf(f, "\n|---|");
    for (int rep = 0; rep < STUDY_REPS; rep++)
        if (has_rep(o, scene, rep))
            fprintf(f, "--:|--:|%s", paper && (rep == STUDY_PROCEDURAL || rep == STUDY_FULL) ? "--:|" : "");
    fputc('\n', f);
    for (int m = 0; m < STUDY_TABLE_ROWS; m++) {
        fprintf(f, "| %s |", STUDY_TABLE_METHODS[m].paper);
        for (int rep = 0; rep < STUDY_REPS; rep++) {
            if (!has_rep(o, scene, rep))
                continue;
            const int i = find(o, run, scene, rep, &STUDY_TABLE_METHODS[m], 1, cap);
            char a[64], b[64];
            if (i < 0)
                fprintf(f, " | |");
            else
                fprintf(f, " %s | %s |", time_cell(a, sizeof a, &sum_of(run, i)->cpu),
                        rel_cell(b, sizeof b, &sum_of(run, i)->rel_enhanced));
            if (paper && (rep == STUDY_PROCEDURAL || rep == STUDY_FULL)) {
                const int v = PAPER_REL[ps][rep == STUDY_FULL][m];
                if (v)
                    fprintf(f, " %d%% |", v);
                else
                    fputs(" – |", f);
            }
        }
        fputc('\n', f);
    }
    fputc('\n', f);
}

/* Cells "a / b / c" over the subject's representations. */
enum {
    CELL_STEPS,
    CELL_STEPS_ENH,
    CELL_GPU,
    CELL_GPU_ENH,
    CELL_FALLBACKS,
    CELL_NONCONV,
    CELL_HITS,
    CELL_AGREE,
    CELL_MISMATCH
};

static void cells(FILE *f, const study_options *o, const study_run *run, const sdft_scene *scene,
                  const int idx[STUDY_REPS], int what)
{
    fputc(' ', f);
    int first = 1;
    for (int rep = 0; rep < STUDY_REPS; rep++) {
        if (!has_rep(o, scene, rep) || (what >= CELL_AGREE && (rep == STUDY_PROCEDURAL || is_mesh(o, scene))))
            continue;
        fputs(first ? "" : " / ", f);
        first = 0;
        if (idx[rep] < 0) {
            fputs("–", f);
            continue;
        }
        const study_summary *s = sum_of(run, idx[rep]);
        const study_config *c = &run->configs[idx[rep]];
        const study_summary *e = c->ref_enhanced >= 0 ? sum_of(run, c->ref_enhanced) : NULL;
        switch (what) {
        case CELL_STEPS:
            fprintf(f, "%.2f + %.2f", s->primary, s->shadow);
            break;
        case CELL_STEPS_ENH:
            fprintf(f, "%.2f", e ? s->steps / e->steps : NAN);
            break;
        case CELL_GPU:
            fprintf(f, "%.1f (×%.2f)", s->gpu, s->gpu / s->steps);
            break;
        case CELL_GPU_ENH:
            fprintf(f, "%.2f", e ? s->gpu / e->gpu : NAN);
            break;
        case CELL_FALLBACKS:
            fprintf(f, "%.2f", s->fallbacks);
            break;
        case CELL_NONCONV:
            fprintf(f, "%.3f", 100.0 * s->nonconverged);
            break;
        case CELL_HITS:
            fprintf(f, "%.2f", 100.0 * s->hits);
            break;
        case CELL_AGREE:
            fprintf(f, "%.2f", 100.0 * c->agree);
            break;
        default:
            fprintf(f, "%.3f", 100.0 * c->mismatch);
            break;
        }
    }
    fputs(" |", f);
}

static void table_counts(FILE *f, const study_options *o, const study_run *run, const sdft_scene *scene, int shadows,
                         int cap)
{
    char reps[128] = "", discrete[128] = "";
    for (int rep = 0; rep < STUDY_REPS; rep++)
        if (has_rep(o, scene, rep)) {
            snprintf(reps + strlen(reps), sizeof reps - strlen(reps), "%s%s", *reps ? " / " : "", STUDY_REP_NAMES[rep]);
            if (rep != STUDY_PROCEDURAL && !is_mesh(o, scene))
                snprintf(discrete + strlen(discrete), sizeof discrete - strlen(discrete), "%s%s",
                         *discrete ? " / " : "", STUDY_REP_NAMES[rep]);
        }
    const int agreement = *discrete != '\0';
    fprintf(f,
            "| %s: %s | evaluations/px, primary + shadow | evaluations / ENH's | GPU cost/px (× evaluations) | "
            "GPU cost / ENH's | fallbacks/px | not converged %% | hit %% |",
            scene->name, reps);
    if (agreement)
        fprintf(f, " depth within 1.5 voxels %% (%s) | hit by one only %% (%s) |", discrete, discrete);
    fprintf(f, "\n|---|---|---|---|---|---|---|---|%s\n", agreement ? "---|---|" : "");
    for (int m = 0; m < STUDY_TABLE_ROWS; m++) {
        int idx[STUDY_REPS];
        for (int rep = 0; rep < STUDY_REPS; rep++)
            idx[rep] = has_rep(o, scene, rep) ? find(o, run, scene, rep, &STUDY_TABLE_METHODS[m], shadows, cap) : -1;
        fprintf(f, "| %s |", STUDY_TABLE_METHODS[m].paper);
        for (int k = CELL_STEPS; k <= (agreement ? CELL_MISMATCH : CELL_HITS); k++)
            cells(f, o, run, scene, idx, k);
        fputc('\n', f);
    }
    fputc('\n', f);
}

/* A table's header: the leading columns, then one per method of the paper's table. */
static void method_header(FILE *f, const char *lead, const char *lead_align)
{
    fputs(lead, f);
    for (int m = 0; m < STUDY_TABLE_ROWS; m++)
        fprintf(f, " %s |", STUDY_TABLE_METHODS[m].paper);
    fprintf(f, "\n%s", lead_align);
    for (int m = 0; m < STUDY_TABLE_ROWS; m++)
        fprintf(f, "--:|");
    fputc('\n', f);
}

/* What a step costs: the processor time per million evaluations, over
 * ENH's, of the table's timed rows (shadows, each cap). */
static void table_step_cost(FILE *f, const study_options *o, const study_run *run)
{
    const sdft_scene *subj[STUDY_MAX_SUBJECTS];
    const int ns = subjects(o, subj);
    fprintf(f, "## What an evaluation costs: processor ms per million evaluations (over ENH's), with the shadow ray\n\n"
               "The median frame's processor time over the frame's evaluations: where a method's time and its "
               "evaluations disagree, this is why.\n\n");
    method_header(f, "| subject | representation | cap |", "|---|---|--:|");
    for (int s = 0; s < ns; s++)
        for (int rep = 0; rep < STUDY_REPS; rep++)
            for (int k = 0; k < o->ncaps && has_rep(o, subj[s], rep); k++) {
                fprintf(f, "| %s | %s | %d |", subj[s]->name, STUDY_REP_NAMES[rep], o->caps[k]);
                const int e = find(o, run, subj[s], rep, &STUDY_TABLE_METHODS[1], 1, o->caps[k]);
                for (int m = 0; m < STUDY_TABLE_ROWS; m++) {
                    const int i = find(o, run, subj[s], rep, &STUDY_TABLE_METHODS[m], 1, o->caps[k]);
                    if (i < 0 || e < 0 || !sum_of(run, i)->cpu.n) {
                        fputs(" |", f);
                        continue;
                    }
                    const double per = sum_of(run, i)->cpu.median / (double)run->configs[i].stats.steps * 1e6,
                                 per_e = sum_of(run, e)->cpu.median / (double)run->configs[e].stats.steps * 1e6;
                    fprintf(f, " %.1f (%.2f) |", per, per / per_e);
                }
                fputc('\n', f);
            }
    fputc('\n', f);
}

/* The paper's times over our counts: what each of its frame-time ratios
 * would ask of one step of the method, against one of ENH's, if its scene
 * took our evaluations (or our GPU cost). A model, not a measurement:
 * ratios near 1 say the paper's time follows our counts; a method far from
 * 1 (while ST, the cheapest step of all, stays near it) says its counts on
 * the paper's scene were not ours. */
static void table_paper_per_step(FILE *f, const study_options *o, const study_run *run)
{
    fprintf(f, "## The paper's times over our counts (shadows, 1000 steps)\n\n"
               "Each cell: the paper's rel (a GPU's frame time over ENH's) divided by our evaluations over ENH's, "
               "and in brackets by our GPU cost over ENH's: the cost of one of the method's steps against one of "
               "ENH's that the paper's time would imply if its scene took our counts. ST's step is the simplest "
               "of all, so its value bounds what a cheaper step can explain; a value well below ST's says the "
               "paper's scene took fewer steps of that method than ours.\n\n");
    method_header(f, "| paper's column | ours |", "|---|---|");
    for (int s = 0; s < o->nscenes; s++) {
        const int ps = paper_scene(o->scenes[s]);
        for (int k = 0; k < 2 && ps >= 0; k++) {
            const int rep = k ? STUDY_FULL : STUDY_PROCEDURAL;
            if (!o->reps[rep])
                continue;
            const int e = find(o, run, o->scenes[s], rep, &STUDY_TABLE_METHODS[1], 1, 1000);
            if (e < 0)
                continue;
            fprintf(f, "| %s, %s | %s, %s |", ps ? "Girl" : "Temple", k ? "discrete 1024³" : "procedural",
                    o->scenes[s]->name, STUDY_REP_NAMES[rep]);
            for (int m = 0; m < STUDY_TABLE_ROWS; m++) {
                const int i = find(o, run, o->scenes[s], rep, &STUDY_TABLE_METHODS[m], 1, 1000);
                if (i < 0 || !PAPER_REL[ps][k][m]) {
                    fputs(" – |", f);
                    continue;
                }
                const double paper = PAPER_REL[ps][k][m] / 100.0;
                fprintf(f, " %.2f (%.2f) |", paper / (sum_of(run, i)->steps / sum_of(run, e)->steps),
                        paper / (sum_of(run, i)->gpu / sum_of(run, e)->gpu));
            }
            fputc('\n', f);
        }
    }
    fputc('\n', f);
}

/* ---- Fig. 2 and Fig. 5's numbers ---------------------------------------- */

/* The share of row c's primary rays not finished after k evaluations. */
static double share_marching(const study_config *c, size_t k)
{
    uint64_t left = c->stats.primary_rays;
    for (size_t j = 0; j <= k && j < c->hist_len; j++)
        left -= c->hist[j];
    return (double)left / (double)c->stats.primary_rays;
}

/* Fig. 2's rows (no shadows, 1000 steps) per method of the paper's table,
 * for one subject and representation; -1 where a row or its counts are missing. */
static int fig2_rows(const study_options *o, const study_run *run, const sdft_scene *scene, int rep,
                     int idx[STUDY_TABLE_ROWS])
{
    int any = 0;
    for (int m = 0; m < STUDY_TABLE_ROWS; m++) {
        idx[m] = find(o, run, scene, rep, &STUDY_TABLE_METHODS[m], 0, 1000);
        if (idx[m] >= 0 && run->configs[idx[m]].hist)
            any = 1;
        else
            idx[m] = -1;
    }
    return any;
}

static void table_fig2(FILE *f, const study_options *o, const study_run *run)
{
    static const size_t ks[] = {10, 20, 30, 50};
    const sdft_scene *subj[STUDY_MAX_SUBJECTS];
    const int ns = subjects(o, subj);
    fprintf(f, "## Fig. 2's numbers: primary rays still marching after k evaluations, %%, no shadows, 1000 steps\n\n");
    method_header(f, "| subject | representation | k |", "|---|---|--:|");
    for (int s = 0; s < ns; s++)
        for (int rep = 0; rep < STUDY_REPS; rep++) {
            int idx[STUDY_TABLE_ROWS];
            if (!has_rep(o, subj[s], rep) || !fig2_rows(o, run, subj[s], rep, idx))
                continue;
            for (size_t j = 0; j < sizeof ks / sizeof ks[0]; j++) {
                fprintf(f, "| %s | %s | %zu |", subj[s]->name, STUDY_REP_NAMES[rep], ks[j]);
                for (int m = 0; m < STUDY_TABLE_ROWS; m++)
                    if (idx[m] < 0)
                        fputs(" |", f);
                    else
                        fprintf(f, " %.2f |", 100.0 * share_marching(&run->configs[idx[m]], ks[j]));
                fputc('\n', f);
            }
        }
    fputc('\n', f);
}

static void table_fig5(FILE *f, const study_options *o, const study_run *run)
{
    const sdft_scene *subj[STUDY_MAX_SUBJECTS];
    const int ns = subjects(o, subj);
    fprintf(f,
            "## Fig. 5's numbers: auto-relaxation's step multiplier (β = %s), no shadows, 1000 steps\n\n"
            "The multiplier of a step is z / r, the step over the distance at the point it leaves (Algorithm 4, "
            "line 14: 2 / (1 − m)); a pixel's is the mean over the steps its primary ray took (a refused trial, "
            "a fallback, takes none: Fig. 1 counts those). Each cell: the median pixel's, over the pixels that "
            "took a step, and in brackets the share of them whose mean exceeds 2 (rays that leave a surface "
            "behind: there the slope m turns positive and 2 / (1 − m) passes 2; Fig. 5's scale stops at 2).\n\n"
            "| subject |",
            STUDY_TABLE_METHODS[STUDY_BEST_ROW].param);
    for (int rep = 0; rep < STUDY_REPS; rep++)
        if (o->reps[rep])
            fprintf(f, " %s |", STUDY_REP_NAMES[rep]);
    fprintf(f, "\n|---|");
    for (int rep = 0; rep < STUDY_REPS; rep++)
        if (o->reps[rep])
            fprintf(f, "--:|");
    fputc('\n', f);
    for (int s = 0; s < ns; s++) {
        fprintf(f, "| %s |", subj[s]->name);
        for (int rep = 0; rep < STUDY_REPS; rep++) {
            if (!o->reps[rep])
                continue;
            const int i = has_rep(o, subj[s], rep)
                              ? find(o, run, subj[s], rep, &STUDY_TABLE_METHODS[STUDY_BEST_ROW], 0, 1000)
                              : -1;
            if (i < 0)
                fputs(" |", f);
            else
                fprintf(f, " %.3f (%.1f%%) |", run->configs[i].multiplier, 100.0 * run->configs[i].multiplier_above_2);
        }
        fputc('\n', f);
    }
    fputc('\n', f);
}

/* ---- Fig. 3 and the transfer of its values ------------------------------ */

/* Fig. 3's methods, in its blocks' order: auto, enhanced, relaxed as the
 * paper's Algorithm 2 and as Keinert's Listing 2. */
enum { SWEEP_COUNT = 4 };
static const sdft_method SWEEP_METHODS[SWEEP_COUNT] = {SDFT_AUTO, SDFT_ENHANCED, SDFT_RELAXED_BV, SDFT_RELAXED};

static int sweep_params(const study_run *run, sdft_method m, char params[][16], int most)
{
    int n = 0;
    for (size_t i = 0; i < run->n; i++) {
        const study_config *c = &run->configs[i];
        if (!(c->groups & STUDY_SWEEP) || c->method != m)
            continue;
        int seen = 0;
        for (int k = 0; k < n; k++)
            seen |= !strcmp(params[k], c->param);
        if (!seen && n < most)
            snprintf(params[n++], 16, "%s", c->param);
    }
    /* by value */
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && strtod(params[j - 1], NULL) > strtod(params[j], NULL); j--) {
            char t[16];
            memcpy(t, params[j], 16), memcpy(params[j], params[j - 1], 16), memcpy(params[j - 1], t, 16);
        }
    return n;
}

static int has_sweep(const study_run *run)
{
    for (size_t i = 0; i < run->n; i++)
        if (run->configs[i].groups & STUDY_SWEEP)
            return 1;
    return 0;
}

/* Whether the sweep on scene, rep ran without the shadow ray too (where it
 * is timed, as the paper shows both). */
static int swept_bare(const sdft_scene *scene, int rep) { return study_sweep_timed(scene, rep); }

static void table_sweep(FILE *f, const study_options *o, const study_run *run)
{
    fprintf(f, "## Fig. 3's numbers: 1000 steps, evaluations / sphere tracing's (GPU cost / sphere's)\n\n"
               "*time*: on the paper's own panel (the temple's discrete version, our full grid), the processor time "
               "over sphere tracing's, pass by pass (median [95%% interval]).\n\n");
    for (int s = 0; s < o->nscenes; s++) {
        const sdft_scene *scene = o->scenes[s];
        const int timed = o->reps[STUDY_FULL] && study_sweep_timed(scene, STUDY_FULL);
        fprintf(f, "| %s | value |", scene->name);
        for (int rep = 0; rep <= STUDY_FULL; rep++)
            if (o->reps[rep])
                fprintf(f, " %s, shadows |", STUDY_REP_NAMES[rep]);
        for (int rep = 0; rep <= STUDY_FULL; rep++)
            if (o->reps[rep] && swept_bare(scene, rep))
                fprintf(f, " %s, none |", STUDY_REP_NAMES[rep]);
        fprintf(f, "%s\n|---|--:|", timed ? " time, full, shadows | time, full, none |" : "");
        for (int rep = 0; rep <= STUDY_FULL; rep++)
            if (o->reps[rep])
                fprintf(f, "--:|%s", swept_bare(scene, rep) ? "--:|" : "");
        fprintf(f, "%s\n", timed ? "--:|--:|" : "");
        for (int k = 0; k < SWEEP_COUNT; k++) {
            char params[128][16];
            const int n = sweep_params(run, SWEEP_METHODS[k], params, 128);
            for (int j = 0; j < n; j++) {
                fprintf(f, "| %s | %s |", sdft_method_name(SWEEP_METHODS[k]), params[j]);
                const study_method m = {SWEEP_METHODS[k], params[j], ""};
                bench_summary times[2] = {{NAN, NAN, NAN, 0}, {NAN, NAN, NAN, 0}};
                for (int shadows = 1; shadows >= 0; shadows--)
                    for (int rep = 0; rep <= STUDY_FULL; rep++) {
                        if (!o->reps[rep] || (!shadows && !swept_bare(scene, rep)))
                            continue;
                        const int i = find(o, run, scene, rep, &m, shadows, 1000);
                        if (i < 0 || run->configs[i].ref_sphere < 0) {
                            fputs(" |", f);
                            continue;
                        }
                        const study_summary *sm = sum_of(run, i), *sp = sum_of(run, run->configs[i].ref_sphere);
                        fprintf(f, " %.2f (%.2f) |", sm->steps / sp->steps, sm->gpu / sp->gpu);
                        if (study_sweep_timed(scene, rep))
                            times[!shadows] = sm->rel_sphere;
                    }
                char a[64], b[64];
                if (timed)
                    fprintf(f, " %s | %s |", rel_cell(a, sizeof a, &times[0]), rel_cell(b, sizeof b, &times[1]));
                fputc('\n', f);
            }
        }
        fputc('\n', f);
    }
}

/* The value of method m's sweep with the fewest evaluations per pixel on
 * scene, rep, with shadows (-1: none), and that count; by GPU cost if gpu. */
static int best_value(const study_options *o, const study_run *run, const sdft_scene *scene, int rep, char params[][16],
                      int n, sdft_method method, int gpu, double *cost)
{
    int best = -1;
    *cost = INFINITY;
    for (int j = 0; j < n; j++) {
        const study_method m = {method, params[j], ""};
        const int i = find(o, run, scene, rep, &m, 1, 1000);
        if (i < 0)
            continue;
        const double c = gpu ? sum_of(run, i)->gpu : sum_of(run, i)->steps;
        if (c < *cost)
            *cost = c, best = j;
    }
    return best;
}

static double cost_at(const study_options *o, const study_run *run, const sdft_scene *scene, int rep, const char *param,
                      sdft_method method, int gpu)
{
    const study_method m = {method, param, ""};
    const int i = find(o, run, scene, rep, &m, 1, 1000);
    return i < 0 ? NAN : gpu ? sum_of(run, i)->gpu : sum_of(run, i)->steps;
}

/* Tuned on one scene, used on the other: for each method and
 * representation, the value with the fewest evaluations on each scene, and
 * what the other scene's best value costs here over this scene's own. */
static void table_transfer(FILE *f, const study_options *o, const study_run *run)
{
    if (o->nscenes < 2)
        return;
    const sdft_scene *a = o->scenes[0], *b = o->scenes[1];
    fprintf(f,
            "## The hyperparameters carried from one scene to the other (shadows, 1000 steps)\n\n"
            "Each method's value tuned on one scene (the fewest evaluations per pixel over Fig. 3's sweep; in "
            "brackets, the fewest by GPU cost) and used on the other: the *loss* is the evaluations (GPU cost) "
            "there over what that scene's own best value takes. *spread* is the sweep's worst over its best on "
            "each scene: how much choosing the value matters at all.\n\n"
            "| method | representation | best on %s | best on %s | %s's value on %s: loss | %s's value on %s: "
            "loss | spread, %s / %s |\n|---|---|--:|--:|--:|--:|--:|\n",
            a->name, b->name, a->name, b->name, b->name, a->name, a->name, b->name);
    for (int k = 0; k < SWEEP_COUNT; k++) {
        char params[128][16];
        const int n = sweep_params(run, SWEEP_METHODS[k], params, 128);
        for (int rep = 0; rep <= STUDY_FULL && n > 0; rep++) {
            if (!o->reps[rep])
                continue;
            double ca, cb, ga, gb;
            const int ba = best_value(o, run, a, rep, params, n, SWEEP_METHODS[k], 0, &ca),
                      bb = best_value(o, run, b, rep, params, n, SWEEP_METHODS[k], 0, &cb),
                      gba = best_value(o, run, a, rep, params, n, SWEEP_METHODS[k], 1, &ga),
                      gbb = best_value(o, run, b, rep, params, n, SWEEP_METHODS[k], 1, &gb);
            if (ba < 0 || bb < 0 || gba < 0 || gbb < 0)
                continue;
            const double loss_b = cost_at(o, run, b, rep, params[ba], SWEEP_METHODS[k], 0) / cb - 1.0,
                         loss_a = cost_at(o, run, a, rep, params[bb], SWEEP_METHODS[k], 0) / ca - 1.0,
                         gloss_b = cost_at(o, run, b, rep, params[gba], SWEEP_METHODS[k], 1) / gb - 1.0,
                         gloss_a = cost_at(o, run, a, rep, params[gbb], SWEEP_METHODS[k], 1) / ga - 1.0;
            double worst_a = 0.0, worst_b = 0.0;
            for (int j = 0; j < n; j++) {
                worst_a = fmax(worst_a, cost_at(o, run, a, rep, params[j], SWEEP_METHODS[k], 0));
                worst_b = fmax(worst_b, cost_at(o, run, b, rep, params[j], SWEEP_METHODS[k], 0));
            }
            fprintf(f, "| %s | %s | %s (%s) | %s (%s) | %+.1f%% (%+.1f%%) | %+.1f%% (%+.1f%%) | %.2f / %.2f |\n",
                    sdft_method_name(SWEEP_METHODS[k]), STUDY_REP_NAMES[rep], params[ba], params[gba], params[bb],
                    params[gbb], 100.0 * loss_b, 100.0 * gloss_b, 100.0 * loss_a, 100.0 * gloss_a, worst_a / ca,
                    worst_b / cb);
        }
    }
    fputc('\n', f);
}

/* ---- the resolution and the step cap ------------------------------------ */

static void table_res(FILE *f, const study_options *o, const study_run *run)
{
    const int res[3] = {o->res / 4, o->res / 2, o->res};
    fprintf(f,
            "## The grids' resolution (shadows, 1000 steps)\n\n"
            "Evaluations per pixel at each resolution, in brackets over ENH's at that resolution; then the share of "
            "both-hit pixels whose depth lies within 1.5 voxels of the procedural image's, %%.\n\n"
            "| scene | representation | method | %d³ | %d³ | %d³ | depth %d³ / %d³ / %d³ |\n"
            "|---|---|---|--:|--:|--:|--:|\n",
            res[0], res[1], res[2], res[0], res[1], res[2]);
    for (int s = 0; s < o->nscenes; s++)
        for (int rep = STUDY_BAND; rep <= STUDY_FULL; rep++)
            for (int m = 0; m < STUDY_TABLE_ROWS && o->reps[rep]; m++) {
                fprintf(f, "| %s | %s | %s |", o->scenes[s]->name, STUDY_REP_NAMES[rep], STUDY_TABLE_METHODS[m].paper);
                char depth[128] = "";
                for (int k = 0; k < 3; k++) {
                    const int i =
                        find_row(o, run, (row_key){o->scenes[s], rep, res[k], &STUDY_TABLE_METHODS[m], 1, 1000, 0, 0});
                    if (i < 0) {
                        fputs(" |", f);
                        continue;
                    }
                    const study_config *c = &run->configs[i];
                    const double e = c->ref_enhanced >= 0 ? sum_of(run, c->ref_enhanced)->steps : NAN;
                    fprintf(f, " %.2f (%.2f) |", sum_of(run, i)->steps, sum_of(run, i)->steps / e);
                    snprintf(depth + strlen(depth), sizeof depth - strlen(depth), "%s%.2f", k ? " / " : "",
                             100.0 * c->agree);
                }
                fprintf(f, " %s |\n", depth);
            }
    fputc('\n', f);
}

/* The caps of the cap sweep and the table's that lie among them, sorted. */
static int cap_list(const study_options *o, int caps[2 * STUDY_MAX_CAPS])
{
    int n = 0;
    const int lo = o->ncap_sweep ? o->cap_sweep[0] : 0;
    int hi = lo;
    for (int k = 0; k < o->ncap_sweep; k++)
        hi = o->cap_sweep[k] > hi ? o->cap_sweep[k] : hi;
    for (int k = 0; k < o->ncap_sweep; k++)
        caps[n++] = o->cap_sweep[k];
    for (int k = 0; k < o->ncaps; k++) {
        int seen = 0;
        for (int j = 0; j < n; j++)
            seen |= caps[j] == o->caps[k];
        if (!seen && o->caps[k] >= lo && o->caps[k] <= hi)
            caps[n++] = o->caps[k];
    }
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && caps[j - 1] > caps[j]; j--) {
            const int t = caps[j];
            caps[j] = caps[j - 1], caps[j - 1] = t;
        }
    return n;
}

static void table_caps(FILE *f, const study_options *o, const study_run *run)
{
    int caps[2 * STUDY_MAX_CAPS];
    const int nc = cap_list(o, caps);
    fprintf(f, "## The step cap (shadows)\n\nEach cell: evaluations per pixel · primary rays not converged, %% · GPU "
               "cost per pixel.\n\n| scene | representation | method |");
    for (int k = 0; k < nc; k++)
        fprintf(f, " %d steps |", caps[k]);
    fprintf(f, "\n|---|---|---|");
    for (int k = 0; k < nc; k++)
        fprintf(f, "--:|");
    fputc('\n', f);
    for (int s = 0; s < o->nscenes; s++)
        for (int rep = 0; rep <= STUDY_FULL; rep++)
            for (int m = 0; m < STUDY_TABLE_ROWS && o->reps[rep]; m++) {
                fprintf(f, "| %s | %s | %s |", o->scenes[s]->name, STUDY_REP_NAMES[rep], STUDY_TABLE_METHODS[m].paper);
                for (int k = 0; k < nc; k++) {
                    const int i = find(o, run, o->scenes[s], rep, &STUDY_TABLE_METHODS[m], 1, caps[k]);
                    if (i < 0)
                        fputs(" |", f);
                    else
                        fprintf(f, " %.2f · %.2f · %.1f |", sum_of(run, i)->steps, 100.0 * sum_of(run, i)->nonconverged,
                                sum_of(run, i)->gpu);
                }
                fputc('\n', f);
            }
    fputc('\n', f);
}

/* ---- Keinert's rows and beyond the paper -------------------------------- */

static void table_keinert(FILE *f, const study_options *o, const study_run *run)
{
    fprintf(f,
            "## Keinert et al. on the city: over-relaxation at his step caps\n\n"
            "Ray casting (no shadows), %dx%d. *×ST* is the processor time over sphere tracing's with the same cap "
            "and criterion, pass by pass; Keinert reports 16.829 ms against 20.409 ms at 80 steps (×0.82).\n\n"
            "| method | cap | criterion | cpu ms | ×ST | evaluations/px | evaluations ×ST | GPU cost/px | not "
            "converged %% | hit %% |\n|---|--:|---|--:|--:|--:|--:|--:|--:|--:|\n",
            o->width, o->height);
    for (size_t i = 0; i < run->n; i++) {
        const study_config *c = &run->configs[i];
        if (!(c->groups & STUDY_KEINERT))
            continue;
        const study_summary *s = sum_of(run, (int)i);
        char label[64], a[64], b[64];
        const double st = c->ref_sphere >= 0 ? sum_of(run, c->ref_sphere)->primary : NAN;
        fprintf(f, "| %s | %d | %s | %s | %s | %.2f | %.2f | %.1f | %.3f | %.2f |\n",
                study_method_label(c, label, sizeof label), c->cap, c->screen_space ? "screen-space" : "ε = 1e-4",
                time_cell(a, sizeof a, &s->cpu), rel_cell(b, sizeof b, &s->rel_sphere), s->primary, s->primary / st,
                s->gpu, 100.0 * s->nonconverged, 100.0 * s->hits);
    }
    fputc('\n', f);
}

static void table_beyond(FILE *f, const study_options *o, const study_run *run)
{
    fprintf(f,
            "## Beyond the paper: cones and the screen-space criterion (auto β = %s, shadows, 1000 steps)\n\n"
            "*×plain* is the processor time over the same representation's plain row, pass by pass. Evaluations "
            "are each ray's own plus the cones' shared ones. Agreement is with the procedural image under the "
            "same options.\n\n"
            "| scene | representation | options | cpu ms | ×plain | evaluations/px (own + cones) | "
            "depth within 1.5 voxels %% | hit by one only %% |\n|---|---|---|--:|--:|--:|--:|--:|\n",
            STUDY_TABLE_METHODS[STUDY_BEST_ROW].param);
    static const char *const options[4] = {"plain", "cones", "screen-space", "cones, screen-space"};
    for (int s = 0; s < o->nscenes; s++)
        for (int rep = 0; rep <= STUDY_FULL; rep++)
            for (int v = 0; v < 4; v++) {
                const int i = find_row(
                    o, run,
                    (row_key){o->scenes[s], rep, 0, &STUDY_TABLE_METHODS[STUDY_BEST_ROW], 1, 1000, v >> 1, v & 1});
                if (i < 0 || !(run->configs[i].groups & STUDY_BEYOND))
                    continue;
                const study_config *c = &run->configs[i];
                const study_summary *r = sum_of(run, i);
                char a[32], b[32], t[64], x[64];
                fprintf(f, "| %s | %s | %s | %s | %s | %.2f + %.2f | %s | %s |\n", c->scene->name, STUDY_REP_NAMES[rep],
                        options[v], time_cell(t, sizeof t, &r->cpu), rel_cell(x, sizeof x, &r->rel_plain), r->steps,
                        r->cone, num(a, sizeof a, "%.2f", 100.0 * c->agree),
                        num(b, sizeof b, "%.3f", 100.0 * c->mismatch));
            }
    fputc('\n', f);
}

/* ---- table.md ----------------------------------------------------------- */

static void caps_text(const study_options *o, char *buf, size_t len)
{
    *buf = '\0';
    for (int k = 0; k < o->ncaps; k++)
        snprintf(buf + strlen(buf), len - strlen(buf), "%s%d", k ? ", " : "", o->caps[k]);
}

static int write_table(const study_options *o, const study_run *run)
{
    out_file of;
    if (out_open(&of, o->out, "table.md"))
        return -1;
    FILE *f = of.f;
    char caps[128];
    caps_text(o, caps, sizeof caps);
    const sdft_scene *subj[STUDY_MAX_SUBJECTS];
    const int ns = subjects(o, subj);
    fprintf(f,
            "# The study's tables\n\n"
            "Written by `bench/study` (run by `bench/study.sh`, `make bench`); every row, with the exact "
            "`sdftrace render` command that reproduces its counts, is in `results.csv`; the machine is in "
            "`machine.txt`. %dx%d pixels, the table's step caps %s; %zu rows, each rendered once for its counts "
            "(the warm-up), and the %zu whose time a table shows %d more times, interleaved in one process, one "
            "grid in memory at a time; %.0f s in all (warm-up %.0f s).\n\n"
            "**Times.** *cpu ms* is a frame's processor time over both threads (trace only): on this shared "
            "machine its wall time measures the others' load more than the work (both are in `results.csv`). "
            "Each is the median of the %d timed passes, with its 95%% bootstrap interval in brackets "
            "(`bench/stats.h`; with 5 passes, their range). Within a pass the rows compared with each other run "
            "back to back in a shuffled order, and a ratio (*rel*: over enhanced sphere tracing's, ω = 0.88, in "
            "the same configuration) is the median of the passes' ratios, with its own interval: an interval that "
            "holds 100%% is a difference this run cannot tell from noise. *paper* is Bán and Valasek's rel "
            "(Section 4), a GPU's frame time: their procedural column beside ours, their discrete 1024³ (a dense "
            "3D texture) beside our full grid. Times are compared with times, counts with counts.\n\n"
            "**Counts** are exact: evaluations of the SDF per pixel, fallbacks, rays that reach the cap. *GPU "
            "cost* is what the frame would cost a GPU from the same per-pixel counts: pixels run in wavefronts of "
            "%dx%d lanes that each step as long as their slowest lane, in the primary loop and then in the shadow "
            "loop, so a tile costs its largest primary count plus its largest shadow count; the mean over tiles, "
            "per pixel (in brackets, over the evaluations: how much divergence adds).\n\n",
            o->width, o->height, caps, run->n, run->timed_rows, o->repeats, run->total_s, run->warmup_s, o->repeats,
            STUDY_TILE_W, STUDY_TILE_H);
    if (o->parts & STUDY_TABLE) {
        for (int k = 0; k < o->ncaps; k++) {
            fprintf(f, "## Frame time, with the hard shadow ray, %d steps\n\n", o->caps[k]);
            for (int s = 0; s < ns; s++)
                table_times(f, o, run, subj[s], o->caps[k]);
        }
        for (int shadows = 1; shadows >= 0; shadows--)
            for (int k = 0; k < o->ncaps && (shadows || o->caps[k] == 1000); k++) {
                fprintf(f, "## Counts, %s, %d steps\n\n", shadows ? "with the hard shadow ray" : "no shadows",
                        o->caps[k]);
                for (int s = 0; s < ns; s++)
                    table_counts(f, o, run, subj[s], shadows, o->caps[k]);
            }
        table_step_cost(f, o, run);
        table_paper_per_step(f, o, run);
        table_fig2(f, o, run);
        table_fig5(f, o, run);
    }
    if (has_sweep(run)) {
        table_sweep(f, o, run);
        table_transfer(f, o, run);
    }
    if (o->parts & STUDY_RES)
        table_res(f, o, run);
    if ((o->parts & STUDY_CAPS) && o->ncap_sweep)
        table_caps(f, o, run);
    if (o->parts & STUDY_KEINERT)
        table_keinert(f, o, run);
    if (o->parts & STUDY_BEYOND)
        table_beyond(f, o, run);
    fprintf(f,
            "1-minute load average as the measuring began: %.2f; as it ended: %.2f; between %.2f and %.2f as each "
            "grid's rows began.\n",
            run->load_first, run->load_last, run->load_lo, run->load_hi);
    return out_close(&of);
}

/* ---- the figures' data -------------------------------------------------- */

/* The smallest multiple of 4 that at least `share` of the counts do not exceed. */
static unsigned long scale_of(const uint64_t *hist, double share)
{
    uint64_t total = 0, seen = 0;
    for (size_t k = 0; k < STUDY_HIST; k++)
        total += hist[k];
    size_t k = 0;
    for (; k < STUDY_HIST; k++) {
        seen += hist[k];
        if ((double)seen >= share * (double)total)
            break;
    }
    unsigned long top = (unsigned long)k < 4 ? 4 : (unsigned long)k;
    return (top + 3) / 4 * 4;
}

static int write_fig1(const study_options *o, const study_run *run)
{
    out_file f;
    if (out_open(&f, o->out, "fig1.txt"))
        return -1;
    fprintf(f.f, "# scene steps_max fallbacks_max width height: the shared scales of Fig. 1 (the 99th percentile of "
                 "the scene's maps, rounded up to a multiple of 4)\n");
    for (int k = 0; k < run->nfig1; k++)
        fprintf(f.f, "%s %lu %lu %d %d\n", run->fig1[k]->scene->name, scale_of(run->fig1[k]->steps_hist, 0.99),
                scale_of(run->fig1[k]->fallback_hist, 0.99), o->width, o->height);
    return out_close(&f);
}

/* Fig. 2: per subject and representation, the share of primary rays still
 * marching after k evaluations, one column per method, up to the k where
 * every method's last ray has finished. */
static int write_fig2(const study_options *o, const study_run *run)
{
    const sdft_scene *subj[STUDY_MAX_SUBJECTS];
    const int ns = subjects(o, subj);
    for (int s = 0; s < ns; s++)
        for (int rep = 0; rep < STUDY_REPS; rep++) {
            int idx[STUDY_TABLE_ROWS];
            if (!has_rep(o, subj[s], rep) || !fig2_rows(o, run, subj[s], rep, idx))
                continue;
            size_t len = 0;
            for (int m = 0; m < STUDY_TABLE_ROWS; m++)
                if (idx[m] >= 0)
                    len = run->configs[idx[m]].hist_len;
            char name[256];
            snprintf(name, sizeof name, "fig2-%s-%s.dat", subj[s]->name, STUDY_REP_NAMES[rep]);
            out_file f;
            if (out_open(&f, o->out, name))
                return -1;
            fprintf(f.f, "# %s, %s, no shadows, 1000 steps: share of primary rays not finished after k evaluations\nk",
                    subj[s]->name, STUDY_REP_NAMES[rep]);
            for (int m = 0; m < STUDY_TABLE_ROWS; m++)
                fprintf(f.f, " \"%s\"", STUDY_TABLE_METHODS[m].paper);
            fputc('\n', f.f);
            for (size_t k = 0; k < len; k++) {
                int live = 0;
                fprintf(f.f, "%zu", k);
                for (int m = 0; m < STUDY_TABLE_ROWS; m++) {
                    if (idx[m] < 0) {
                        fputs(" NaN", f.f);
                        continue;
                    }
                    const double share = share_marching(&run->configs[idx[m]], k);
                    live |= share > 0;
                    fprintf(f.f, " %.8f", share);
                }
                fputc('\n', f.f);
                if (!live)
                    break;
            }
            if (out_close(&f))
                return -1;
        }
    return 0;
}

/* Fig. 3: per scene and representation, one gnuplot block per method
 * (SWEEP_METHODS) and shadow setting: value, evaluations /
 * sphere's, GPU cost / sphere's, and the processor time / sphere's with
 * its interval (NaN where not timed). */
static int write_fig3(const study_options *o, const study_run *run)
{
    for (int s = 0; s < o->nscenes; s++)
        for (int rep = 0; rep <= STUDY_FULL; rep++) {
            if (!o->reps[rep])
                continue;
            char name[128];
            snprintf(name, sizeof name, "fig3-%s-%s.dat", o->scenes[s]->name, STUDY_REP_NAMES[rep]);
            out_file f;
            if (out_open(&f, o->out, name))
                return -1;
            fprintf(
                f.f,
                "# %s, %s, 1000 steps; blocks: auto, enhanced, relaxed-bv, relaxed, each with shadows then without: "
                "value evaluations/sphere gpu/sphere time/sphere time_lo time_hi\n",
                o->scenes[s]->name, STUDY_REP_NAMES[rep]);
            for (int k = 0; k < SWEEP_COUNT; k++) {
                char params[128][16];
                const int n = sweep_params(run, SWEEP_METHODS[k], params, 128);
                for (int shadows = 1; shadows >= 0; shadows--) {
                    for (int j = 0; j < n; j++) {
                        const study_method m = {SWEEP_METHODS[k], params[j], ""};
                        const int i = find(o, run, o->scenes[s], rep, &m, shadows, 1000);
                        if (i < 0 || run->configs[i].ref_sphere < 0 || (!shadows && !swept_bare(o->scenes[s], rep)))
                            continue;
                        const study_summary *sm = sum_of(run, i), *sp = sum_of(run, run->configs[i].ref_sphere);
                        const bench_summary *t = &sm->rel_sphere;
                        fprintf(f.f, "%s %.5f %.5f", params[j], sm->steps / sp->steps, sm->gpu / sp->gpu);
                        if (t->n && study_sweep_timed(o->scenes[s], rep))
                            fprintf(f.f, " %.5f %.5f %.5f\n", t->median, t->lo, t->hi);
                        else
                            fprintf(f.f, " NaN NaN NaN\n");
                    }
                    fprintf(f.f, "\n\n"); /* one gnuplot data block per method and shadow setting */
                }
            }
            if (out_close(&f))
                return -1;
        }
    return 0;
}

/* Fig. 5: the panels drawn (each a float32 plane, fig5-SUBJECT-REP.f32). */
static int write_fig5(const study_options *o, const study_run *run)
{
    out_file f;
    if (out_open(&f, o->out, "fig5.txt"))
        return -1;
    fprintf(f.f, "# subject representation width height median_multiplier share_above_2: Fig. 5's maps, "
                 "fig5-SUBJECT-REP.f32\n");
    for (size_t i = 0; i < run->n; i++) {
        const study_config *c = &run->configs[i];
        if (study_fig_row(c) && study_fig5_method(c))
            fprintf(f.f, "%s %s %d %d %.4f %.4f\n", c->scene->name, STUDY_REP_NAMES[c->rep], o->width, o->height,
                    c->multiplier, c->multiplier_above_2);
    }
    return out_close(&f);
}

/* The cap sweep for its figure: per scene and representation (a block
 * each), per method (a sub-block), cap, evaluations/px, not converged %, GPU cost/px. */
static int write_caps(const study_options *o, const study_run *run)
{
    int caps[2 * STUDY_MAX_CAPS];
    const int nc = cap_list(o, caps);
    out_file f;
    if (out_open(&f, o->out, "caps.dat"))
        return -1;
    fprintf(f.f, "# blocks: scene x representation (procedural, band, full) x method (the table's order); "
                 "columns: cap evaluations/px not_converged_%% gpu_cost/px\n");
    for (int s = 0; s < o->nscenes; s++)
        for (int rep = 0; rep <= STUDY_FULL; rep++)
            for (int m = 0; m < STUDY_TABLE_ROWS; m++) {
                fprintf(f.f, "# %s %s %s\n", o->scenes[s]->name, STUDY_REP_NAMES[rep], STUDY_TABLE_METHODS[m].paper);
                for (int k = 0; k < nc && o->reps[rep]; k++) {
                    const int i = find(o, run, o->scenes[s], rep, &STUDY_TABLE_METHODS[m], 1, caps[k]);
                    if (i >= 0)
                        fprintf(f.f, "%d %.4f %.4f %.3f\n", caps[k], sum_of(run, i)->steps,
                                100.0 * sum_of(run, i)->nonconverged, sum_of(run, i)->gpu);
                }
                fprintf(f.f, "\n\n");
            }
    return out_close(&f);
}

int study_write_results(const study_options *o, study_run *run)
{
    if (study_summarize_all(o, run)) {
        fprintf(stderr, "study: out of memory\n");
        return -1;
    }
    if (write_csv(o, run) || write_table(o, run))
        return -1;
    if ((o->parts & STUDY_TABLE) && (write_fig1(o, run) || write_fig2(o, run) || write_fig5(o, run)))
        return -1;
    if (has_sweep(run) && write_fig3(o, run))
        return -1;
    if ((o->parts & STUDY_CAPS) && o->ncap_sweep && write_caps(o, run))
        return -1;
    return 0;
}
