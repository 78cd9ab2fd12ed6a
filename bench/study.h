/* study — what a row of the study is, for the program that measures the
 * rows (bench/study.c) and the one file that writes them out
 * (bench/study_write.c): the options, the configurations, what was
 * measured of them and what a row reports (bench/study_rows.c). Neither of
 * those two files reaches into the other but through study_write.h. */
#ifndef SDFT_STUDY_H
#define SDFT_STUDY_H

#include <stddef.h>
#include <stdint.h>

#include "sdftrace/grid.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "stats.h"

/* Representations: the scene's own function, its two bakes, and a mesh's
 * level sets made by two tools (a subject that is a mesh has only those). */
enum { STUDY_PROCEDURAL = 0, STUDY_BAND, STUDY_FULL, STUDY_VDB_TOOL, STUDY_MESH2SDF, STUDY_REPS };
extern const char *const STUDY_REP_NAMES[STUDY_REPS]; /* "procedural", "band", "full", "vdb_tool", "mesh2sdf" */

/* The groups of rows; one configuration may serve several. */
enum {
    STUDY_TABLE = 1,   /* the paper's table (Section 4), Figs. 1, 2 and 5 */
    STUDY_SWEEP = 2,   /* Fig. 3: each method's hyperparameter, and its transfer between scenes */
    STUDY_KEINERT = 4, /* Keinert et al.'s city at his step caps */
    STUDY_BEYOND = 8,  /* cones and the screen-space criterion */
    STUDY_RES = 16,    /* the grids at a quarter, a half and the whole resolution */
    STUDY_CAPS = 32,   /* the step caps of a GPU renderer's budget */
    STUDY_GROUPS = 6,
};
extern const char *const STUDY_GROUP_NAMES[STUDY_GROUPS]; /* "table", "sweep", ... by bit */

enum {
    STUDY_MAX_SCENES = 8,
    STUDY_MAX_MESHES = 4,
    STUDY_MAX_SUBJECTS = STUDY_MAX_SCENES + STUDY_MAX_MESHES,
    STUDY_MAX_CAPS = 8,
    STUDY_MAX_SOURCES = 64,
    STUDY_MAX_DEPTHS = 512,
    STUDY_MAX_REPEATS = 100,
    STUDY_TABLE_ROWS = 8,
    STUDY_HIST = 1 << 16, /* Fig. 1's scale histograms: counts beyond are lumped */
    STUDY_TILE_W = 8,     /* a GPU wavefront's pixels: 8 x 4 = 32 lanes */
    STUDY_TILE_H = 4,
};

typedef struct study_method {
    sdft_method method;
    const char *param; /* omega or beta as on the command line; "" for sphere */
    const char *paper; /* the paper's row label */
} study_method;
extern const study_method STUDY_TABLE_METHODS[STUDY_TABLE_ROWS];
enum { STUDY_BEST_ROW = 6 }; /* auto, beta 0.3: the variant of the rows beyond the paper, and of Fig. 5 */

typedef struct study_options {
    const char *out, *grids, *cli, *row_exr;
    int res, width, height, repeats, sweep;
    int caps[STUDY_MAX_CAPS], ncaps;            /* the table's */
    int cap_sweep[STUDY_MAX_CAPS], ncap_sweep;  /* the step-cap sweep's, beside the table's */
    const sdft_scene *scenes[STUDY_MAX_SCENES]; /* procedural, from the registry */
    int nscenes;
    sdft_scene meshes[STUDY_MAX_MESHES]; /* a mesh's level sets: the name alone (each grid is seen from
                                          * its own front view, study_config.camera) */
    int nmeshes;
    int reps[STUDY_REPS]; /* 1: measured */
    unsigned parts;       /* STUDY_TABLE | ... */
    int quiet, dry_run;
} study_options;

typedef struct study_config {
    const sdft_scene *scene; /* a procedural scene, or one of study_options.meshes */
    int rep, res;            /* res: the grid's resolution; 0 for the procedural scene */
    sdft_method method;
    char param[16]; /* "" for sphere */
    int shadows, cap, screen_space, cones;
    unsigned groups;
    int timed;          /* 1: rendered in every timed pass; 0: its counts only (the warm-up frame) */
    int source;         /* index into study_run.sources */
    sdft_camera camera; /* the view: the scene's, or a mesh's grid's front view (set with the sources) */
    sdft_vec3 light;
    /* partners (indices, -1: none) and the comparison set (its first row) */
    int ref_enhanced, ref_sphere, ref_plain, ref_procedural, set;
    /* measured */
    sdft_render_stats stats;   /* the warm-up frame's; every repeat's counts equal them */
    double *ms, *cpu_ms;       /* each timed pass's frame: wall and processor time */
    double gpu_cost;           /* evaluations per pixel a wavefront pays (study_wavefront_cost) */
    double agree, mismatch;    /* against the procedural image: both-hit pixels within 1.5 voxels; hit by one only */
    double multiplier;         /* Fig. 5 rows: the median pixel's mean step multiplier (pixels that took a step) */
    double multiplier_above_2; /* and the share of those pixels whose mean exceeds 2; else both NAN */
    uint64_t *hist;            /* Fig. 2 rows: pixels by primary-ray steps */
    size_t hist_len;
} study_config;

