/* sdftrace tests — deferred leaves (src/grid/grid_deferred.c): voxels,
 * samples, renders and bytes against the whole load, leaves filled once and
 * a failing fill counted, and every refusal. */
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
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/sdf.h"
#include "sdftrace/vdb.h"
#include "testutil.h"

/* ---- deferred leaves --------------------------------------------------------------- */

/* A .vdb opened with deferred leaves (sdft_grid_options.defer) reads nothing
 * of a leaf until something samples it, and then reads exactly what the
 * whole load holds: every voxel equal, trilinear samples equal, renders
 * (2 threads filling leaves at once) equal within a thousandth of a voxel
 * and with the same hits, the far bound never larger than the whole
 * grid's (it counts unread leaves as occupied), and once every leaf is
 * filled (sdft_grid_data) the very same bytes, float and Fp16. */
static void test_deferred_leaves_match_whole_load(void **state)
{
    (void)state;
    char path[512], msg[256];
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    tu_tmp(path, sizeof path, "deferred.vdb");
    remove(path);
    static const sdft_quant quants[2] = {SDFT_QUANT_NONE, SDFT_QUANT_FP16};
    for (int q = 0; q < 2; q++) {
        sdft_grid *g[2] = {NULL, NULL}; /* whole, deferred */
        sdft_grid_options loaded = sdft_grid_options_defaults(), deferred = loaded;
        deferred.defer = 2; /* always: a grid this small would otherwise load whole (below) */
        open_figure_twice("deferred.vdb", 160, quants[q], loaded, deferred, path, sizeof path, g);
        uint64_t leaves, filled, failed, whole_leaves, whole_filled;
        sdft_grid_leaf_counts(g[0], &whole_leaves, &whole_filled, &failed);
        assert_int_equal(whole_filled, whole_leaves);
        assert_int_equal(failed, 0);
        sdft_grid_leaf_counts(g[1], &leaves, &filled, &failed);
        assert_int_equal(leaves, whole_leaves);
        assert_true(leaves > 1000);
        assert_int_equal(filled, 0); /* loading read no leaf */
        assert_int_equal(sdft_grid_size(g[1]), sdft_grid_size(g[0]));

        /* Samples from two threads at once, against the whole grid's. */
        enum { N = 20000 };
        static sdft_vec3 p[N];
        static float whole[N], whole_none[N];
        static int whole_level[N];
        tu_rng r = tu_rng_seed(77);
        sdft_scratch s0;
        sdft_field f0 = sdft_grid_field(g[0], SDFT_GRID_BOUND_FAR);
        sdft_scratch_init(&f0, &s0);
        for (int i = 0; i < N; i++) {
            p[i] = sdft_v3(tu_uniform(&r, sc->field.bounds.lo.x, sc->field.bounds.hi.x),
                           tu_uniform(&r, sc->field.bounds.lo.y, sc->field.bounds.hi.y),
                           tu_uniform(&r, sc->field.bounds.lo.z, sc->field.bounds.hi.z));
            whole[i] = sdft_grid_sample(g[0], SDFT_GRID_BOUND_FAR, &s0, p[i], &whole_level[i]);
            whole_none[i] = sdft_grid_sample(g[0], SDFT_GRID_BOUND_NONE, &s0, p[i], NULL);
        }
        int bad = 0;
        const sdft_field f1 = sdft_grid_field(g[1], SDFT_GRID_BOUND_FAR);
#pragma omp parallel num_threads(2) reduction(+ : bad)
        {
            sdft_scratch s1;
            sdft_scratch_init(&f1, &s1);
#pragma omp for schedule(dynamic, 64)
            for (int i = 0; i < N; i++) {
                int level;
                const float v = sdft_grid_sample(g[1], SDFT_GRID_BOUND_FAR, &s1, p[i], &level);
                const float none = sdft_grid_sample(g[1], SDFT_GRID_BOUND_NONE, &s1, p[i], NULL);
                bad += none != whole_none[i]; /* the same voxels, the same interpolant */
                /* A looser far bound: on the same side, and never above the whole grid's bounds (its
                 * trilinear band values, level 0, are no bounds to compare with). */
                bad += level == 5 &&
                       ((v < 0.0f) != (whole[i] < 0.0f) || (whole_level[i] != 0 && fabsf(v) > fabsf(whole[i])));
            }
        }
        assert_int_equal(bad, 0);
        sdft_grid_leaf_counts(g[1], NULL, &filled, NULL);
        print_message("%s: %llu of %llu leaves read by %d samples\n", sdft_grid_type_name(g[1]),
                      (unsigned long long)filled, (unsigned long long)leaves, N);
        assert_true(filled > 0 && filled < leaves);

        /* A render with two threads filling leaves as its rays reach them. */
        sdft_render_params rp = sdft_render_defaults();
        rp.width = 160, rp.height = 90, rp.threads = 2, rp.camera = sc->camera, rp.light = sc->light;
        sdft_image img[2];
        sdft_render_stats st[2];
        for (int d = 0; d < 2; d++) {
            const sdft_field f = sdft_grid_field(g[d], SDFT_GRID_BOUND_FAR);
            assert_int_equal(sdft_image_alloc(&img[d], rp.width, rp.height, msg, sizeof msg), 0);
            assert_int_equal(sdft_render(&f, &rp, &img[d], &st[d], msg, sizeof msg), 0);
        }
        const float voxel = sdft_grid_voxel_size(g[0]).x;
        assert_true(st[0].hits > 1000);
        assert_int_equal(st[1].hits, st[0].hits);
        for (int i = 0; i < rp.width * rp.height; i++) {
            assert_int_equal(img[1].status[i], img[0].status[i]);
            if (img[0].status[i] == SDFT_HIT && !(fabsf(img[1].depth[i] - img[0].depth[i]) <= 1e-3f * voxel))
                fail_msg("pixel %d: depth %g deferred, %g whole", i, img[1].depth[i], img[0].depth[i]);
        }
        sdft_image_free(&img[0]);
        sdft_image_free(&img[1]);

        /* Every leaf filled: the bytes of the whole load. */
        size_t n0, n1;
        const void *b0 = sdft_grid_data(g[0], &n0), *b1 = sdft_grid_data(g[1], &n1);
        sdft_grid_leaf_counts(g[1], NULL, &filled, &failed);
        assert_int_equal(filled, leaves);
        assert_int_equal(failed, 0);
        assert_int_equal(n1, n0);
        assert_memory_equal(b1, b0, n0);
        same_voxels(g[0], g[1]);
        sdft_grid_free(g[0]);
        sdft_grid_free(g[1]);
    }
    remove(path);
}

