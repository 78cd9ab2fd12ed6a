/* study — writing what bench/study.c measured (bench/study_write.c). */
#ifndef SDFT_STUDY_WRITE_H
#define SDFT_STUDY_WRITE_H

#include <stddef.h>

#include "study.h"

/* Writes bytes to path through the atomic writer (src/common/atomic_file.h:
 * a temporary file renamed into place, the umask's mode); 0, or -1 with one
 * line on stderr. */
int study_write_file(const char *path, const void *data, size_t size);

/* results.csv, table.md and the figures' data (fig1.txt, fig2-*.dat,
 * fig3-*.dat, fig5.txt, caps.dat) under o->out; summarizes the run first
 * (study_summarize_all). 0, or -1 with one line on stderr. */
int study_write_results(const study_options *o, study_run *run);

#endif
