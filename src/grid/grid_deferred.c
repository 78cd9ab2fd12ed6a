/* sdftrace — deferred leaves: a grid laid out in full whose leaves are
 * filled the first time anything reads them (sdft_grid_options.fill).
 *
 * WHY. A renderer that opens a big .vdb wants its first image, not the whole
 * grid: OpenVDB's vdb_render reads a leaf's values from the file only when a
 * ray reaches it, and a frame reaches a few percent of a 4096^3 level set's
 * leaves. A NanoVDB grid has no such hook, so the loader lays the grid out
 * (every node above the leaves, which is small) and this file fills a leaf
 * on its first read, through the loader's callback. Untouched leaves are
 * never written, so their pages are never faulted in either.
 *
 * WHERE IT IS ASKED. Every read of a leaf goes one of two ways: through the
 * leaf directory (grid_leaves.c), whose entry for a deferred leaf stays 0
 * ("not known here") until the leaf is filled and published; or through the
 * read accessor (read_value, grid_cell.h), which calls grid_leaf_ready for
 * every leaf it reaches. So the directory's hot path is unchanged, and the
 * first read of a leaf always takes the accessor's path and fills it. The
 * far bound (grid_bound.c) reads leaves at load time and counts a deferred
 * leaf as occupied instead.
 *
 * THREADS. One state byte per leaf: EMPTY -> FILLING by one compare-and-swap
 * (that thread fills it, publishes it in the directory, then stores READY
 * with release order); a thread that finds FILLING waits for READY. Readers
 * of READY (acquire) or of a published directory entry see the whole leaf:
 * the entry is stored with release order after the leaf is written, and a
 * reader's loads of the leaf depend on the entry's value. */
#include <sched.h>
#include <stdlib.h>

#include "grid_cell.h"

sdft_error grid_deferred_init(sdft_grid *g)
{
    grid_deferred *d = &g->deferred;
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(g->buf, g->grid);
    d->first = PNANOVDB_GRID_SIZE + pnanovdb_tree_get_node_offset_leaf(g->buf, tree);
    d->stride = PNANOVDB_GRID_TYPE_GET(g->type, leaf_size);
    d->count = pnanovdb_tree_get_node_count_leaf(g->buf, tree);
    if (d->count && (d->first > g->size || (g->size - d->first) / d->stride < d->count))
        return SDFT_EFORMAT;
    d->state = calloc(d->count ? d->count : 1, 1);
    return d->state ? SDFT_OK : SDFT_ENOMEM;
}

void grid_deferred_free(sdft_grid *g)
{
    grid_deferred *d = &g->deferred;
    if (d->release_user)
        d->release_user(d->user);
    free(d->state);
    *d = (grid_deferred){0};
}

void grid_leaf_fill(const sdft_grid *g, uint64_t at, pnanovdb_coord_t ijk)
{
    grid_deferred *d = (grid_deferred *)&g->deferred; /* its counts and states are atomic */
    const uint64_t i = deferred_leaf_index(d, at);    /* grid_leaf_ready checked it is one */
    uint8_t *state = &d->state[i];
    uint8_t empty = LEAF_EMPTY;
    if (!__atomic_compare_exchange_n(state, &empty, LEAF_FILLING, 0, __ATOMIC_ACQUIRE, __ATOMIC_ACQUIRE)) {
        while (__atomic_load_n(state, __ATOMIC_ACQUIRE) != LEAF_READY)
            sched_yield(); /* another thread is filling it: a leaf's worth of reading */
        return;
    }
    if (d->fill(d->user, i, (char *)g->words + at))
        __atomic_add_fetch(&d->failed, 1, __ATOMIC_RELAXED);
    if (g->leaves.top) { /* the leaf's block from the voxel read, not from what fill wrote */
        const int32_t b[3] = {ijk.x >> 3, ijk.y >> 3, ijk.z >> 3};
        grid_leaves_publish(g, b, (uint32_t)((at + PNANOVDB_GRID_TYPE_GET(g->type, leaf_off_table)) / 4u));
    }
    __atomic_add_fetch(&d->filled, 1, __ATOMIC_RELAXED);
    __atomic_store_n(state, LEAF_READY, __ATOMIC_RELEASE);
}

static void fill_visited(void *ctx, const int32_t b[3], uint64_t at, uint32_t word)
{
    (void)word;
    grid_leaf_ready(ctx, at, (pnanovdb_coord_t){b[0] * 8, b[1] * 8, b[2] * 8});
}

void grid_fill_all(const sdft_grid *g)
{
    const grid_deferred *d = &g->deferred;
    if (d->state && __atomic_load_n(&d->filled, __ATOMIC_RELAXED) < d->count) /* else every leaf is there */
        grid_each_leaf(g, fill_visited, (void *)(uintptr_t)g);
}

uint64_t grid_deferred_fill_now(sdft_grid *g)
{
    grid_fill_all(g); /* no directory yet: nothing to publish */
    const uint64_t failed = g->deferred.failed;
    free(g->deferred.state);
    g->deferred.state = NULL; /* every read now goes as in a grid loaded whole */
    return failed;
}

int sdft_grid_defers(sdft_defer how, int level_set, float background, const int32_t lo[3], const int32_t hi[3])
{
    if (how != SDFT_DEFER_WHERE_EXACT)
        return how == SDFT_DEFER_ALWAYS;
    /* Where the far bound's cells are narrower than a leaf (boxes up to
     * about 1024^3), it reads the active states of a leaf's sub-blocks, and
     * deferring would loosen it (an unread leaf counts as occupied): such a
     * grid is filled at load. Wider cells look at a leaf as one block,
     * read or not. */
    return !(level_set && background > 0.0f && grid_far_cell(lo, hi) < 8);
}

void sdft_grid_leaf_counts(const sdft_grid *g, uint64_t *leaves, uint64_t *filled, uint64_t *failed)
{
    const grid_deferred *d = &g->deferred;
    const uint64_t n =
        d->state ? d->count : pnanovdb_tree_get_node_count_leaf(g->buf, pnanovdb_grid_get_tree(g->buf, g->grid));
    if (leaves)
        *leaves = n;
    if (filled)
        *filled = d->state ? __atomic_load_n(&d->filled, __ATOMIC_RELAXED) : n;
    if (failed)
        *failed = d->state ? __atomic_load_n(&d->failed, __ATOMIC_RELAXED) : 0;
}