/* Deferring where it is exact (sdft_grid_options.defer 1, render's way): a
 * level set this small has far-bound cells narrower than a leaf, so it is
 * filled whole at load, and a render counts exactly what the whole load's
 * counts. An unknown way to defer is refused. */
static void test_deferred_where_exact_loads_small_grids_whole(void **state)
{
    (void)state;
    char path[512], msg[256];
    sdft_grid *g[2] = {NULL, NULL}; /* whole, deferred where exact */
    sdft_grid_options loaded = sdft_grid_options_defaults(), deferred = loaded;
    deferred.defer = 1;
    open_figure_twice("deferred-exact.vdb", 96, SDFT_QUANT_NONE, loaded, deferred, path, sizeof path, g);
    uint64_t leaves, filled, failed;
    sdft_grid_leaf_counts(g[1], &leaves, &filled, &failed);
    assert_true(leaves > 100);
    assert_int_equal(filled, leaves);
    assert_int_equal(failed, 0);
    const sdft_scene *sc = sdft_scene_find("figure");
    sdft_render_params rp = sdft_render_defaults();
    rp.width = 96, rp.height = 54, rp.threads = 2, rp.camera = sc->camera, rp.light = sc->light;
    sdft_render_stats st[2];
    for (int d = 0; d < 2; d++) {
        sdft_image img;
        const sdft_field f = sdft_grid_field(g[d], SDFT_GRID_BOUND_FAR);
        assert_int_equal(sdft_image_alloc(&img, rp.width, rp.height, msg, sizeof msg), 0);
        assert_int_equal(sdft_render(&f, &rp, &img, &st[d], msg, sizeof msg), 0);
        sdft_image_free(&img);
    }
    assert_true(st[0].hits > 100);
    assert_int_equal(st[1].steps, st[0].steps);
    assert_int_equal(st[1].cone_steps, st[0].cone_steps);
    assert_int_equal(st[1].hits, st[0].hits);
    sdft_grid_free(g[0]);
    sdft_grid_free(g[1]);
    sdft_grid *none = NULL;
    deferred.defer = 3;
    assert_int_equal(tu_open_with(path, NULL, &deferred, &none, msg, sizeof msg), SDFT_EINVAL);
    assert_null(none);
    remove(path);
}

