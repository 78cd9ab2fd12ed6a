/* sdftrace — the leaf directory of a grid: where the leaf of each 8^3
 * block keeps its values in the NanoVDB buffer, found in two loads whose
 * addresses follow from the sample point alone.
 *
 * WHY. Near the surface nearly every sample lands in a leaf, and a ray's
 * consecutive samples are voxels apart, so the read accessor's cached leaf
 * is usually the wrong one: a lookup walks root -> upper -> lower -> leaf,
 * three dependent loads before the values, each a likely cache miss in a
 * 1024^3 grid. The directory only locates leaves; the values are the
 * grid's own, so the field is unchanged.
 *
 * LAYOUT. Index space is cut into regions of 8^3 blocks (64^3 voxels). A
 * dense top table over the regions of the active box holds, per region,
 * which chunk describes it (0: none). A chunk has one entry per block of
 * the region and of its one-block apron on the + sides, 9^3 entries: the
 * word offset of that block's leaf value table, 0 where it has no leaf.
 * A block without a leaf that lies in a tile of value +background or
 * -background (a level set's outside and inside) holds GRID_TILE_POSITIVE
 * or GRID_TILE_NEGATIVE instead, so cells where the band's leaves meet the
 * tiles are read without the accessor too (0: ask the accessor).
 * Chunks exist only for regions whose 9^3 blocks hold a leaf, so the
 * directory grows with the surface, not with the box (a 4096^3 box costs a
 * 1 MiB top table). A trilinear cell spans voxels i0 and i0 + 1 per axis,
 * in block i0 >> 3 or the next one, which is in the same chunk thanks to
 * the apron: one top load, one chunk load per block the cell touches.
 *
 * TYPES. Float leaves hold 32-bit values; Fp16, Fp8 and Fp4 leaves hold
 * codes of 16, 8 or 4 bits, value = code * quantum + minimum with the two
 * floats just before the table (PNanoVDB's pnanovdb_leaf_fp_read_float).
 * Those four types get a directory; FpN (a bit depth per leaf) and double
 * grids go through the accessor.
 *
 * TRUST. Leaves are found through the lower nodes that a read accessor
 * over the checked tree (grid_load.c) reaches from their own origins, and
 * placed where their lower node says: a corrupt node array can at worst
 * leave blocks to the accessor, never misplace one. */
#include <stdlib.h>
#include <string.h>

#include "grid_cell.h" /* has_directory */

enum { MAX_REGIONS = 1 << 24 }; /* a 64 MiB top table: a box of 16384^3 voxels */

/* The leaves the tree itself reaches (each lower node the tree reaches from
 * its origin, then its children), in the order of the lower nodes' array:
 * visit(block coordinates, the leaf's byte offset, its value table's word
 * offset) for each. Nothing is read from the leaves themselves: a deferred
 * grid's may not be filled yet (grid_deferred.c), and a leaf's place is
 * where its lower node puts it, which is where the accessor finds it. */

/* The address of node i of the tree's array of `level` (0 leaves, 1 lower
 * nodes) when the tree itself reaches that node from its origin, else 0
 * (past the grid's bytes, or not where the tree has it). acc: a read
 * accessor over g, reused between calls. */
static uint64_t reached_node(const sdft_grid *g, pnanovdb_readaccessor_t *acc, int level, uint64_t i)
{
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(g->buf, g->grid);
    const uint64_t first = PNANOVDB_GRID_SIZE + (level ? pnanovdb_tree_get_node_offset_lower(g->buf, tree)
                                                       : pnanovdb_tree_get_node_offset_leaf(g->buf, tree));
    const uint64_t stride =
        level ? PNANOVDB_GRID_TYPE_GET(g->type, lower_size) : PNANOVDB_GRID_TYPE_GET(g->type, leaf_size);
    const uint64_t at = first + i * stride;
    if (at > g->size || g->size - at < stride)
        return 0;
    /* Both nodes start with their bounding box's minimum. */
    pnanovdb_coord_t o = pnanovdb_read_coord(g->buf, pnanovdb_address_offset64((pnanovdb_address_t){0}, at));
    uint32_t found;
    pnanovdb_readaccessor_get_value_address_and_level(g->type, g->buf, acc, &o, &found);
    const uint64_t reached = level ? acc->lower.address.byte_offset : acc->leaf.address.byte_offset;
    return found <= (uint32_t)level && reached == at ? at : 0;
}

