/* sdftrace common — a progress bar on stderr, for the tools: `sdftrace bake`
 * draws the bake's progress callback with it, mesh2sdf its stages. One
 * line, redrawn in place, each whole percent once; drawn only when asked
 * and stderr is a terminal, so logs and pipes stay clean. Internal header
 * (C and C++). */
#ifndef SDFTRACE_COMMON_PROGRESS_BAR_H
#define SDFTRACE_COMMON_PROGRESS_BAR_H

#ifdef __cplusplus
extern "C" {
#endif

typedef struct progress_bar {
    int draw;          /* asked for, and stderr is a terminal */
    int shown;         /* the percent on screen, -1 for none (its drawer's) */
    int target;        /* the most asked for, -1 for none; atomic */
    int busy;          /* a thread is drawing; atomic */
    const char *label; /* the label of the latest rise; atomic */
} progress_bar;

/* A bar that draws when `enabled` and stderr is a terminal. */
void progress_bar_init(progress_bar *bar, int enabled);

/* Shows `percent` (clamped to 0..100) with a label of up to 24 characters,
 * if it is more than the bar was asked for so far. Safe from any thread:
 * one thread draws at a time, so the frames reach the terminal in order and
 * the last one is the most asked for. */
void progress_bar_show(progress_bar *bar, const char *label, int percent);

/* Clears the bar's line, if anything was drawn. */
void progress_bar_clear(progress_bar *bar);

#ifdef __cplusplus
}
#endif
#endif