typedef struct study_source {
    const sdft_scene *scene;
    int rep, res;
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

/* What a row reports: its times' medians with their intervals (n 0 for
 * a row that was not timed), the ratios to its partners timed in the same
 * pass, and its exact counts per pixel. */
typedef struct study_summary {
    bench_summary cpu, ms;                             /* milliseconds per frame */
    bench_summary rel_enhanced, rel_sphere, rel_plain; /* processor time over the partner's, pass by pass */
    double steps, primary, shadow, cone, fallbacks, primary_fallbacks, nonconverged, hits, gpu;
} study_summary;

typedef struct study_run {
    study_config *configs;
    size_t n, cap;
    study_summary *summaries; /* one per configuration, once measured (study_summarize_all) */
    study_source sources[STUDY_MAX_SOURCES];
    int nsources;
    float *depths[STUDY_MAX_DEPTHS]; /* procedural depth maps kept for the agreement */
    size_t depth_of[STUDY_MAX_DEPTHS], ndepths;
    study_fig1 *fig1[STUDY_MAX_SCENES];
    int nfig1;
    double load_first, load_last, load_lo, load_hi; /* the 1-minute load average as the measuring began and
                                                     * ended, and its least and most as each source began */
    double started, warmup_s, total_s;
    size_t timed_rows;
} study_run;

/* ---- study_rows.c ------------------------------------------------------- */

int study_rep_parse(const char *name); /* -1 if unknown */
int study_rep_of_mesh(int rep);        /* 1 for vdb_tool and mesh2sdf */
/* The grid file of a discrete representation: DIR/NAME-REP-RES.nvdb. */
const char *study_source_path(const study_options *o, const sdft_scene *scene, int rep, int res, char *buf, size_t len);
/* The front view `sdftrace render --grid` gives a grid without --scene:
 * the camera framing its bounds, the light above and in front of it. */
void study_front_view(sdft_aabb bounds, int width, int height, sdft_camera *camera, sdft_vec3 *light);
/* The render parameters of configuration c, exactly as `sdftrace render`
 * makes them from study_command's line. */
sdft_render_params study_params(const study_options *o, const study_config *c);
/* The `sdftrace render` command line that reproduces c's counts. */
void study_command(const study_options *o, const study_config *c, char *buf, size_t len);
/* 1 for the rows Figs. 1, 2 and 5 show (no shadows, the paper's cap); for
 * the three methods of Fig. 1; for Fig. 5's (auto, beta 0.3). */
int study_fig_row(const study_config *c);
int study_fig1_method(const study_config *c);
int study_fig5_method(const study_config *c);
/* 1 for the sweep that is timed: the paper's Fig. 3 panel, the temple's
 * discrete version (our full grid); the others are counted. */
int study_sweep_timed(const sdft_scene *scene, int rep);
/* "auto 0.3", "sphere". */
const char *study_method_label(const study_config *c, char *buf, size_t len);

/* Fills run->summaries from what was measured; -1 when out of memory. */
int study_summarize_all(const study_options *o, study_run *run);

study_fig1 *study_fig1_of(study_run *run, const sdft_scene *scene);
double study_now(void);     /* seconds, monotonic */
double study_cpu_now(void); /* the process's processor seconds, all threads (clock(), as sdftrace's cpu_ms) */
void study_run_free(study_run *run);

/* ---- study_cost.c ------------------------------------------------------- */

/* What a GPU pays for a frame, from its per-pixel counts: the pixels run in
 * wavefronts of tile_w x tile_h lanes, and a wavefront takes as long as its
 * slowest lane, in each of the loops it runs one after the other (the
 * primary rays, then the shadow rays). The mean over the image's tiles (at
 * its right and bottom edges, the pixels there are) of the tile's largest
 * primary count plus its largest shadow count (total - primary), per
 * pixel: evaluations a pixel costs on such a machine. total may be NULL
 * (no shadow loop). */
double study_wavefront_cost(const uint32_t *primary, const uint32_t *total, int width, int height, int tile_w,
                            int tile_h);

/* ---- study_multiplier.c ------------------------------------------------ */

/* Fig. 5: traces the primary rays of a width x height frame from camera
 * again, one by one, with sdft_trace and params tp (eps constant: tp's
 * pixel_radius 0), logging the field's evaluations, and gives each pixel's
 * mean step multiplier z / r over the steps its march took (the accepted
 * trials) in map (NAN for a ray that took none) and, unless NULL, the
 * number of those steps in steps.
 * With expect_steps (the frame's primary_steps plane), every ray must take
 * exactly that many evaluations. 0, or -1 with one line in msg. */
int study_multiplier_map(const sdft_field *f, const sdft_trace_params *tp, const sdft_camera *camera, int width,
                         int height, const uint32_t *expect_steps, float *map, uint32_t *steps, char *msg,
                         size_t msg_len);

#endif