/* Calls visit(ctx, lower) for each lower node the tree reaches, in
 * parallel. */
typedef void (*lower_node_visit)(void *ctx, pnanovdb_lower_handle_t lower);

static void each_lower(const sdft_grid *g, lower_node_visit visit, void *ctx)
{
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(g->buf, g->grid);
    const uint64_t count = pnanovdb_tree_get_node_count_lower(g->buf, tree);
#pragma omp parallel
    {
        pnanovdb_readaccessor_t acc;
        pnanovdb_readaccessor_init(&acc, g->root);
#pragma omp for schedule(dynamic, 16)
        for (long li = 0; li < (long)count; li++) {
            const uint64_t at = reached_node(g, &acc, 1, (uint64_t)li);
            if (at)
                visit(ctx, (pnanovdb_lower_handle_t){{at}});
        }
    }
}

/* The block (index >> 3) of entry n of a lower node whose origin is o. */
static inline void lower_entry_block(pnanovdb_coord_t o, uint32_t n, int32_t b[3])
{
    b[0] = ((o.x & ~127) >> 3) + (int32_t)(n >> 8);
    b[1] = ((o.y & ~127) >> 3) + (int32_t)(n >> 4 & 15u);
    b[2] = ((o.z & ~127) >> 3) + (int32_t)(n & 15u);
}

/* Calls visit(ctx, lower, n, block) for each entry n with a child (a leaf)
 * of each lower node the tree reaches; lower nodes in parallel. */
typedef void (*lower_visit)(void *ctx, pnanovdb_lower_handle_t lower, uint32_t n, const int32_t b[3]);

typedef struct child_walk {
    const sdft_grid *g;
    lower_visit visit;
    void *ctx;
} child_walk;

static void visit_children(void *ctx, pnanovdb_lower_handle_t lower)
{
    const child_walk *w = ctx;
    const sdft_grid *g = w->g;
    const pnanovdb_coord_t o = pnanovdb_lower_get_bbox_min(g->buf, lower);
    for (uint32_t n = 0; n < 4096u; n++) {
        if ((n & 31u) == 0 &&
            !pnanovdb_read_uint32(
                g->buf, pnanovdb_address_offset(lower.address, PNANOVDB_LOWER_OFF_CHILD_MASK + 4u * (n >> 5)))) {
            n += 31u; /* 32 entries without a child */
            continue;
        }
        if (!pnanovdb_lower_get_child_mask(g->buf, lower, n))
            continue;
        int32_t b[3];
        lower_entry_block(o, n, b);
        w->visit(w->ctx, lower, n, b);
    }
}

static void each_lower_child(const sdft_grid *g, lower_visit visit, void *ctx)
{
    child_walk w = {g, visit, ctx};
    each_lower(g, visit_children, &w);
}

typedef struct leaf_walk {
    const sdft_grid *g;
    leaf_visit visit;
    void *ctx;
} leaf_walk;

static void visit_leaf(void *ctx, pnanovdb_lower_handle_t lower, uint32_t n, const int32_t b[3])
{
    const leaf_walk *w = ctx;
    const sdft_grid *g = w->g;
    const grid_deferred *def = &g->deferred;
    const uint64_t leaf = pnanovdb_lower_get_child(g->type, g->buf, lower, n).address.byte_offset;
    if (def->state && deferred_leaf_index(def, leaf) == def->count)
        return; /* not one of the deferred grid's leaves: left to the accessor */
    w->visit(w->ctx, b, leaf, (uint32_t)((leaf + PNANOVDB_GRID_TYPE_GET(g->type, leaf_off_table)) / 4u));
}

void grid_each_leaf(const sdft_grid *g, leaf_visit visit, void *ctx)
{
    leaf_walk w = {g, visit, ctx};
    each_lower_child(g, visit_leaf, &w);
}

/* The chunks a block appears in: its own region's, and the region before
 * along each axis where the block is that region's apron (offset 0). */
typedef struct builder {
    grid_leaves *d;
    uint32_t chunks; /* chunks handed out so far */
} builder;

