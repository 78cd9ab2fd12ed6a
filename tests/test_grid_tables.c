/* sdftrace tests — a grid's acceleration tables stored with it
 * (src/grid/grid_tables.c): taken from the grid's bytes they equal the
 * tables built from scratch, bit for bit, and give the same field; a file
 * `sdftrace bake` writes carries them; tables that are damaged, belong to
 * another grid or were forged past their hashes are left, and the grid
 * built as any other, never read outside the buffer. */
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "grid_internal.h"
#include "grid_support.h"
#include "sdftrace/grid.h"
#include "sdftrace/scene.h"
#include "sdftrace/vdb.h"
#include "testutil.h"

/* The grid of `bytes` (copied), which must open. */
static sdft_grid *open_bytes(const void *bytes, size_t size)
{
    sdft_grid_options o = sdft_grid_options_defaults();
    o.data = bytes, o.size = size;
    sdft_grid *g = NULL;
    char msg[256] = "";
    const sdft_error rc = sdft_grid_open(&o, &g, msg, sizeof msg);
    if (rc)
        print_error("open: %s\n", msg);
    assert_int_equal(rc, SDFT_OK);
    return g;
}

static sdft_grid_phases phases_of(const sdft_grid *g)
{
    sdft_grid_phases p;
    sdft_grid_load_phases(g, &p);
    return p;
}

/* Hull i of g as one record: box, slab, gradient box, for sorting. */
typedef struct hull_part {
    sdft_aabb box;
    sdft_slab slab;
    sdft_aabb gradient;
} hull_part;

static int part_order(const void *a, const void *b) { return memcmp(a, b, sizeof(hull_part)); }

static hull_part *hull_parts(const sdft_grid *g)
{
    hull_part *p = calloc(g->hull_count ? g->hull_count : 1, sizeof *p);
    assert_non_null(p);
    for (size_t i = 0; i < g->hull_count; i++)
        p[i] = (hull_part){g->hull[i], g->hull_slab[i], g->hull_gradient[i]};
    qsort(p, g->hull_count, sizeof *p, part_order);
    return p;
}

/* The same far bound and hull (its parts in any order, as the leaves are
 * visited in parallel), bit for bit. */
static void same_tables(const sdft_grid *a, const sdft_grid *b)
{
    assert_int_equal(a->far.cell, b->far.cell);
    assert_memory_equal(a->far.n, b->far.n, sizeof a->far.n);
    assert_memory_equal(a->far.c0, b->far.c0, sizeof a->far.c0);
    assert_true(a->far.bonus == b->far.bonus && a->far.inv_cell == b->far.inv_cell);
    assert_memory_equal(a->far.origin, b->far.origin, sizeof a->far.origin);
    const size_t corners = (size_t)(a->far.n[0] + 1) * (a->far.n[1] + 1) * (a->far.n[2] + 1);
    assert_non_null(a->far.corner);
    assert_non_null(b->far.corner);
    assert_memory_equal(a->far.corner, b->far.corner, corners * sizeof *a->far.corner);
    assert_int_equal(a->hull_count, b->hull_count);
    hull_part *pa = hull_parts(a), *pb = hull_parts(b);
    assert_memory_equal(pa, pb, a->hull_count * sizeof *pa);
    free(pa), free(pb);
}

/* The same field everywhere in the grid's box, with every bound. */
static void same_field(const sdft_grid *a, const sdft_grid *b, uint32_t seed)
{
    for (int bound = 0; bound < 3; bound++) {
        sdft_field fa = sdft_grid_field(a, (sdft_grid_bound)bound), fb = sdft_grid_field(b, (sdft_grid_bound)bound);
        sdft_scratch sa, sb;
        sdft_scratch_init(&fa, &sa), sdft_scratch_init(&fb, &sb);
        tu_rng r = tu_rng_seed(seed);
        const sdft_aabb box = sdft_grid_world_bounds(a);
        for (int i = 0; i < 4000; i++) {
            const sdft_vec3 p = sdft_v3(tu_uniform(&r, box.lo.x - 0.2f, box.hi.x + 0.2f),
                                        tu_uniform(&r, box.lo.y - 0.2f, box.hi.y + 0.2f),
                                        tu_uniform(&r, box.lo.z - 0.2f, box.hi.z + 0.2f));
            const float da = fa.distance(fa.ctx, &sa, p), db = fb.distance(fb.ctx, &sb, p);
            if (!(da == db))
                fail_msg("bound %d at (%g, %g, %g): %.9g against %.9g", bound, p.x, p.y, p.z, da, db);
        }
    }
}

