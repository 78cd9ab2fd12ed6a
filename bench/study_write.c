/* study — writing what bench/study.c measured: results.csv (every row, with
 * its command line), table.md (the paper's layout and the other groups),
 * and the data of the three figures for bench/fig*.gp. Every file goes
 * through sdftrace's atomic writer (src/common/atomic_file.h): a temporary
 * file beside it, flushed and renamed into place, with the umask's mode. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "atomic_file.h"
#include "study.h"

/* ---- small helpers ------------------------------------------------------ */

int study_rep_parse(const char *name)
{
    for (int r = 0; r < STUDY_REPS; r++)
        if (!strcmp(name, STUDY_REP_NAMES[r]))
            return r;
    return -1;
}

double study_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

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
        free(run->configs[i].hist);
    }
    free(run->configs);
    for (int k = 0; k < run->nsources; k++)
        sdft_grid_free(run->sources[k].grid);
    for (size_t k = 0; k < run->ndepths; k++)
        free(run->depths[k]);
    for (int k = 0; k < run->nfig1; k++)
        free(run->fig1[k]);
}

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

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* ---- what each row reports --------------------------------------------- */

typedef struct row_summary {
    double ms, ms_min, ms_max;
    double rel_enhanced, rel_sphere, rel_plain; /* NAN: no partner */
    double steps, primary, shadow, cone, fallbacks, primary_fallbacks, nonconverged, hits;
} row_summary;

/* The median over passes of row i's time over row ref's in the same pass. */
static double rel_to(const study_options *o, const study_run *run, size_t i, int ref)
{
    if (ref < 0)
        return NAN;
    double r[100];
    for (int p = 0; p < o->repeats; p++)
        r[p] = run->configs[i].ms[p] / run->configs[ref].ms[p];
    return median(r, o->repeats);
}

static row_summary summarize(const study_options *o, const study_run *run, size_t i)
{
    const study_config *c = &run->configs[i];
    double t[100];
    memcpy(t, c->ms, (size_t)o->repeats * sizeof *t);
    row_summary s = {.ms = median(t, o->repeats), .ms_min = t[0], .ms_max = t[o->repeats - 1]};
    s.rel_enhanced = rel_to(o, run, i, c->ref_enhanced);
    s.rel_sphere = rel_to(o, run, i, c->ref_sphere);
    s.rel_plain = rel_to(o, run, i, c->ref_plain);
    const double px = (double)c->stats.primary_rays;
    s.steps = (double)c->stats.steps / px;
    s.primary = (double)c->stats.primary_steps / px;
    s.shadow = (double)(c->stats.steps - c->stats.primary_steps) / px;
    s.cone = (double)c->stats.cone_steps / px;
    s.fallbacks = (double)c->stats.fallbacks / px;
    s.primary_fallbacks = (double)c->stats.primary_fallbacks / px;
    s.nonconverged = (double)c->stats.nonconverged / px;
    s.hits = (double)c->stats.hits / px;
    return s;
}

/* "0.94" or "" for a missing ratio. */
static const char *num(char *buf, size_t len, const char *fmt, double v)
{
    if (isnan(v))
        snprintf(buf, len, "%s", "");
    else
        snprintf(buf, len, fmt, v);
    return buf;
}

static const char *method_label(const study_config *c, char *buf, size_t len)
{
    if (*c->param)
        snprintf(buf, len, "%s %s", sdft_method_name(c->method), c->param);
    else
        snprintf(buf, len, "%s", sdft_method_name(c->method));
    return buf;
}

/* ---- results.csv -------------------------------------------------------- */

