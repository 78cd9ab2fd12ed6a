/* sdftrace — which grid of a file or buffer a loader takes: the one rule
 * that `.nvdb` files and buffers (grid_load.c) and `.vdb` files
 * (src/vdb/vdb_load.cpp) share, so that a name means the same in both
 * (the rule is stated in include/sdftrace/grid.h). Internal header, C and
 * C++; header-only (static), so that each library keeps its own copy. */
#ifndef SDFTRACE_GRID_CHOOSE_H
#define SDFTRACE_GRID_CHOOSE_H

#include <stddef.h>
#include <string.h>

#include "fail.h"

/* What a loader knows of each grid before reading it. */
typedef struct grid_candidate {
    const char *name;
    const char *type; /* the value type's name, for messages */
    int scalar;       /* float, double or a quantized float */
    int level_set;
} grid_candidate;

/* By name, else the first scalar level set, else the first scalar grid;
 * `what` names the file or buffer in messages. SDFT_OK with *pick, or
 * SDFT_ENOTFOUND / SDFT_ENOTSCALAR with one line in msg. */
static inline sdft_error grid_choose(const grid_candidate *e, size_t n, const char *name, const char *what,
                                     size_t *pick, char *msg, size_t msg_len)
{
    if (n == 0)
        return fail_with(msg, msg_len, SDFT_ENOTFOUND, "%s holds no grids", what);
    if (name) {
        for (size_t i = 0; i < n; i++)
            if (strcmp(e[i].name, name) == 0) {
                if (!e[i].scalar)
                    return fail_with(msg, msg_len, SDFT_ENOTSCALAR,
                                     "grid '%s' in %s holds %s values, not scalar distances", name, what, e[i].type);
                *pick = i;
                return SDFT_OK;
            }
        return fail_with(msg, msg_len, SDFT_ENOTFOUND, "%s has no grid named '%s'", what, name);
    }
    for (int pass = 0; pass < 2; pass++)
        for (size_t i = 0; i < n; i++)
            if (e[i].scalar && (pass == 1 || e[i].level_set)) {
                *pick = i;
                return SDFT_OK;
            }
    return fail_with(msg, msg_len, SDFT_ENOTSCALAR, "%s holds no scalar grid (first grid '%s' is %s)", what, e[0].name,
                     e[0].type);
}

#endif
