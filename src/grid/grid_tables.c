/* sdftrace — a grid's acceleration tables stored with it: the far bound's
 * corner table and the hull, kept as NanoVDB blind data after the tree, so
 * that opening a `.nvdb` file sdftrace wrote is reading the file and
 * checking, not building (sdft_grid_export writes them; grid_load.c takes
 * them through grid_tables_take).
 *
 * THE BLOB. One blind data entry named TABLES_NAME (semantic, class and
 * type unknown to NanoVDB, which passes it through), element count its
 * bytes, 64-byte aligned: a tables_header, then the corner table and the
 * hull's boxes, slabs and gradient boxes, each 64-byte aligned, at the
 * offsets the header gives (from the blob's start).
 *
 * TRUST. A file's tables are data from a stranger, as the grid is. They
 * are taken only when every check holds, else built as for any grid (the
 * picture is the same either way):
 *   - the entry, the blob and every table lie inside the grid's bytes,
 *     aligned, their sizes those the header's counts imply;
 *   - they belong to this very grid and are as written: the header's
 *     hashes are those of the grid's bytes before its blind data
 *     (grid_hash, the header's fields that blind data changes set to 0)
 *     and of the tables, so a grid edited by another tool that kept the
 *     blob, or a damaged blob, has them rebuilt;
 *   - the far bound's cells are the ones grid_far_build would lay over
 *     this grid's box;
 *   - the hull has no more boxes than leaves and face patches, each box
 *     finite, ordered, inside the grid's box grown by ten voxels (the face
 *     patches reach 9.5 beyond it, block-aligned) and no
 *     wider than the world box of 12 voxels (a leaf's box spans at most 9,
 *     a face patch's 11), each slab finite or everywhere, no NaN in the
 *     gradient boxes.
 * So a forged blob can at worst mislead the picture as a forged grid
 * could, and never makes a read outside the buffer or an allocation
 * larger than a true grid's would be. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "grid_internal.h"

#define TABLES_NAME "sdftrace.tables"
#define TABLES_MAGIC "SDFTTAB1"

typedef struct tables_header {
    char magic[8];        /* TABLES_MAGIC */
    uint32_t header_size; /* sizeof(tables_header) */
    uint32_t flags;       /* TABLES_FAR, TABLES_HULL: which tables follow */
    uint64_t grid_bytes;  /* the grid before its blind data: what grid_hash covers */
    uint64_t grid_hash;
    uint64_t tables_hash; /* of the blob after this header */
    int32_t far_c0[3], far_n[3];
    int32_t far_cell, pad;
    uint64_t far_at; /* the corner table: (n[0] + 1) (n[1] + 1) (n[2] + 1) uint16 */
    uint64_t hull_count;
    uint64_t box_at, slab_at, gradient_at; /* hull_count sdft_aabb, sdft_slab, sdft_aabb */
} tables_header;

enum { TABLES_FAR = 1, TABLES_HULL = 2 };

static uint64_t align64(uint64_t n) { return (n + 63u) & ~(uint64_t)63u; }

/* ---- the grid's hash -------------------------------------------------------
 * 64 KiB blocks, each hashed on its own in parallel (8 lanes of 64-bit
 * words, each lane h = (h ^ w) P, then mixed), the blocks' hashes folded in
 * order: the same number for any thread count. Not a cryptographic hash:
 * it tells a grid from an edited one. */

enum { HASH_BLOCK = 1 << 16 };
static const uint64_t HASH_P = 0x9E3779B97F4A7C15ull, HASH_Q = 0xC2B2AE3D27D4EB4Full;

static uint64_t mix64(uint64_t h)
{
    h ^= h >> 33, h *= HASH_Q, h ^= h >> 29, h *= HASH_P, h ^= h >> 32;
    return h;
}

static uint64_t hash_block(const unsigned char *p, size_t n, uint64_t seed)
{
    uint64_t lane[8];
    for (int l = 0; l < 8; l++)
        lane[l] = seed + (uint64_t)l * HASH_Q;
    size_t i = 0;
    for (; i + 64 <= n; i += 64)
        for (int l = 0; l < 8; l++) {
            uint64_t w;
            memcpy(&w, p + i + 8 * l, 8);
            lane[l] = (lane[l] ^ w) * HASH_P;
        }
    uint64_t h = mix64(seed ^ n);
    for (; i < n; i++)
        h = (h ^ p[i]) * HASH_P;
    for (int l = 0; l < 8; l++)
        h = mix64(h ^ mix64(lane[l]));
    return h;
}