static int write_csv(const study_options *o, const study_run *run)
{
    out_file f;
    if (out_open(&f, o->out, "results.csv"))
        return -1;
    fprintf(f.f, "groups,scene,representation,method,param,shadows,max_steps,screen_space,cones,width,height,repeats,"
                 "ms_median,ms_min,ms_max,rel_enhanced,rel_sphere,rel_plain,mean_steps,mean_primary_steps,"
                 "mean_shadow_steps,mean_cone_steps,mean_fallbacks,mean_primary_fallbacks,nonconverged,hit_fraction,"
                 "agree_1p5vox,hit_mismatch,steps,command\n");
    static const char *const group_names[] = {"table", "sweep", "keinert", "beyond"};
    for (size_t i = 0; i < run->n; i++) {
        const study_config *c = &run->configs[i];
        const row_summary s = summarize(o, run, i);
        char groups[64] = "", a[32], b[32], d[32], e[32], g[32], cmd[8192];
        for (unsigned k = 0; k < 4; k++)
            if (c->groups & (1u << k))
                snprintf(groups + strlen(groups), sizeof groups - strlen(groups), "%s%s", *groups ? " " : "",
                         group_names[k]);
        study_command(o, c, cmd, sizeof cmd);
        /* mean_steps as `sdftrace render --json` prints it (%.4f), to compare digit by digit */
        fprintf(f.f,
                "%s,%s,%s,%s,%s,%d,%d,%d,%d,%d,%d,%d,%.3f,%.3f,%.3f,%s,%s,%s,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.6f,%.6f,"
                "%s,%s,%llu,\"%s\"\n",
                groups, c->scene->name, STUDY_REP_NAMES[c->rep], sdft_method_name(c->method), c->param, c->shadows,
                c->cap, c->screen_space, c->cones, o->width, o->height, o->repeats, s.ms, s.ms_min, s.ms_max,
                num(a, sizeof a, "%.4f", s.rel_enhanced), num(b, sizeof b, "%.4f", s.rel_sphere),
                num(d, sizeof d, "%.4f", s.rel_plain), s.steps, s.primary, s.shadow, s.cone, s.fallbacks,
                s.primary_fallbacks, s.nonconverged, s.hits, num(e, sizeof e, "%.6f", c->agree),
                num(g, sizeof g, "%.6f", c->mismatch), (unsigned long long)c->stats.steps, cmd);
    }
    return out_close(&f);
}

/* ---- table.md ----------------------------------------------------------- */

/* The paper's rel column (Bán–Valasek, Section 4), in STUDY_TABLE_METHODS'
 * order; its procedural and its discrete 1024^3 (a dense 3D texture) columns. */
static const int PAPER_REL[2][2][STUDY_TABLE_ROWS] = {
    {{125, 100, 106, 98, 94, 94}, {112, 100, 95, 85, 81, 79}}, /* Temple */
    {{109, 100, 98, 100, 90, 91}, {102, 100, 95, 91, 87, 87}}, /* Girl */
};

static int paper_scene(const sdft_scene *s)
{
    return !strcmp(s->name, "temple") ? 0 : !strcmp(s->name, "figure") ? 1 : -1;
}

static int find(const study_run *run, const sdft_scene *scene, int rep, const study_method *m, int shadows, int cap,
                int ss, int cones)
{
    for (size_t i = 0; i < run->n; i++) {
        const study_config *c = &run->configs[i];
        if (c->scene == scene && c->rep == rep && c->method == m->method && !strcmp(c->param, m->param) &&
            c->shadows == shadows && c->cap == cap && c->screen_space == ss && c->cones == cones)
            return (int)i;
    }
    return -1;
}

static void table_times(FILE *f, const study_options *o, const study_run *run, const sdft_scene *scene, int shadows,
                        int cap)
{
    const int ps = paper_scene(scene), paper = ps >= 0 && shadows && cap == 1000;
    fprintf(f, "| %s |", scene->name);
    for (int rep = 0; rep < STUDY_REPS; rep++)
        if (o->reps[rep])
            fprintf(f, " %s ms | min–max | rel |%s", STUDY_REP_NAMES[rep],
                    paper && rep != STUDY_BAND ? " paper |" : "");
    fprintf(f, "\n|---|");
    for (int rep = 0; rep < STUDY_REPS; rep++)
        if (o->reps[rep])
            fprintf(f, "--:|:-:|--:|%s", paper && rep != STUDY_BAND ? "--:|" : "");
    fputc('\n', f);
    for (int m = 0; m < STUDY_TABLE_ROWS; m++) {
        fprintf(f, "| %s |", STUDY_TABLE_METHODS[m].paper);
        for (int rep = 0; rep < STUDY_REPS; rep++) {
            if (!o->reps[rep])
                continue;
            const int i = find(run, scene, rep, &STUDY_TABLE_METHODS[m], shadows, cap, 0, 0);
            if (i < 0) {
                fprintf(f, " | | |%s", paper && rep != STUDY_BAND ? " |" : "");
                continue;
            }
            const row_summary s = summarize(o, run, (size_t)i);
            fprintf(f, " %.1f | %.0f–%.0f | %.0f%% |", s.ms, s.ms_min, s.ms_max, 100.0 * s.rel_enhanced);
            if (paper && rep != STUDY_BAND)
                fprintf(f, " %d%% |", PAPER_REL[ps][rep == STUDY_FULL][m]);
        }
        fputc('\n', f);
    }
    fputc('\n', f);
}

