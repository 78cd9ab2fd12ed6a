/* study — the parts of bench/study.c that bench/study_write.c shares: the
 * options, the configurations and what was measured of them. */
#ifndef SDFT_STUDY_H
#define SDFT_STUDY_H

#include <stddef.h>
#include <stdint.h>

#include "sdftrace/grid.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"

enum { STUDY_PROCEDURAL = 0, STUDY_BAND, STUDY_FULL, STUDY_REPS };
extern const char *const STUDY_REP_NAMES[STUDY_REPS]; /* "procedural", "band", "full" */

/* The groups of rows; one configuration may serve several. */
enum { STUDY_TABLE = 1, STUDY_SWEEP = 2, STUDY_KEINERT = 4, STUDY_BEYOND = 8 };

enum {
    STUDY_MAX_SCENES = 8,
    STUDY_MAX_CAPS = 8,
    STUDY_MAX_SOURCES = 32,
    STUDY_MAX_DEPTHS = 256,
    STUDY_TABLE_ROWS = 6,
    STUDY_HIST = 1 << 16, /* Fig. 1's scale histograms: counts beyond are lumped */
};

typedef struct study_method {
    sdft_method method;
    const char *param; /* omega or beta as on the command line; "" for sphere */
    const char *paper; /* the paper's row label */
} study_method;
extern const study_method STUDY_TABLE_METHODS[STUDY_TABLE_ROWS];
enum { STUDY_BEST_ROW = 4 }; /* auto, beta 0.3: the variant of the rows beyond the paper */

typedef struct study_options {
    const char *out, *grids, *cli, *row_exr;
    int res, width, height, repeats, sweep;
    int caps[STUDY_MAX_CAPS], ncaps;
    const sdft_scene *scenes[STUDY_MAX_SCENES];
    int nscenes;
    int reps[STUDY_REPS]; /* 1: measured */
    unsigned parts;       /* STUDY_TABLE | ... */
    int quiet, dry_run;
} study_options;

typedef struct study_config {
    const sdft_scene *scene;
    int rep;
    sdft_method method;
    char param[16]; /* "" for sphere */
    int shadows, cap, screen_space, cones;
    unsigned groups;
    int source; /* index into study_run.sources */
    /* partners (indices, -1: none) and the comparison set (its first row) */
    int ref_enhanced, ref_sphere, ref_plain, ref_procedural, set;
    /* measured */
    sdft_render_stats stats; /* the warm-up frame's; every repeat's counts equal them */
    double *ms;              /* each repeat's frame time */
    double agree, mismatch;  /* against the procedural image: both-hit pixels within 1.5 voxels; hit by one only */
    uint64_t *hist;          /* Fig. 2 rows: pixels by primary-ray steps */
    size_t hist_len;
} study_config;

typedef struct study_source {
    const sdft_scene *scene;
    int rep;
    sdft_field field;
    sdft_grid *grid; /* discrete representations: owned */
    char path[4096];
    float voxel;
} study_source;

/* Fig. 1: a scene's shared colour scales come from all its maps. */
typedef struct study_fig1 {
    const sdft_scene *scene;
    uint64_t steps_hist[STUDY_HIST], fallback_hist[STUDY_HIST];
} study_fig1;

typedef struct study_run {
    study_config *configs;
    size_t n, cap;
    study_source sources[STUDY_MAX_SOURCES];
    int nsources;
    float *depths[STUDY_MAX_DEPTHS]; /* procedural depth maps kept for the agreement */
    size_t depth_of[STUDY_MAX_DEPTHS], ndepths;
    study_fig1 *fig1[STUDY_MAX_SCENES];
    int nfig1;
    double load[101]; /* the 1-minute load average as each pass began (0: the warm-up) */
    double started, warmup_s, total_s;
} study_run;

/* The render parameters of configuration c, exactly as `sdftrace render`
 * makes them from study_command's line. */
sdft_render_params study_params(const study_options *o, const study_config *c);
/* The `sdftrace render` command line that reproduces c's counts. */
void study_command(const study_options *o, const study_config *c, char *buf, size_t len);
/* 1 for the rows Figs. 1 and 2 show; for the three methods of Fig. 1. */
int study_fig_row(const study_config *c);
int study_fig1_method(const study_config *c);

int study_rep_parse(const char *name); /* -1 if unknown */
study_fig1 *study_fig1_of(study_run *run, const sdft_scene *scene);
double study_now(void); /* seconds, monotonic */

/* Writes bytes to path through the atomic writer (src/common/atomic_file.h:
 * a temporary file renamed into place, the umask's mode); 0, or -1 with one
 * line on stderr. */
int study_write_file(const char *path, const void *data, size_t size);
/* results.csv, table.md, fig1.txt, fig2.dat, fig3.dat under o->out. */
int study_write_results(const study_options *o, study_run *run);
void study_run_free(study_run *run);

#endif