/* The hash of n bytes, folded onto h. */
static uint64_t bytes_hash(uint64_t h, const unsigned char *p, size_t n)
{
    const size_t blocks = (n + HASH_BLOCK - 1) / HASH_BLOCK;
    uint64_t *part = malloc((blocks ? blocks : 1) * sizeof *part);
    if (!part) { /* no memory for the parts: the same hash, one block after the other */
        for (size_t b = 0; b < blocks; b++) {
            const size_t at = b * HASH_BLOCK;
            h = mix64(h ^ hash_block(p + at, n - at < HASH_BLOCK ? n - at : HASH_BLOCK, b + 2));
        }
        return h;
    }
#pragma omp parallel for schedule(static)
    for (long b = 0; b < (long)blocks; b++) {
        const size_t at = (size_t)b * HASH_BLOCK;
        part[b] = hash_block(p + at, n - at < HASH_BLOCK ? n - at : HASH_BLOCK, (uint64_t)b + 2);
    }
    for (size_t b = 0; b < blocks; b++)
        h = mix64(h ^ part[b]);
    free(part);
    return h;
}

/* The hash of the grid's first `bytes` bytes (the grid before its blind
 * data), with the header's fields that blind data changes (its size, its
 * checksum, the blind metadata's place and count) taken as 0. */
static uint64_t grid_hash(const sdft_grid *g, uint64_t bytes)
{
    unsigned char head[PNANOVDB_GRID_SIZE];
    memcpy(head, g->words, sizeof head);
    memset(head + PNANOVDB_GRID_OFF_CHECKSUM, 0, 8);
    memset(head + PNANOVDB_GRID_OFF_GRID_SIZE, 0, 8);
    memset(head + PNANOVDB_GRID_OFF_BLIND_METADATA_OFFSET, 0, 8);
    memset(head + PNANOVDB_GRID_OFF_BLIND_METADATA_COUNT, 0, 4);
    return bytes_hash(hash_block(head, sizeof head, 1), (const unsigned char *)g->words + PNANOVDB_GRID_SIZE,
                      (size_t)bytes - PNANOVDB_GRID_SIZE);
}

/* The hash of a blob's tables: its bytes after the header. */
static uint64_t tables_hash(const unsigned char *blob, uint64_t blob_bytes)
{
    return bytes_hash(0, blob + sizeof(tables_header), (size_t)(blob_bytes - sizeof(tables_header)));
}

/* ---- taking a grid's tables ------------------------------------------------ */

/* Where the grid's blind metadata begins (its tree's end), and how many
 * entries it has, when they lie inside the grid; else 0. */
static uint64_t blind_metadata(const sdft_grid *g, uint32_t *count)
{
    const int64_t at = pnanovdb_grid_get_blind_metadata_offset(g->buf, g->grid);
    *count = pnanovdb_grid_get_blind_metadata_count(g->buf, g->grid);
    if (*count == 0 || at < (int64_t)(PNANOVDB_GRID_SIZE + PNANOVDB_TREE_SIZE) || (uint64_t)at > g->size ||
        (at & 7) != 0 || (g->size - (uint64_t)at) / PNANOVDB_GRIDBLINDMETADATA_SIZE < *count)
        return 0;
    return (uint64_t)at;
}

/* The tables' blob of g (its header at *h, copied), or NULL. */
static const unsigned char *find_blob(const sdft_grid *g, uint64_t *meta_at, tables_header *h, uint64_t *blob_bytes)
{
    uint32_t count;
    const uint64_t first = blind_metadata(g, &count);
    if (!first)
        return NULL;
    const unsigned char *bytes = (const unsigned char *)g->words;
    for (uint32_t i = 0; i < count; i++) {
        const uint64_t meta = first + (uint64_t)i * PNANOVDB_GRIDBLINDMETADATA_SIZE;
        char name[sizeof TABLES_NAME];
        memcpy(name, bytes + meta + PNANOVDB_GRIDBLINDMETADATA_OFF_NAME, sizeof name);
        if (memcmp(name, TABLES_NAME, sizeof name) != 0)
            continue;
        int64_t offset;
        uint64_t n;
        memcpy(&offset, bytes + meta + PNANOVDB_GRIDBLINDMETADATA_OFF_BYTE_OFFSET, 8);
        memcpy(&n, bytes + meta + PNANOVDB_GRIDBLINDMETADATA_OFF_ELEMENT_COUNT, 8);
        /* NanoVDB's byte offset is from the metadata entry itself. */
        if (offset < 0 || (uint64_t)offset > g->size - meta)
            return NULL;
        const uint64_t at = meta + (uint64_t)offset;
        if ((at & 63) != 0 || n < sizeof *h || n > g->size - at)
            return NULL;
        memcpy(h, bytes + at, sizeof *h);
        if (memcmp(h->magic, TABLES_MAGIC, 8) != 0 || h->header_size != sizeof *h)
            return NULL;
        *meta_at = first, *blob_bytes = n;
        return bytes + at;
    }
    return NULL;
}