/* Cells "a / b / c" over the measured representations. */
static void triple(FILE *f, const study_options *o, const int idx[STUDY_REPS], const study_run *run, int what)
{
    fputc(' ', f);
    int first = 1;
    for (int rep = 0; rep < STUDY_REPS; rep++) {
        if (!o->reps[rep] || (what >= 5 && rep == STUDY_PROCEDURAL))
            continue;
        fputs(first ? "" : " / ", f);
        first = 0;
        if (idx[rep] < 0) {
            fputs("–", f);
            continue;
        }
        const row_summary s = summarize(o, run, (size_t)idx[rep]);
        const study_config *c = &run->configs[idx[rep]];
        switch (what) {
        case 0:
            fprintf(f, "%.2f + %.2f", s.primary, s.shadow);
            break;
        case 1:
            fprintf(f, "%.2f", s.fallbacks);
            break;
        case 2:
            fprintf(f, "%.3f", 100.0 * s.nonconverged);
            break;
        case 3:
            fprintf(f, "%.2f", 100.0 * s.hits);
            break;
        case 4:
            fprintf(f, "%.2f", s.steps / summarize(o, run, (size_t)c->ref_enhanced).steps);
            break;
        case 5:
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
    char reps[64] = "", discrete[64] = "";
    for (int rep = 0; rep < STUDY_REPS; rep++)
        if (o->reps[rep]) {
            snprintf(reps + strlen(reps), sizeof reps - strlen(reps), "%s%s", *reps ? " / " : "", STUDY_REP_NAMES[rep]);
            if (rep != STUDY_PROCEDURAL)
                snprintf(discrete + strlen(discrete), sizeof discrete - strlen(discrete), "%s%s",
                         *discrete ? " / " : "", STUDY_REP_NAMES[rep]);
        }
    fprintf(f,
            "| %s: %s | evaluations/px, primary + shadow | evaluations / ENH's | fallbacks/px | not converged %% | "
            "hit %% | depth within 1.5 voxels %% (%s) | hit by one only %% (%s) |\n|---|---|---|---|---|---|---|---|\n",
            scene->name, reps, discrete, discrete);
    for (int m = 0; m < STUDY_TABLE_ROWS; m++) {
        int idx[STUDY_REPS];
        for (int rep = 0; rep < STUDY_REPS; rep++)
            idx[rep] = o->reps[rep] ? find(run, scene, rep, &STUDY_TABLE_METHODS[m], shadows, cap, 0, 0) : -1;
        fprintf(f, "| %s |", STUDY_TABLE_METHODS[m].paper);
        static const int columns[] = {0, 4, 1, 2, 3, 5, 6}; /* the header's order */
        for (int k = 0; k < 7; k++)
            triple(f, o, idx, run, columns[k]);
        fputc('\n', f);
    }
    fputc('\n', f);
}

/* The share of row c's primary rays not finished after k evaluations. */
static double share_marching(const study_config *c, size_t k)
{
    uint64_t left = c->stats.primary_rays;
    for (size_t j = 0; j <= k && j < c->hist_len; j++)
        left -= c->hist[j];
    return (double)left / (double)c->stats.primary_rays;
}

/* Fig. 2's rows (no shadows, 1000 steps) per method of the paper's table,
 * for one scene and representation; -1 where a row or its counts are missing. */
static int fig2_rows(const study_run *run, const sdft_scene *scene, int rep, int idx[STUDY_TABLE_ROWS])
{
    int any = 0;
    for (int m = 0; m < STUDY_TABLE_ROWS; m++) {
        idx[m] = find(run, scene, rep, &STUDY_TABLE_METHODS[m], 0, 1000, 0, 0);
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
    fprintf(f, "## Fig. 2's numbers: primary rays still marching after k evaluations, %%, no shadows, 1000 steps\n\n"
               "| scene | representation | k |");
    for (int m = 0; m < STUDY_TABLE_ROWS; m++)
        fprintf(f, " %s |", STUDY_TABLE_METHODS[m].paper);
    fprintf(f, "\n|---|---|--:|");
    for (int m = 0; m < STUDY_TABLE_ROWS; m++)
        fprintf(f, "--:|");
    fputc('\n', f);
    for (int s = 0; s < o->nscenes; s++)
        for (int rep = 0; rep < STUDY_REPS; rep++) {
            int idx[STUDY_TABLE_ROWS];
            if (!fig2_rows(run, o->scenes[s], rep, idx))
                continue;
            for (size_t j = 0; j < sizeof ks / sizeof ks[0]; j++) {
                fprintf(f, "| %s | %s | %zu |", o->scenes[s]->name, STUDY_REP_NAMES[rep], ks[j]);
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

static void table_keinert(FILE *f, const study_options *o, const study_run *run)
{
    fprintf(f,
            "## Keinert et al. on the city: over-relaxation at his step caps\n\n"
            "Ray casting (no shadows), %dx%d. *×ST* is the time over sphere tracing's with the same cap and "
            "criterion; Keinert reports 16.829 ms against 20.409 ms at 80 steps (×0.82).\n\n"
            "| method | cap | criterion | ms | min–max | ×ST | evaluations/px | not converged %% | hit %% |\n"
            "|---|--:|---|--:|:-:|--:|--:|--:|--:|\n",
            o->width, o->height);
    for (size_t i = 0; i < run->n; i++) {
        const study_config *c = &run->configs[i];
        if (!(c->groups & STUDY_KEINERT))
            continue;
        const row_summary s = summarize(o, run, i);
        char label[64];
        fprintf(f, "| %s | %d | %s | %.1f | %.0f–%.0f | %.2f | %.2f | %.3f | %.2f |\n",
                method_label(c, label, sizeof label), c->cap, c->screen_space ? "screen-space" : "ε = 1e-4", s.ms,
                s.ms_min, s.ms_max, s.rel_sphere, s.primary, 100.0 * s.nonconverged, 100.0 * s.hits);
    }
    fputc('\n', f);
}

static void table_beyond(FILE *f, const study_options *o, const study_run *run)
{
    fprintf(f,
            "## Beyond the paper: cones and the screen-space criterion (auto β = %s, shadows, 1000 steps)\n\n"
            "*×plain* is the time over the same representation's plain row in the same pass. Evaluations are "
            "each ray's own plus the cones' shared ones. Agreement is with the procedural image under the same "
            "options.\n\n"
            "| scene | representation | options | ms | min–max | ×plain | evaluations/px (own + cones) | "
            "depth within 1.5 voxels %% | hit by one only %% |\n|---|---|---|--:|:-:|--:|--:|--:|--:|\n",
            STUDY_TABLE_METHODS[STUDY_BEST_ROW].param);
    static const char *const options[4] = {"plain", "cones", "screen-space", "cones, screen-space"};
    for (int s = 0; s < o->nscenes; s++)
        for (int rep = 0; rep < STUDY_REPS; rep++)
            for (int v = 0; v < 4; v++) {
                const int i =
                    find(run, o->scenes[s], rep, &STUDY_TABLE_METHODS[STUDY_BEST_ROW], 1, 1000, v >> 1, v & 1);
                if (i < 0 || !(run->configs[i].groups & STUDY_BEYOND))
                    continue;
                const study_config *c = &run->configs[i];
                const row_summary r = summarize(o, run, (size_t)i);
                char a[32], b[32];
                fprintf(f, "| %s | %s | %s | %.1f | %.0f–%.0f | %.2f | %.2f + %.2f | %s | %s |\n", c->scene->name,
                        STUDY_REP_NAMES[rep], options[v], r.ms, r.ms_min, r.ms_max, r.rel_plain, r.steps, r.cone,
                        num(a, sizeof a, "%.2f", 100.0 * c->agree), num(b, sizeof b, "%.3f", 100.0 * c->mismatch));
            }
    fputc('\n', f);
}

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

static const sdft_method SWEEP_METHODS[3] = {SDFT_AUTO, SDFT_ENHANCED, SDFT_RELAXED_BV};

static void table_sweep(FILE *f, const study_options *o, const study_run *run)
{
    const sdft_scene *temple = sdft_scene_find("temple");
    fprintf(f, "## Fig. 3's numbers: temple, 1000 steps, time / sphere tracing's (evaluations / sphere's)\n\n"
               "| method | value |");
    for (int rep = 0; rep < STUDY_REPS; rep++)
        if (o->reps[rep])
            fprintf(f, " %s, shadows | %s, none |", STUDY_REP_NAMES[rep], STUDY_REP_NAMES[rep]);
    fprintf(f, "\n|---|--:|");
    for (int rep = 0; rep < STUDY_REPS; rep++)
        if (o->reps[rep])
            fprintf(f, "--:|--:|");
    fputc('\n', f);
    for (int k = 0; k < 3; k++) {
        char params[128][16];
        const int n = sweep_params(run, SWEEP_METHODS[k], params, 128);
        for (int j = 0; j < n; j++) {
            fprintf(f, "| %s | %s |", sdft_method_name(SWEEP_METHODS[k]), params[j]);
            const study_method m = {SWEEP_METHODS[k], params[j], ""};
            for (int rep = 0; rep < STUDY_REPS; rep++)
                for (int shadows = 1; shadows >= 0 && o->reps[rep]; shadows--) {
                    const int i = find(run, temple, rep, &m, shadows, 1000, 0, 0);
                    if (i < 0) {
                        fputs(" |", f);
                        continue;
                    }
                    const row_summary s = summarize(o, run, (size_t)i);
                    const row_summary sp = summarize(o, run, (size_t)run->configs[i].ref_sphere);
                    fprintf(f, " %.2f (%.2f) |", s.rel_sphere, s.steps / sp.steps);
                }
            fputc('\n', f);
        }
    }
    fputc('\n', f);
}

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
    fprintf(f,
            "# The study's tables\n\n"
            "Written by `bench/study` (run by `bench/study.sh`, `make bench`); every row, with the exact "
            "`sdftrace render` command that reproduces its counts, is in `results.csv`; the machine is in "
            "`machine.txt`. %dx%d pixels, step caps %s, %d timed frames per row after one warm-up, rows "
            "interleaved in one process; %zu rows, %.0f s in all (warm-up %.0f s).\n\n"
            "*ms* is the median frame time (trace only), *min–max* the range of the repeats, *rel* the time "
            "over enhanced sphere tracing's (ω = 0.88) in the same configuration: the median over passes of "
            "the two rows' ratio in each pass. *paper* is Bán and Valasek's rel (Section 4): their "
            "procedural column beside ours, their discrete 1024³ (a dense 3D texture) beside our full grid.\n\n",
            o->width, o->height, caps, o->repeats, run->n, run->total_s, run->warmup_s);
    if (o->parts & STUDY_TABLE)
        for (int shadows = 1; shadows >= 0; shadows--)
            for (int k = 0; k < o->ncaps; k++) {
                fprintf(f, "## Frame time, %s, %d steps\n\n", shadows ? "with the hard shadow ray" : "no shadows",
                        o->caps[k]);
                for (int s = 0; s < o->nscenes; s++)
                    table_times(f, o, run, o->scenes[s], shadows, o->caps[k]);
                fprintf(f, "### Counts, %s, %d steps\n\n", shadows ? "with the hard shadow ray" : "no shadows",
                        o->caps[k]);
                for (int s = 0; s < o->nscenes; s++)
                    table_counts(f, o, run, o->scenes[s], shadows, o->caps[k]);
            }
    if (o->parts & STUDY_TABLE)
        table_fig2(f, o, run);
    if (o->parts & STUDY_KEINERT)
        table_keinert(f, o, run);
    if (o->parts & STUDY_BEYOND)
        table_beyond(f, o, run);
    for (size_t i = 0; i < run->n; i++)
        if (run->configs[i].groups & STUDY_SWEEP) {
            table_sweep(f, o, run);
            break;
        }
    fprintf(f, "1-minute load average as each pass began (the warm-up first):");
    for (int p = 0; p <= o->repeats; p++)
        fprintf(f, " %.2f", run->load[p]);
    fprintf(f, ".\n");
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

/* Fig. 2: per scene and representation, the share of primary rays still
 * marching after k evaluations, one column per method. */
static int write_fig2(const study_options *o, const study_run *run)
{
    for (int s = 0; s < o->nscenes; s++)
        for (int rep = 0; rep < STUDY_REPS; rep++) {
            int idx[STUDY_TABLE_ROWS];
            if (!fig2_rows(run, o->scenes[s], rep, idx))
                continue;
            size_t len = 0;
            for (int m = 0; m < STUDY_TABLE_ROWS; m++)
                if (idx[m] >= 0)
                    len = run->configs[idx[m]].hist_len;
            char name[256];
            snprintf(name, sizeof name, "fig2-%s-%s.dat", o->scenes[s]->name, STUDY_REP_NAMES[rep]);
            out_file f;
            if (out_open(&f, o->out, name))
                return -1;
            fprintf(f.f,
                    "# %s, %s, no shadows, 1000 steps: share of primary rays not finished after k evaluations\n# k",
                    o->scenes[s]->name, STUDY_REP_NAMES[rep]);
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

/* Fig. 3: temple's sweep, per representation: method (0 auto, 1 enhanced,
 * 2 relaxed-bv), value, shadows, time / sphere's, evaluations / sphere's. */
static int write_fig3(const study_options *o, const study_run *run)
{
    const sdft_scene *temple = sdft_scene_find("temple");
    for (int rep = 0; rep < STUDY_REPS; rep++) {
        if (!o->reps[rep])
            continue;
        char name[64];
        snprintf(name, sizeof name, "fig3-%s.dat", STUDY_REP_NAMES[rep]);
        out_file f;
        if (out_open(&f, o->out, name))
            return -1;
        fprintf(f.f,
                "# temple, %s, 1000 steps: method (0 auto, 1 enhanced, 2 relaxed-bv) value shadows "
                "time/sphere evaluations/sphere\n",
                STUDY_REP_NAMES[rep]);
        for (int k = 0; k < 3; k++) {
            char params[128][16];
            const int n = sweep_params(run, SWEEP_METHODS[k], params, 128);
            for (int shadows = 1; shadows >= 0; shadows--) {
                for (int j = 0; j < n; j++) {
                    const study_method m = {SWEEP_METHODS[k], params[j], ""};
                    const int i = find(run, temple, rep, &m, shadows, 1000, 0, 0);
                    if (i < 0 || run->configs[i].ref_sphere < 0)
                        continue;
                    const row_summary s = summarize(o, run, (size_t)i);
                    const row_summary sp = summarize(o, run, (size_t)run->configs[i].ref_sphere);
                    fprintf(f.f, "%d %s %d %.5f %.5f\n", k, params[j], shadows, s.rel_sphere, s.steps / sp.steps);
                }
                fprintf(f.f, "\n\n"); /* one gnuplot data block per method and shadow setting */
            }
        }
        if (out_close(&f))
            return -1;
    }
    return 0;
}

int study_write_results(const study_options *o, study_run *run)
{
    if (write_csv(o, run) || write_table(o, run))
        return -1;
    if ((o->parts & STUDY_TABLE) && (write_fig1(o, run) || write_fig2(o, run)))
        return -1;
    int sweep = 0;
    for (size_t i = 0; i < run->n; i++)
        sweep |= (run->configs[i].groups & STUDY_SWEEP) != 0;
    if (sweep && write_fig3(o, run))
        return -1;
    return 0;
}