static size_t region_index(const grid_leaves *d, const int32_t r[3])
{
    for (int k = 0; k < 3; k++)
        if ((uint32_t)(r[k] - d->r0[k]) >= (uint32_t)d->nr[k])
            return SIZE_MAX;
    return ((size_t)(r[2] - d->r0[2]) * (size_t)d->nr[1] + (size_t)(r[1] - d->r0[1])) * (size_t)d->nr[0] +
           (size_t)(r[0] - d->r0[0]);
}

/* Calls fn for each (region, local entry) that describes block b. */
static void each_place(grid_leaves *d, const int32_t b[3], void (*fn)(grid_leaves *, size_t, uint32_t, void *),
                       void *arg)
{
    const int at_zero = ((b[0] & 7) == 0) | ((b[1] & 7) == 0) << 1 | ((b[2] & 7) == 0) << 2;
    for (int c = 0; c < 8; c++) {
        if (c & ~at_zero) /* an apron place needs offset 0 along each of c's axes */
            continue;
        int32_t r[3], l[3];
        for (int k = 0; k < 3; k++) {
            r[k] = b[k] >> 3, l[k] = b[k] & 7;
            if (c >> k & 1) /* the apron of the region before */
                r[k]--, l[k] = 8;
        }
        const size_t ri = region_index(d, r);
        if (ri != SIZE_MAX)
            fn(d, ri, (uint32_t)((l[2] * GRID_CHUNK_SIDE + l[1]) * GRID_CHUNK_SIDE + l[0]), arg);
    }
}

static void mark_region(grid_leaves *d, size_t ri, uint32_t local, void *arg)
{
    (void)local, (void)arg;
    __atomic_store_n(&d->top[ri], 1u, __ATOMIC_RELAXED); /* threads may mark a region together */
}

static void mark_leaf(void *ctx, const int32_t b[3], uint64_t at, uint32_t word)
{
    (void)at, (void)word;
    builder *bl = ctx;
    each_place(bl->d, b, mark_region, NULL);
}

static void set_entry(grid_leaves *d, size_t ri, uint32_t local, void *arg)
{
    d->chunk[(size_t)(d->top[ri] - 1u) * GRID_CHUNK_ENTRIES + local] = *(const uint32_t *)arg;
}

static void fill_leaf(void *ctx, const int32_t b[3], uint64_t at, uint32_t word)
{
    builder *bl = ctx;
    (void)at;
    each_place(bl->d, b, set_entry, &word);
}

/* The tiles of the lower nodes (8^3 blocks without a leaf) whose value is
 * +-background, marked in the chunks that exist. Like the leaves, a lower
 * node is entered only when the tree itself reaches it from its origin.
 * A lower node spans 2^3 regions; a block of one is entered in that
 * region's chunk and, where its offset along some axes is 0, in the apron
 * of the regions before along them (each_place). Those chunks are looked up
 * once per region, and a region none of them exists for is skipped (on
 * vdb_tool's fandisk at 4096^3 this took a quarter off the marking). Each
 * entry belongs to one block and so to one lower node, which one thread
 * visits. */
typedef struct tile_walk {
    const sdft_grid *g;
    grid_leaves *d;
} tile_walk;