/* Whether table [at, at + bytes) lies in the blob, 64-byte aligned. */
static int in_blob(uint64_t at, uint64_t bytes, uint64_t blob_bytes)
{
    return (at & 63) == 0 && at >= sizeof(tables_header) && at <= blob_bytes && bytes <= blob_bytes - at;
}

static int finite_box(sdft_aabb b)
{
    return sdft_isfinite3(b.lo) && sdft_isfinite3(b.hi) && b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z;
}

/* The far bound of the blob, checked, into g->far (the table in place). */
static int take_far(sdft_grid *g, const tables_header *h, const unsigned char *blob, uint64_t blob_bytes)
{
    grid_far want;
    memset(&want, 0, sizeof want);
    if (!(h->flags & TABLES_FAR) || !grid_far_plan(g, &want) || want.cell != h->far_cell)
        return 0;
    for (int k = 0; k < 3; k++)
        if (want.c0[k] != h->far_c0[k] || want.n[k] != h->far_n[k])
            return 0;
    const uint64_t corners = (uint64_t)(want.n[0] + 1) * (uint64_t)(want.n[1] + 1) * (uint64_t)(want.n[2] + 1);
    if (!in_blob(h->far_at, corners * sizeof(uint16_t), blob_bytes))
        return 0;
    g->far = want;
    g->far.corner = (uint16_t *)(uintptr_t)(blob + h->far_at); /* read only; not freed (stored) */
    g->far.stored = 1;
    return 1;
}

/* The hull of the blob, checked, into g (its arrays in place). */
static int take_hull(sdft_grid *g, const tables_header *h, const unsigned char *blob, uint64_t blob_bytes)
{
    const uint64_t n = h->hull_count;
    if (!(h->flags & TABLES_HULL) || !grid_hull_wanted(g) || n > grid_hull_most(g) ||
        !in_blob(h->box_at, n * sizeof(sdft_aabb), blob_bytes) ||
        !in_blob(h->slab_at, n * sizeof(sdft_slab), blob_bytes) ||
        !in_blob(h->gradient_at, n * sizeof(sdft_aabb), blob_bytes))
        return 0;
    const sdft_aabb *box = (const sdft_aabb *)(const void *)(blob + h->box_at),
                    *gradient = (const sdft_aabb *)(const void *)(blob + h->gradient_at);
    const sdft_slab *slab = (const sdft_slab *)(const void *)(blob + h->slab_at);
    /* The grid's box grown by ten voxels, and the widest a box may be. */
    const float twelve[3] = {12.0f, 12.0f, 12.0f}, zero[3] = {0.0f, 0.0f, 0.0f};
    const float lo[3] = {(float)g->ilo[0] - 10.0f, (float)g->ilo[1] - 10.0f, (float)g->ilo[2] - 10.0f},
                hi[3] = {(float)g->ihi[0] + 10.0f, (float)g->ihi[1] + 10.0f, (float)g->ihi[2] + 10.0f};
    const sdft_aabb room = grid_world_box(g, lo, hi), unit = grid_world_box(g, zero, twelve);
    const sdft_vec3 widest = sdft_sub(unit.hi, unit.lo);
    int ok = 1;
#pragma omp parallel for schedule(static) reduction(& : ok)
    for (long i = 0; i < (long)n; i++) {
        const sdft_aabb b = box[i], gr = gradient[i];
        const sdft_slab s = slab[i];
        const sdft_vec3 w = sdft_sub(b.hi, b.lo);
        const int everywhere = s.n.x == 0.0f && s.n.y == 0.0f && s.n.z == 0.0f && s.lo == -INFINITY && s.hi == INFINITY;
        ok &= finite_box(b) && b.lo.x >= room.lo.x && b.lo.y >= room.lo.y && b.lo.z >= room.lo.z &&
              b.hi.x <= room.hi.x && b.hi.y <= room.hi.y && b.hi.z <= room.hi.z && w.x <= widest.x && w.y <= widest.y &&
              w.z <= widest.z;
        ok &= everywhere || (sdft_isfinite3(s.n) && isfinite(s.lo) && isfinite(s.hi) && s.lo <= s.hi);
        ok &= gr.lo.x <= gr.hi.x && gr.lo.y <= gr.hi.y && gr.lo.z <= gr.hi.z; /* no NaN; infinite: unbounded */
    }
    if (!ok)
        return 0;
    if (n) /* else stored as none: the grid's faces keep it from having one (grid_hull.c) */
        g->hull = (sdft_aabb *)(uintptr_t)box, g->hull_slab = (sdft_slab *)(uintptr_t)slab,
        g->hull_gradient = (sdft_aabb *)(uintptr_t)gradient;
    g->hull_count = (size_t)n;
    g->hull_stored = 1;
    return 1;
}