/* g exported is exactly `bytes`, `size` of them. */
static void exports_as(const sdft_grid *g, const void *bytes, size_t size)
{
    void *again;
    size_t again_size;
    char msg[256];
    assert_int_equal(sdft_grid_export(g, &again, &again_size, msg, sizeof msg), SDFT_OK);
    assert_int_equal(again_size, size);
    assert_memory_equal(again, bytes, size);
    free(again);
}

/* The test grid: the union of spheres at 96^3 (a narrow band: a far bound
 * and a hull), built from scratch; and its bytes with the tables. */
static sdft_grid *tables_grid(void **bytes, size_t *size)
{
    const sdft_field f = spheres_field();
    sdft_grid *g = bake(&f, 96, 0, NULL);
    const sdft_grid_phases p = phases_of(g);
    assert_false(p.far_stored || p.hull_stored); /* a bake's grid in memory builds them */
    assert_non_null(g->far.corner);
    assert_true(g->hull_count > 100);
    char msg[256];
    assert_int_equal(sdft_grid_export(g, bytes, size, msg, sizeof msg), SDFT_OK);
    assert_true(*size > sdft_grid_size(g));
    return g;
}

/* Taken from the bytes, the tables are the ones built from scratch; so
 * is the field; and exported again, the bytes are the same. */
static void test_stored_tables_are_the_built_ones(void **state)
{
    (void)state;
    void *bytes;
    size_t size;
    sdft_grid *built = tables_grid(&bytes, &size);
    sdft_grid *stored = open_bytes(bytes, size);
    const sdft_grid_phases p = phases_of(stored);
    assert_true(p.far_stored && p.hull_stored);
    assert_true(stored->far.stored && stored->hull_stored);
    same_tables(built, stored);
    same_field(built, stored, 7);
    /* The same voxels: the tables sit after the tree, which is unchanged. */
    same_voxels(built, stored);
    exports_as(stored, bytes, size);
    sdft_grid_free(stored);
    sdft_grid_free(built);
    free(bytes);
}

/* The same grid makes the same bytes whatever order its hull was found
 * in (the leaves are visited in parallel, so the order changes from run
 * to run): here the same hull reversed in memory. */
static void test_export_does_not_depend_on_the_hull_order(void **state)
{
    (void)state;
    void *bytes;
    size_t size;
    sdft_grid *g = tables_grid(&bytes, &size);
    const size_t n = g->hull_count;
    for (size_t i = 0, j = n - 1; i < j; i++, j--) {
        const sdft_aabb b = g->hull[i], gr = g->hull_gradient[i];
        const sdft_slab s = g->hull_slab[i];
        g->hull[i] = g->hull[j], g->hull_gradient[i] = g->hull_gradient[j], g->hull_slab[i] = g->hull_slab[j];
        g->hull[j] = b, g->hull_gradient[j] = gr, g->hull_slab[j] = s;
    }
    exports_as(g, bytes, size);
    free(bytes);
    sdft_grid_free(g);
}

/* A `.nvdb` that `sdftrace bake` writes carries the tables, and one that
 * NanoVDB's own writer made of the same grid (no tables) gets the same
 * ones built. */
static void test_bake_writes_the_tables(void **state)
{
    (void)state;
    char path[512], out[4096];
    tu_tmp(path, sizeof path, "tables.nvdb");
    remove(path);
    assert_int_equal(tu_run(out, sizeof out, "%s bake --scene figure --res 64 -o '%s' --quiet 2>&1", SDFT_CLI, path),
                     0);
    sdft_grid_options o = sdft_grid_options_defaults();
    o.path = path;
    sdft_grid *g = NULL;
    char msg[256];
    assert_int_equal(sdft_grid_open(&o, &g, msg, sizeof msg), SDFT_OK);
    const sdft_grid_phases p = phases_of(g);
    assert_true(p.far_stored && p.hull_stored);
    /* The grid's bytes before the tables, opened alone: built from scratch. */
    uint32_t count;
    const int64_t meta = pnanovdb_grid_get_blind_metadata_offset(g->buf, g->grid);
    count = pnanovdb_grid_get_blind_metadata_count(g->buf, g->grid);
    assert_int_equal(count, 1);
    unsigned char *plain = malloc((size_t)meta);
    assert_non_null(plain);
    memcpy(plain, g->words, (size_t)meta);
    const uint64_t bytes = (uint64_t)meta, zero = 0;
    memcpy(plain + PNANOVDB_GRID_OFF_GRID_SIZE, &bytes, 8);
    memcpy(plain + PNANOVDB_GRID_OFF_BLIND_METADATA_OFFSET, &zero, 8);
    memset(plain + PNANOVDB_GRID_OFF_BLIND_METADATA_COUNT, 0, 4);
    sdft_grid *built = open_bytes(plain, (size_t)meta);
    const sdft_grid_phases q = phases_of(built);
    assert_false(q.far_stored || q.hull_stored);
    same_tables(built, g);
    same_field(built, g, 11);
    sdft_grid_free(built);
    sdft_grid_free(g);
    free(plain);
    /* The render's report says so. */
    assert_int_equal(tu_run(out, sizeof out,
                            "%s render --grid '%s' --scene figure -o '%s.exr' --width 32 --height 18 "
                            "--json --quiet",
                            SDFT_CLI, path, path),
                     0);
    assert_non_null(strstr(out, "\"far_bound_stored\": true"));
    assert_non_null(strstr(out, "\"hull_stored\": true"));
}