static void mark_lower_tiles(void *ctx, pnanovdb_lower_handle_t lower)
{
    const tile_walk *w = ctx;
    const sdft_grid *g = w->g;
    grid_leaves *d = w->d;
    const pnanovdb_coord_t o = pnanovdb_lower_get_bbox_min(g->buf, lower);
    int32_t b0[3];
    lower_entry_block(o, 0, b0);
    for (int q = 0; q < 8; q++) {
        uint32_t *chunk[8]; /* [c]: the chunk of the region q - c (c's bits: one region back along x, y, z) */
        int any = 0;
        for (int c = 0; c < 8; c++) {
            int32_t r[3];
            for (int k = 0; k < 3; k++)
                r[k] = (b0[k] >> 3) + (q >> k & 1) - (c >> k & 1);
            const size_t ri = region_index(d, r);
            chunk[c] = ri != SIZE_MAX && d->top[ri] ? d->chunk + (size_t)(d->top[ri] - 1u) * GRID_CHUNK_ENTRIES : NULL;
            any |= chunk[c] != NULL;
        }
        if (!any)
            continue;
        for (uint32_t l = 0; l < 512u; l++) {
            const uint32_t lx = l >> 6, ly = l >> 3 & 7u, lz = l & 7u;
            const uint32_t n = ((uint32_t)(q & 1) * 8u + lx) << 8 | ((uint32_t)(q >> 1 & 1) * 8u + ly) << 4 |
                               ((uint32_t)(q >> 2) * 8u + lz);
            if (pnanovdb_lower_get_child_mask(g->buf, lower, n))
                continue;
            const float v = pnanovdb_read_float(g->buf, pnanovdb_lower_get_table_address(g->type, g->buf, lower, n));
            const uint32_t marker = v == g->background    ? GRID_TILE_POSITIVE
                                    : v == -g->background ? GRID_TILE_NEGATIVE
                                                          : 0u;
            if (!marker)
                continue;
            const int at_zero = (lx == 0) | (ly == 0) << 1 | (lz == 0) << 2;
            for (int c = 0; c < 8; c++) {
                if ((c & ~at_zero) || !chunk[c]) /* an apron place needs offset 0 along each of c's axes */
                    continue;
                const uint32_t x = c & 1 ? 8u : lx, y = c & 2 ? 8u : ly, z = c & 4 ? 8u : lz;
                uint32_t *e = &chunk[c][(z * GRID_CHUNK_SIDE + y) * GRID_CHUNK_SIDE + x];
                if (*e == 0)
                    *e = marker;
            }
        }
    }
}

static void mark_tiles(const sdft_grid *g, grid_leaves *d)
{
    tile_walk w = {g, d};
    each_lower(g, mark_lower_tiles, &w);
}

sdft_error grid_leaves_build(sdft_grid *g)
{
    grid_leaves *d = &g->leaves;
    *d = (grid_leaves){0};
    if (!has_directory(g->type) || g->size / 4u > UINT32_MAX)
        return SDFT_OK; /* the accessor serves these */
    size_t regions = 1;
    for (int k = 0; k < 3; k++) {
        d->r0[k] = g->ilo[k] >> 6;
        d->nr[k] = (g->ihi[k] >> 6) - d->r0[k] + 1;
        regions *= (size_t)d->nr[k];
    }
    if (regions > MAX_REGIONS)
        return SDFT_OK;
    d->top = grid_table_alloc(regions * sizeof *d->top);
    if (!d->top)
        return SDFT_ENOMEM;
    memset(d->top, 0, regions * sizeof *d->top);
    builder bl = {d, 0};
    grid_each_leaf(g, mark_leaf, &bl);
    for (size_t i = 0; i < regions; i++)
        if (d->top[i])
            d->top[i] = ++bl.chunks;
    d->chunks = bl.chunks;
    const size_t entries = (size_t)bl.chunks * GRID_CHUNK_ENTRIES;
    d->chunk = grid_table_alloc((entries ? entries : 1) * sizeof *d->chunk);
    if (!d->chunk) {
        grid_leaves_free(g);
        return SDFT_ENOMEM;
    }
    memset(d->chunk, 0, entries * sizeof *d->chunk);
    if (!g->deferred.state) /* a deferred grid's leaves are entered as they are filled */
        grid_each_leaf(g, fill_leaf, &bl);
    if (g->background > 0.0f && g->type != PNANOVDB_GRID_TYPE_DOUBLE)
        mark_tiles(g, d);
    return SDFT_OK;
}

static void publish_entry(grid_leaves *d, size_t ri, uint32_t local, void *arg)
{
    __atomic_store_n(&d->chunk[(size_t)(d->top[ri] - 1u) * GRID_CHUNK_ENTRIES + local], *(const uint32_t *)arg,
                     __ATOMIC_RELEASE);
}

void grid_leaves_publish(const sdft_grid *g, const int32_t b[3], uint32_t word)
{
    each_place((grid_leaves *)&g->leaves, b, publish_entry, &word); /* its entries are written atomically */
}

void grid_leaves_free(sdft_grid *g)
{
    free(g->leaves.top);
    free(g->leaves.chunk);
    g->leaves.top = NULL;
    g->leaves.chunk = NULL;
}

size_t grid_leaves_bytes(const sdft_grid *g)
{
    const grid_leaves *d = &g->leaves;
    if (!d->top)
        return 0;
    return (size_t)d->nr[0] * d->nr[1] * d->nr[2] * sizeof *d->top + d->chunks * GRID_CHUNK_ENTRIES * sizeof *d->chunk;
}