void grid_tables_take(sdft_grid *g)
{
    if (g->deferred.state) /* a deferred grid's far bound differs, and it has no hull */
        return;
    tables_header h;
    uint64_t meta_at, blob_bytes;
    const unsigned char *blob = find_blob(g, &meta_at, &h, &blob_bytes);
    if (!blob || h.grid_bytes != meta_at || h.grid_hash != grid_hash(g, meta_at) ||
        h.tables_hash != tables_hash(blob, blob_bytes))
        return;
    take_far(g, &h, blob, blob_bytes);
    take_hull(g, &h, blob, blob_bytes);
}

/* ---- storing them ------------------------------------------------------------ */

void grid_tables_seal(void *bytes, size_t size)
{
    sdft_grid view;
    memset(&view, 0, sizeof view);
    view.words = bytes, view.size = size;
    view.buf = pnanovdb_make_buf(view.words, size / 4);
    tables_header h;
    uint64_t meta_at, blob_bytes;
    const unsigned char *blob = find_blob(&view, &meta_at, &h, &blob_bytes);
    if (!blob)
        return;
    h.grid_bytes = meta_at;
    h.grid_hash = grid_hash(&view, meta_at);
    h.tables_hash = tables_hash(blob, blob_bytes);
    memcpy((unsigned char *)bytes + (blob - (const unsigned char *)bytes), &h, sizeof h);
}

/* ---- the hull, in a fixed order ----------------------------------------
 * The hull's boxes are found by leaves on many threads, so they come in an
 * order that changes from run to run; a renderer takes the least entry
 * and the greatest exit over them (render_hull.c), which no order changes.
 * A file is written with them sorted by their bytes, so that the same grid
 * makes the same file every time. */

typedef struct hull_entry {
    sdft_aabb box;
    sdft_slab slab;
    sdft_aabb gradient;
} hull_entry;

static int hull_entry_order(const void *a, const void *b) { return memcmp(a, b, sizeof(hull_entry)); }

/* g's n hull entries, sorted, into the three arrays at `box`, `slab` and
 * `gradient`; 0, or -1 out of memory. */
static int write_hull_sorted(const sdft_grid *g, uint64_t n, unsigned char *box, unsigned char *slab,
                             unsigned char *gradient)
{
    hull_entry *e = malloc((size_t)n * sizeof *e);
    if (!e)
        return -1;
    for (uint64_t i = 0; i < n; i++) {
        memset(&e[i], 0, sizeof e[i]);
        e[i].box = g->hull[i], e[i].slab = g->hull_slab[i], e[i].gradient = g->hull_gradient[i];
    }
    qsort(e, (size_t)n, sizeof *e, hull_entry_order);
    for (uint64_t i = 0; i < n; i++) {
        memcpy(box + i * sizeof(sdft_aabb), &e[i].box, sizeof(sdft_aabb));
        memcpy(slab + i * sizeof(sdft_slab), &e[i].slab, sizeof(sdft_slab));
        memcpy(gradient + i * sizeof(sdft_aabb), &e[i].gradient, sizeof(sdft_aabb));
    }
    free(e);
    return 0;
}