/* The rule a loader asks before it reads leaves (sdft_grid_defers): with
 * SDFT_DEFER_WHERE_EXACT, a level set is filled at load while its far
 * bound's cells are 4 voxels (at most 2^24 of them over the box: a box of
 * 1024^3 voxels, 256^3 cells), and deferred once they must be wider (one
 * voxel more: 257 x 256 x 256 cells); anything but a level set with a
 * positive background is deferred; NONE never, ALWAYS always. */
static void test_defer_rule(void **state)
{
    (void)state;
    const int32_t lo[3] = {-512, -512, -512}, hi[3] = {511, 511, 511}, wider[3] = {512, 511, 511};
    assert_int_equal(sdft_grid_defers(SDFT_DEFER_WHERE_EXACT, 1, 0.1f, lo, hi), 0);
    assert_int_equal(sdft_grid_defers(SDFT_DEFER_WHERE_EXACT, 1, 0.1f, lo, wider), 1);
    assert_int_equal(sdft_grid_defers(SDFT_DEFER_WHERE_EXACT, 0, 0.1f, lo, hi), 1);
    assert_int_equal(sdft_grid_defers(SDFT_DEFER_WHERE_EXACT, 1, 0.0f, lo, hi), 1);
    assert_int_equal(sdft_grid_defers(SDFT_DEFER_NONE, 1, 0.1f, lo, wider), 0);
    assert_int_equal(sdft_grid_defers(SDFT_DEFER_ALWAYS, 1, 0.1f, lo, hi), 1);
}

/* What a deferred grid's loader is handed: a reference grid's bytes to
 * copy leaves from, the leaf whose read fails, and a count of fills per
 * leaf. */
typedef struct fill_source {
    const unsigned char *bytes;
    uint64_t first, stride, failing;
    int *calls;
    int released;
} fill_source;

static int fill_from(void *user, uint64_t index, void *leaf)
{
    fill_source *src = user;
    __atomic_add_fetch(&src->calls[index], 1, __ATOMIC_RELAXED);
    memcpy(leaf, src->bytes + src->first + index * src->stride, src->stride);
    if (index != src->failing)
        return 0;
    float *values = (float *)((unsigned char *)leaf + PNANOVDB_GRID_TYPE_GET(PNANOVDB_GRID_TYPE_FLOAT, leaf_off_table));
    for (int i = 0; i < 512; i++)
        values[i] = NAN; /* as a loader writes a leaf it cannot read */
    return 1;
}

static void release_source(void *user) { ((fill_source *)user)->released++; }

/* A 64-byte aligned copy of n bytes, for a grid to adopt (release_buffer frees it). */
static unsigned char *aligned_copy(const unsigned char *bytes, size_t n)
{
    unsigned char *copy = aligned_alloc(64, (n + 63) & ~(size_t)63);
    assert_non_null(copy);
    memcpy(copy, bytes, n);
    return copy;
}
static int released_buffers;
static void release_buffer(void *data) { free(data), released_buffers++; }

/* sdft_grid_open adopting buf, n bytes, whose leaves fill fills from user
 * as `how` defers them; release_buffer and release_source release them. */
static sdft_error open_deferred(void *buf, size_t n, sdft_leaf_fill_fn fill, void *user, sdft_defer how, sdft_grid **g,
                                char *msg, size_t msg_len)
{
    sdft_grid_options o = sdft_grid_options_defaults();
    o.data = buf, o.size = n, o.memory = SDFT_GRID_ADOPT, o.release = release_buffer;
    o.fill = fill, o.fill_user = user, o.fill_release = release_source, o.defer = how;
    return sdft_grid_open(&o, g, msg, msg_len);
}

/* Deferred leaves from C: a buffer whose leaves are garbage until
 * filled; each leaf filled exactly once however many threads read it; a
 * leaf whose fill fails reads NaN and is counted; the rest read as the
 * reference; the loader's user released once, with the grid or on a
 * refusal. */
