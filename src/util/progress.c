/* sdftrace util — the progress bar (see progress.h). */
#define _POSIX_C_SOURCE 200809L
#include "progress.h"

#include <stdio.h>
#include <unistd.h>

enum { BAR_WIDTH = 40 };

void sdft_progress_bar_init(sdft_progress_bar *bar, int enabled)
{
    bar->draw = enabled && isatty(STDERR_FILENO);
    bar->shown = -1;
}

void sdft_progress_bar_show(sdft_progress_bar *bar, const char *label, int percent)
{
    if (!bar->draw)
        return;
    percent = percent < 0 ? 0 : percent > 100 ? 100 : percent;
    int shown = __atomic_load_n(&bar->shown, __ATOMIC_RELAXED);
    while (percent > shown)
        if (__atomic_compare_exchange_n(&bar->shown, &shown, percent, 1, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
            char line[BAR_WIDTH + 1];
            for (int i = 0; i < BAR_WIDTH; i++)
                line[i] = i < percent * BAR_WIDTH / 100 ? '#' : '.';
            line[BAR_WIDTH] = '\0';
            fprintf(stderr, "\r[%s] %3d%% %-24.24s", line, percent, label ? label : "");
            fflush(stderr);
            return;
        }
}

void sdft_progress_bar_clear(sdft_progress_bar *bar)
{
    if (bar->draw && __atomic_load_n(&bar->shown, __ATOMIC_RELAXED) >= 0) {
        fprintf(stderr, "\r%*s\r", BAR_WIDTH + 32, "");
        fflush(stderr);
        __atomic_store_n(&bar->shown, -1, __ATOMIC_RELAXED);
    }
}