sdft_error sdft_grid_export(const sdft_grid *g, void **data, size_t *size, char *msg, size_t msg_len)
{
    if (!g || !data || !size)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no grid or no place for its bytes (NULL)");
    *data = NULL, *size = 0;
    if (g->deferred.state)
        grid_fill_all(g);
    uint32_t count;
    /* A deferred grid's far bound is looser than a whole grid's: not stored. */
    const int far = g->far.corner && !g->deferred.state, hull = grid_hull_wanted(g);
    const int with_tables = !blind_metadata(g, &count) && count == 0 && (far || hull);
    /* The grid's own bytes: all of them where it keeps other blind data (or none to add). */
    const uint64_t grid_bytes = with_tables ? align64(g->size) : g->size;
    uint64_t far_bytes = 0, corners = 0;
    if (far) {
        corners = (uint64_t)(g->far.n[0] + 1) * (uint64_t)(g->far.n[1] + 1) * (uint64_t)(g->far.n[2] + 1);
        far_bytes = corners * sizeof(uint16_t);
    }
    const uint64_t n = hull && g->hull ? g->hull_count : 0; /* 0: a grid whose faces keep it from having one */
    tables_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, TABLES_MAGIC, 8);
    h.header_size = sizeof h;
    h.flags = (far ? TABLES_FAR : 0u) | (hull ? TABLES_HULL : 0u);
    h.far_at = align64(sizeof h);
    h.box_at = align64(h.far_at + far_bytes);
    h.slab_at = align64(h.box_at + n * sizeof(sdft_aabb));
    h.gradient_at = align64(h.slab_at + n * sizeof(sdft_slab));
    const uint64_t blob_bytes = align64(h.gradient_at + n * sizeof(sdft_aabb));
    const uint64_t meta_at = grid_bytes, blob_at = align64(meta_at + PNANOVDB_GRIDBLINDMETADATA_SIZE);
    const uint64_t total = with_tables ? blob_at + blob_bytes : g->size;
    unsigned char *out = total <= SIZE_MAX ? calloc(1, (size_t)total) : NULL;
    if (!out)
        return fail_with(msg, msg_len, SDFT_ENOMEM, "out of memory for a %llu-byte grid", (unsigned long long)total);
    memcpy(out, g->words, g->size);
    if (with_tables) {
        const uint64_t none = ~(uint64_t)0;
        const int64_t meta_offset = (int64_t)meta_at, data_offset = (int64_t)(blob_at - meta_at);
        const uint32_t one = 1;
        memcpy(out + PNANOVDB_GRID_OFF_GRID_SIZE, &total, 8);
        memcpy(out + PNANOVDB_GRID_OFF_CHECKSUM, &none, 8); /* no checksum: a writer may set one */
        memcpy(out + PNANOVDB_GRID_OFF_BLIND_METADATA_OFFSET, &meta_offset, 8);
        memcpy(out + PNANOVDB_GRID_OFF_BLIND_METADATA_COUNT, &one, 4);
        unsigned char *meta = out + meta_at;
        memcpy(meta + PNANOVDB_GRIDBLINDMETADATA_OFF_BYTE_OFFSET, &data_offset, 8);
        memcpy(meta + PNANOVDB_GRIDBLINDMETADATA_OFF_ELEMENT_COUNT, &blob_bytes, 8);
        memcpy(meta + PNANOVDB_GRIDBLINDMETADATA_OFF_NAME, TABLES_NAME, sizeof TABLES_NAME);
        h.grid_bytes = meta_at;
        if (far) {
            memcpy(h.far_c0, g->far.c0, sizeof h.far_c0), memcpy(h.far_n, g->far.n, sizeof h.far_n);
            h.far_cell = g->far.cell;
            memcpy(out + blob_at + h.far_at, g->far.corner, (size_t)far_bytes);
        }
        if (n && write_hull_sorted(g, n, out + blob_at + h.box_at, out + blob_at + h.slab_at,
                                   out + blob_at + h.gradient_at) != 0) {
            free(out);
            return fail_with(msg, msg_len, SDFT_ENOMEM, "out of memory for a grid's %llu hull boxes",
                             (unsigned long long)n);
        }
        h.hull_count = n;
        memcpy(out + blob_at, &h, sizeof h);
        grid_tables_seal(out, (size_t)total);
    }
    *data = out, *size = (size_t)total;
    return SDFT_OK;
}