static void test_deferred_fill_and_failure(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *ref = bake(&f, 64, 0, NULL);
    size_t n;
    const unsigned char *bytes = sdft_grid_data(ref, &n);
    uint64_t leaves;
    sdft_grid_leaf_counts(ref, &leaves, NULL, NULL);
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(ref->buf, ref->grid);
    fill_source src = {.bytes = bytes,
                       .first = PNANOVDB_GRID_SIZE + pnanovdb_tree_get_node_offset_leaf(ref->buf, tree),
                       .stride = PNANOVDB_GRID_TYPE_GET(PNANOVDB_GRID_TYPE_FLOAT, leaf_size),
                       .failing = leaves / 2,
                       .calls = calloc(leaves, sizeof(int))};
    assert_non_null(src.calls);
    unsigned char *buf = aligned_copy(bytes, n);
    memset(buf + src.first, 0xA5, n - src.first); /* the leaves: not there yet */
    char msg[256];
    sdft_grid *g = NULL;
    released_buffers = 0;
    assert_int_equal(open_deferred(buf, n, fill_from, &src, SDFT_DEFER_ALWAYS, &g, msg, sizeof msg), SDFT_OK);
    uint64_t filled, failed;
    sdft_grid_leaf_counts(g, NULL, &filled, &failed);
    assert_int_equal(filled, 0);

    /* The failing leaf's voxels read NaN; every other voxel as the reference. */
    const uint64_t at = src.first + src.failing * src.stride;
    /* Its first active voxel, in the leaf whose voxels go NaN. */
    const pnanovdb_coord_t origin = pnanovdb_leaf_get_bbox_min(ref->buf, (pnanovdb_leaf_handle_t){{at}});
    int32_t lo[3], hi[3];
    sdft_grid_index_bounds(ref, lo, hi);
    int bad = 0, nan_voxels = 0, in_leaf = 0;
#pragma omp parallel for num_threads(2) reduction(+ : bad, nan_voxels, in_leaf) schedule(dynamic, 1)
    for (int32_t k = lo[2] - 1; k <= hi[2] + 1; k++)
        for (int32_t j = lo[1] - 1; j <= hi[1] + 1; j++)
            for (int32_t i = lo[0] - 1; i <= hi[0] + 1; i++) {
                const float v = sdft_grid_voxel(g, i, j, k, NULL), want = sdft_grid_voxel(ref, i, j, k, NULL);
                const int in_failing =
                    (i & ~7) == (origin.x & ~7) && (j & ~7) == (origin.y & ~7) && (k & ~7) == (origin.z & ~7);
                in_leaf += in_failing;
                nan_voxels += in_failing && isnan(v);
                bad += in_failing ? !isnan(v) : v != want;
            }
    assert_int_equal(bad, 0);
    assert_true(in_leaf > 0);
    assert_int_equal(nan_voxels, in_leaf);
    sdft_grid_leaf_counts(g, NULL, &filled, &failed);
    assert_int_equal(filled, leaves);
    assert_int_equal(failed, 1);
    for (uint64_t i = 0; i < leaves; i++)
        assert_int_equal(src.calls[i], 1);
    assert_int_equal(src.released, 0);
    sdft_grid_free(g);
    assert_int_equal(src.released, 1);
    assert_int_equal(released_buffers, 1);

    /* Refusals release what they were given, once. */
    assert_int_equal(open_deferred(aligned_copy(bytes, n), n, NULL, &src, SDFT_DEFER_ALWAYS, &g, msg, sizeof msg),
                     SDFT_EINVAL);
    assert_null(g);
    assert_int_equal(src.released, 2);
    assert_int_equal(released_buffers, 2);
    assert_int_equal(open_deferred(aligned_copy(bytes, n), n, fill_from, &src, (sdft_defer)7, &g, msg, sizeof msg),
                     SDFT_EINVAL);
    assert_int_equal(src.released, 3);
    assert_int_equal(released_buffers, 3);
    unsigned char *bad_bytes = aligned_alloc(64, 64);
    assert_non_null(bad_bytes);
    memset(bad_bytes, 0, 64);
    assert_int_equal(open_deferred(bad_bytes, 64, fill_from, &src, SDFT_DEFER_ALWAYS, &g, msg, sizeof msg),
                     SDFT_EFORMAT);
    assert_int_equal(src.released, 4);
    assert_int_equal(released_buffers, 4);
    free(src.calls);
    sdft_grid_free(ref);

    /* Deferred leaves need a streamed float or Fp16 grid. */
    char path[512];
    tu_tmp(path, sizeof path, "deferred-errors.vdb");
    sdft_grid_free(bake(&f, 24, 0, path));
    sdft_grid_options o = sdft_grid_options_defaults();
    o.defer = 1;
    o.quant = SDFT_QUANT_FP8;
    assert_int_equal(tu_open_with(path, NULL, &o, &g, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "deferred"));
    o.quant = SDFT_QUANT_NONE, o.stream = 0;
    assert_int_equal(tu_open_with(path, NULL, &o, &g, msg, sizeof msg), SDFT_EINVAL);
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_deferred_leaves_match_whole_load),
        cmocka_unit_test(test_deferred_fill_and_failure),
        cmocka_unit_test(test_deferred_where_exact_loads_small_grids_whole),
        cmocka_unit_test(test_defer_rule),
    };
    return cmocka_run_group_tests_name("grid_deferred", tests, NULL, NULL);
}
