/* sdftrace tests — the leaf directory (src/grid/grid_leaves.c): its entries
 * against PNanoVDB's accessor, and the field read through it against the
 * same grid without it, bit for bit, for float and quantized grids (these
 * also against the float grid, within their codes' error). */
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

/* The field read through the leaf directory is the accessor's, bit for
 * bit: at random points of box b, the values (unbounded and with the tree
 * bound) and normals of g equal those of g with its directory taken away.
 * Returns how many points lay in the band. */
static int same_without_directory(sdft_grid *g, sdft_aabb b)
{
    sdft_scratch s;
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_scratch_init(&gf, &s);
    enum { N = 20000 };
    static float value[2][2][N];
    static sdft_vec3 normal[2][N];
    const grid_leaves directory = g->leaves;
    int in_leaves = 0;
    for (int pass = 0; pass < 2; pass++) {
        g->leaves.top = pass == 0 ? directory.top : NULL;
        tu_rng r = tu_rng_seed(11);
        for (int i = 0; i < N; i++) {
            sdft_vec3 p =
                sdft_v3(tu_uniform(&r, b.lo.x, b.hi.x), tu_uniform(&r, b.lo.y, b.hi.y), tu_uniform(&r, b.lo.z, b.hi.z));
            int level;
            value[pass][0][i] = sdft_grid_sample(g, SDFT_GRID_BOUND_NONE, &s, p, &level);
            value[pass][1][i] = sdft_grid_sample(g, SDFT_GRID_BOUND_TREE, &s, p, NULL);
            normal[pass][i] = sdft_field_normal(&gf, &s, p);
            in_leaves += pass == 0 && level == 0 && fabsf(value[0][0][i]) < sdft_grid_background(g);
        }
    }
    g->leaves = directory;
    for (int i = 0; i < N; i++) {
        if (!(value[0][0][i] == value[1][0][i]) || !(value[0][1][i] == value[1][1][i]))
            fail_msg("%s grid, point %d: %.9g / %.9g through the directory, %.9g / %.9g through the accessor",
                     sdft_grid_type_name(g), i, value[0][0][i], value[0][1][i], value[1][0][i], value[1][1][i]);
        assert_memory_equal(&normal[0][i], &normal[1][i], sizeof(sdft_vec3));
    }
    assert_true(in_leaves > 1000);
    return in_leaves;
}

/* The leaf directory (grid_leaves.c) holds every leaf of the tree where
 * it belongs, apron included, and marks the +-background tiles of lower
 * nodes beside them; and the field read through it is the
 * accessor's, bit for bit: the same grid with its directory taken away
 * gives the same values and normals. */
static void test_leaf_directory_matches_accessor(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 96, 0, NULL);
    assert_non_null(g->leaves.top);
    /* Every block of every chunk, against the tree: an entry is the value
     * table of the leaf holding that block, 0 where the tree has none. */
    const grid_leaves *d = &g->leaves;
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(&acc, g->root);
    size_t entries = 0, own = 0, tiles = 0;
    for (int rz = 0; rz < d->nr[2]; rz++)
        for (int ry = 0; ry < d->nr[1]; ry++)
            for (int rx = 0; rx < d->nr[0]; rx++) {
                const uint32_t c = d->top[((size_t)rz * d->nr[1] + ry) * d->nr[0] + rx];
                if (!c)
                    continue;
                for (int l = 0; l < GRID_CHUNK_ENTRIES; l++) {
                    const int lx = l % 9, ly = l / 9 % 9, lz = l / 81;
                    pnanovdb_coord_t ijk = {((d->r0[0] + rx) * 8 + lx) * 8, ((d->r0[1] + ry) * 8 + ly) * 8,
                                            ((d->r0[2] + rz) * 8 + lz) * 8};
                    uint32_t level;
                    pnanovdb_address_t a =
                        pnanovdb_readaccessor_get_value_address_and_level(g->type, g->buf, &acc, &ijk, &level);
                    const float tile = pnanovdb_read_float(g->buf, a), bg = sdft_grid_background(g);
                    const uint32_t want = level == 0 ? (uint32_t)((acc.leaf.address.byte_offset + 96u) / 4u)
                                          : level == 1 && tile == bg  ? (uint32_t)GRID_TILE_POSITIVE
                                          : level == 1 && tile == -bg ? (uint32_t)GRID_TILE_NEGATIVE
                                                                      : 0u;
                    assert_int_equal(d->chunk[(size_t)(c - 1) * GRID_CHUNK_ENTRIES + l], want);
                    entries += level == 0;
                    own += level == 0 && lx < 8 && ly < 8 && lz < 8;
                    tiles += want == GRID_TILE_POSITIVE || want == GRID_TILE_NEGATIVE;
                }
            }
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(g->buf, g->grid);
    assert_int_equal(own, pnanovdb_tree_get_node_count_leaf(g->buf, tree));
    assert_true(entries > own); /* the aprons hold some too */
    assert_true(tiles > own);   /* and the tiles beside the leaves are marked */

    same_without_directory(g, sc->field.bounds);
    sdft_grid_free(g);
}

