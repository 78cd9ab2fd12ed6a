/* sdftrace common — the progress bar (see progress_bar.h). */
#define _POSIX_C_SOURCE 200809L
#include "progress_bar.h"

#include <stdio.h>
#include <unistd.h>

enum { BAR_WIDTH = 40 };

void progress_bar_init(progress_bar *bar, int enabled)
{
    bar->draw = enabled && isatty(STDERR_FILENO);
    bar->shown = bar->target = -1;
    bar->busy = 0;
    bar->label = "";
}

static void draw_frame(int percent, const char *label)
{
    char line[BAR_WIDTH + 1];
    for (int i = 0; i < BAR_WIDTH; i++)
        line[i] = i < percent * BAR_WIDTH / 100 ? '#' : '.';
    line[BAR_WIDTH] = '\0';
    fprintf(stderr, "\r[%s] %3d%% %-24.24s", line, percent, label ? label : "");
    fflush(stderr);
}

void progress_bar_show(progress_bar *bar, const char *label, int percent)
{
    if (!bar->draw)
        return;
    percent = percent < 0 ? 0 : percent > 100 ? 100 : percent;
    int target = __atomic_load_n(&bar->target, __ATOMIC_RELAXED);
    do
        if (percent <= target)
            return;
    while (!__atomic_compare_exchange_n(&bar->target, &target, percent, 1, __ATOMIC_RELEASE, __ATOMIC_RELAXED));
    __atomic_store_n(&bar->label, label, __ATOMIC_RELEASE);
    /* One drawer at a time (two threads that each drew their own percent
     * could reach the terminal in either order). A thread that finds the
     * bar busy leaves its rise to the drawer, which looks again after
     * letting go, so the most asked for is always drawn last. */
    while (__atomic_exchange_n(&bar->busy, 1, __ATOMIC_ACQUIRE) == 0) {
        const int want = __atomic_load_n(&bar->target, __ATOMIC_ACQUIRE);
        if (want > bar->shown) {
            draw_frame(want, __atomic_load_n(&bar->label, __ATOMIC_ACQUIRE));
            bar->shown = want;
        }
        __atomic_store_n(&bar->busy, 0, __ATOMIC_RELEASE);
        if (__atomic_load_n(&bar->target, __ATOMIC_ACQUIRE) <= want)
            return;
    }
}

void progress_bar_clear(progress_bar *bar)
{
    if (bar->draw && bar->shown >= 0) {
        fprintf(stderr, "\r%*s\r", BAR_WIDTH + 32, "");
        fflush(stderr);
    }
    bar->shown = -1;
    __atomic_store_n(&bar->target, -1, __ATOMIC_RELAXED);
}