/* The tables' blob in bytes: its offset and size (the test's own reading
 * of the layout grid_tables.c writes: one blind data entry). */
static size_t blob_at(const unsigned char *bytes, size_t *blob_size)
{
    int64_t meta, offset;
    uint64_t n;
    memcpy(&meta, bytes + PNANOVDB_GRID_OFF_BLIND_METADATA_OFFSET, 8);
    memcpy(&offset, bytes + meta + PNANOVDB_GRIDBLINDMETADATA_OFF_BYTE_OFFSET, 8);
    memcpy(&n, bytes + meta + PNANOVDB_GRIDBLINDMETADATA_OFF_ELEMENT_COUNT, 8);
    *blob_size = (size_t)n;
    return (size_t)(meta + offset);
}

/* Opens a changed copy of bytes: it must open, take neither table (or,
 * with `far_ok`, the far bound alone), and give the field built from
 * scratch of the same grid (`built`; NULL: not compared). */
static void refused(const void *bytes, size_t size, const sdft_grid *built, int far_ok, const char *what)
{
    sdft_grid *g = open_bytes(bytes, size);
    const sdft_grid_phases p = phases_of(g);
    if (p.hull_stored || (p.far_stored && !far_ok))
        fail_msg("%s: tables taken (far %d, hull %d)", what, p.far_stored, p.hull_stored);
    if (far_ok && !p.far_stored)
        fail_msg("%s: the far bound, untouched, was not taken", what);
    if (built) {
        same_tables(built, g);
        same_field(built, g, 3);
    }
    sdft_grid_free(g);
}

/* The grid of tables_grid, its bytes with the tables, a copy to change,
 * and where the tables' blob lies in them. */
typedef struct tampering {
    sdft_grid *built;
    void *bytes;
    unsigned char *copy;
    size_t size, blob, blob_size;
} tampering;

static tampering tamper_begin(void)
{
    tampering t;
    t.built = tables_grid(&t.bytes, &t.size);
    t.copy = malloc(t.size);
    assert_non_null(t.copy);
    t.blob = blob_at(t.bytes, &t.blob_size);
    return t;
}

static void tamper_end(tampering *t)
{
    free(t->copy);
    free(t->bytes);
    sdft_grid_free(t->built);
}

/* Damaged tables, and tables of another grid, are not taken: the grid is
 * built as any other. */
static void test_damaged_tables_are_rebuilt(void **state)
{
    (void)state;
    tampering t = tamper_begin();
    sdft_grid *built = t.built;
    void *bytes = t.bytes;
    unsigned char *copy = t.copy;
    const size_t size = t.size, blob = t.blob, blob_size = t.blob_size;
    /* One byte of the far bound's corners, of the tables' end, of the header. */
    const size_t at[3] = {blob + 128 + 1000, blob + blob_size - 100, blob + 20};
    for (int i = 0; i < 3; i++) {
        memcpy(copy, bytes, size);
        copy[at[i]] ^= 0x10;
        refused(copy, size, built, 0, "a flipped byte");
    }
    /* A voxel of the grid changed under its tables: they belong to another grid now. */
    memcpy(copy, bytes, size);
    const uint32_t leaf_words =
        (uint32_t)(pnanovdb_tree_get_node_offset_leaf(built->buf, pnanovdb_grid_get_tree(built->buf, built->grid)) +
                   PNANOVDB_GRID_SIZE) /
        4u;
    float v;
    memcpy(&v, copy + 4u * (leaf_words + 64u), 4);
    v = -v;
    memcpy(copy + 4u * (leaf_words + 64u), &v, 4);
    refused(copy, size, NULL, 0, "a changed voxel");
    /* The blind data's place, its blob's place or size out of the grid. */
    const int64_t huge = INT64_MAX / 2;
    int64_t meta;
    memcpy(&meta, bytes + PNANOVDB_GRID_OFF_BLIND_METADATA_OFFSET, 8);
    const size_t fields[3] = {PNANOVDB_GRID_OFF_BLIND_METADATA_OFFSET,
                              (size_t)meta + PNANOVDB_GRIDBLINDMETADATA_OFF_BYTE_OFFSET,
                              (size_t)meta + PNANOVDB_GRIDBLINDMETADATA_OFF_ELEMENT_COUNT};
    for (int i = 0; i < 3; i++) {
        memcpy(copy, bytes, size);
        memcpy(copy + fields[i], &huge, 8);
        refused(copy, size, built, 0, "an offset out of the grid");
    }
    /* Random damage anywhere in the blob: never taken, never a read outside the buffer. */
    tu_rng r = tu_rng_seed(5);
    for (int i = 0; i < 60; i++) {
        memcpy(copy, bytes, size);
        for (int k = 0; k < 4; k++)
            copy[blob + (size_t)tu_uniform(&r, 0.0f, (float)blob_size - 1.0f)] ^=
                (unsigned char)(1u + (unsigned)i % 255u);
        refused(copy, size, NULL, 0, "random damage");
    }
    tamper_end(&t);
}

