/* sdftrace — the leaf directory of a float grid: a dense table, one entry
 * per 8^3 block of the active index box, giving where that block's leaf
 * keeps its 512 values in the NanoVDB buffer (0: no leaf there).
 *
 * WHY. Near the surface nearly every sample lands in a leaf, and a ray's
 * consecutive samples are voxels apart, so the read accessor's cached leaf
 * is usually the wrong one: a lookup walks root -> upper -> lower -> leaf,
 * three dependent loads before the values, each a likely cache miss in a
 * 1024^3 grid. The directory makes it one load, whose address follows from
 * the sample point alone (8 MiB for a 1024^3 box: it stays in cache). It
 * only locates leaves; the values are the grid's own, so the field is
 * unchanged. Blocks without a leaf, and grids of other types, go through
 * the accessor as before.
 *
 * TRUST. A leaf's origin is read from the leaf and then looked up through
 * a read accessor over the checked tree (grid_load.c): only a leaf the tree
 * itself reaches from that origin is entered, so a corrupt leaf array can
 * at worst leave blocks to the accessor, never misplace one. */
#include <stdlib.h>

#include "grid_internal.h"

enum { MAX_BLOCKS = 1 << 24 }; /* 64 MiB of entries: a 2048^3 box */

sdft_error sdft_grid_leaves_build(sdft_grid *g)
{
    grid_leaves *d = &g->leaves;
    *d = (grid_leaves){0};
    if (g->type != PNANOVDB_GRID_TYPE_FLOAT || g->size / 4u > UINT32_MAX)
        return SDFT_OK; /* the accessor serves these */
    size_t blocks = 1;
    for (int k = 0; k < 3; k++) {
        d->b0[k] = g->ilo[k] >> 3; /* arithmetic shift: floor division by 8 */
        d->n[k] = (g->ihi[k] >> 3) - d->b0[k] + 1;
        blocks *= (size_t)d->n[k];
    }
    if (blocks > MAX_BLOCKS)
        return SDFT_OK;
    uint32_t *word = calloc(blocks, sizeof *word);
    if (!word)
        return SDFT_ENOMEM;

    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(g->buf, g->grid);
    const uint64_t count = pnanovdb_tree_get_node_count_leaf(g->buf, tree);
    const uint64_t first = PNANOVDB_GRID_SIZE + pnanovdb_tree_get_node_offset_leaf(g->buf, tree);
    const uint64_t stride = PNANOVDB_GRID_TYPE_GET(PNANOVDB_GRID_TYPE_FLOAT, leaf_size);
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(&acc, g->root);
    for (uint64_t i = 0; i < count; i++) {
        const uint64_t at = first + i * stride;
        if (at > g->size || g->size - at < stride)
            break; /* the array runs past the grid: leave the rest to the accessor */
        pnanovdb_leaf_handle_t hint = {pnanovdb_address_offset64((pnanovdb_address_t){0}, at)};
        pnanovdb_coord_t o = pnanovdb_leaf_get_bbox_min(g->buf, hint);
        uint32_t level;
        pnanovdb_readaccessor_get_value_address_and_level(PNANOVDB_GRID_TYPE_FLOAT, g->buf, &acc, &o, &level);
        if (level != 0 || acc.leaf.address.byte_offset != at)
            continue;
        const uint32_t bx = (uint32_t)((o.x >> 3) - d->b0[0]), by = (uint32_t)((o.y >> 3) - d->b0[1]),
                       bz = (uint32_t)((o.z >> 3) - d->b0[2]);
        if (bx >= (uint32_t)d->n[0] || by >= (uint32_t)d->n[1] || bz >= (uint32_t)d->n[2])
            continue;
        pnanovdb_address_t values = pnanovdb_leaf_get_table_address(PNANOVDB_GRID_TYPE_FLOAT, g->buf, hint, 0);
        word[((size_t)bz * (size_t)d->n[1] + by) * (size_t)d->n[0] + bx] = (uint32_t)(values.byte_offset / 4u);
    }
    d->word = word;
    return SDFT_OK;
}

void sdft_grid_leaves_free(sdft_grid *g)
{
    free(g->leaves.word);
    g->leaves.word = NULL;
}