/* Quantized grids (NanoVDB's Fp16, Fp8, Fp4 and variable-rate FpN leaves,
 * made by its own converter from a baked .vdb) sample within their codes'
 * error of the float grid. A leaf of FpB codes its values as min + k q,
 * q = (max - min) / (2^B - 1), rounded to the nearest k, so each is off by
 * at most q / 2, and a level set's leaf spans at most twice the background;
 * trilinear weights sum to 1, so the sample is off by no more. Fp16 is a
 * half float: relative error 2^-11. FpN picks each leaf's bit depth to meet
 * NanoVDB's default tolerance for level sets, a tenth of a voxel
 * (OpenToNanoVDB.h). Each renders the float grid's picture too. */
static void test_quantized_grids(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    char path[512], msg[256];
    tu_tmp(path, sizeof path, "quantized.vdb");
    remove(path);
    sdft_grid *ref = bake(&sc->field, 64, 0, path);
    const float bg = sdft_grid_background(ref), h = sdft_grid_voxel_size(ref).x;
    const struct {
        sdft_quant quant;
        const char *type;
        float error; /* most a sample may be off, world units */
    } kinds[] = {
        {SDFT_QUANT_FP16, "fp16", bg / 2048.0f},
        {SDFT_QUANT_FP8, "fp8", bg / 255.0f},
        {SDFT_QUANT_FP4, "fp4", bg / 15.0f},
        {SDFT_QUANT_FPN, "fpN", 0.1f * h},
    };
    sdft_render_params rp = sdft_render_defaults();
    rp.width = 160, rp.height = 90, rp.camera = sc->camera, rp.light = sc->light, rp.shadows = 0;
    sdft_image want, got;
    assert_int_equal(sdft_image_alloc(&want, rp.width, rp.height, NULL, 0), 0);
    assert_int_equal(sdft_image_alloc(&got, rp.width, rp.height, NULL, 0), 0);
    sdft_field rf = sdft_grid_field(ref, SDFT_GRID_BOUND_FAR);
    assert_int_equal(sdft_render(&rf, &rp, &want, NULL, msg, sizeof msg), 0);
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        sdft_grid *q = NULL;
        int rc = tu_open_file(path, NULL, kinds[k].quant, &q, msg, sizeof msg);
        if (rc)
            print_error("%s\n", msg);
        assert_int_equal(rc, 0);
        assert_string_equal(sdft_grid_type_name(q), kinds[k].type);
        /* Fp16, Fp8 and Fp4 leaves are read through the directory. */
        assert_true((q->leaves.top != NULL) == (kinds[k].quant != SDFT_QUANT_FPN));
        same_without_directory(q, sc->field.bounds);
        sdft_scratch s, sq;
        sdft_field qf = sdft_grid_field(q, SDFT_GRID_BOUND_FAR);
        sdft_scratch_init(&rf, &s);
        sdft_scratch_init(&qf, &sq);
        tu_rng r = tu_rng_seed(12);
        float worst = 0.0f;
        int checked = 0;
        for (int i = 0; i < 20000; i++) {
            sdft_vec3 p = sdft_v3(tu_uniform(&r, sc->field.bounds.lo.x, sc->field.bounds.hi.x),
                                  tu_uniform(&r, sc->field.bounds.lo.y, sc->field.bounds.hi.y),
                                  tu_uniform(&r, sc->field.bounds.lo.z, sc->field.bounds.hi.z));
            int la, lb;
            float a = sdft_grid_sample(ref, SDFT_GRID_BOUND_NONE, &s, p, &la);
            float b = sdft_grid_sample(q, SDFT_GRID_BOUND_NONE, &sq, p, &lb);
            if (la != 0 || lb != 0)
                continue;
            checked++;
            const float allowed = kinds[k].error + 1e-6f;
            worst = fmaxf(worst, fabsf(a - b));
            if (fabsf(a - b) > allowed)
                fail_msg("%s: %g against %g at (%g, %g, %g), more than %g", kinds[k].type, b, a, p.x, p.y, p.z,
                         allowed);
        }
        print_message("%s: worst sample error %g voxels over %d points\n", kinds[k].type, worst / h, checked);
        assert_true(checked > 1000);
        assert_true(worst > 0.0f || kinds[k].quant == SDFT_QUANT_FP16); /* quantized for real */
        assert_int_equal(sdft_render(&qf, &rp, &got, NULL, msg, sizeof msg), 0);
        size_t both = 0, close = 0, one = 0;
        for (size_t i = 0; i < (size_t)rp.width * rp.height; i++) {
            const int hw = isfinite(want.depth[i]), hg = isfinite(got.depth[i]);
            both += hw && hg;
            close += hw && hg && fabsf(want.depth[i] - got.depth[i]) <= 1.5f * h;
            one += hw != hg;
        }
        print_message("%s: %zu of %zu depths within 1.5 voxels, %zu pixels hit by one only\n", kinds[k].type, close,
                      both, one);
        assert_true(both > 1000);
        assert_true(close >= 0.99 * both);
        assert_true(one <= 0.005 * rp.width * rp.height);
        sdft_grid_free(q);
    }
    sdft_image_free(&want);
    sdft_image_free(&got);
    sdft_grid_free(ref);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_leaf_directory_matches_accessor),
        cmocka_unit_test(test_quantized_grids),
    };
    return cmocka_run_group_tests_name("grid_leaves", tests, NULL, NULL);
}