/* Tables forged past their hashes (sealed again after the change) are
 * still checked: a hull box too wide, out of the grid's box or NaN, a slab
 * or gradient bound NaN, more boxes than the grid can have, far cells that
 * are not this grid's: the hull (or the far bound) is built instead, and
 * the untouched table is still taken. */
static void test_forged_tables_are_checked(void **state)
{
    (void)state;
    tampering t = tamper_begin();
    sdft_grid *built = t.built;
    void *bytes = t.bytes;
    unsigned char *copy = t.copy;
    const size_t size = t.size, blob = t.blob;
    /* The header's fields, as grid_tables.c lays them out. */
    uint64_t hull_count, box_at, slab_at, gradient_at;
    const size_t head = blob + 8 + 4 + 4 + 8 + 8 + 8 + 12 + 12 + 4 + 4 + 8; /* to hull_count */
    memcpy(&hull_count, (unsigned char *)bytes + head, 8);
    memcpy(&box_at, (unsigned char *)bytes + head + 8, 8);
    memcpy(&slab_at, (unsigned char *)bytes + head + 16, 8);
    memcpy(&gradient_at, (unsigned char *)bytes + head + 24, 8);
    assert_int_equal(hull_count, built->hull_count);
    const float nan = NAN;
    const sdft_aabb whole = sdft_grid_world_bounds(built), away = {{500.0f, 0.0f, 0.0f}, {500.5f, 0.5f, 0.5f}};
    const uint64_t many = UINT64_MAX / 64;
    const struct {
        size_t at;
        const void *value;
        size_t size;
        const char *what;
    } forgeries[] = {
        {blob + box_at, &whole, 24, "a box as wide as the grid"},           /* box 0 */
        {blob + box_at + 24 * 3, &nan, 4, "a NaN box"},                     /* box 3's lo.x */
        {blob + box_at + 24 * 5, &away, 24, "a box out of the grid's box"}, /* box 5 */
        {blob + slab_at + 20 * 7 + 12, &nan, 4, "a NaN slab"},              /* slab 7's lo */
        {blob + gradient_at + 24 * 9, &nan, 4, "a NaN gradient bound"},     /* gradient 9's lo.x */
        {head, &many, 8, "more boxes than leaves and patches"},             /* hull_count */
    };
    for (size_t i = 0; i < sizeof forgeries / sizeof forgeries[0]; i++) {
        memcpy(copy, bytes, size);
        memcpy(copy + forgeries[i].at, forgeries[i].value, forgeries[i].size);
        grid_tables_seal(copy, size);
        refused(copy, size, built, 1, forgeries[i].what);
    }
    /* Far cells that are not the ones this grid gets: the far bound is built. */
    memcpy(copy, bytes, size);
    int32_t cell = 8;
    memcpy(copy + blob + 8 + 4 + 4 + 8 + 8 + 8 + 24, &cell, 4);
    grid_tables_seal(copy, size);
    sdft_grid *g = open_bytes(copy, size);
    const sdft_grid_phases p = phases_of(g);
    assert_true(!p.far_stored && p.hull_stored);
    same_tables(built, g);
    sdft_grid_free(g);
    tamper_end(&t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stored_tables_are_the_built_ones),
        cmocka_unit_test(test_export_does_not_depend_on_the_hull_order),
        cmocka_unit_test(test_bake_writes_the_tables),
        cmocka_unit_test(test_damaged_tables_are_rebuilt),
        cmocka_unit_test(test_forged_tables_are_checked),
    };
    return cmocka_run_group_tests_name("grid_tables", tests, NULL, NULL);
}
