/* sdftrace tests — a .vdb streamed into NanoVDB leaf by leaf
 * (src/vdb/vdb_stream.cpp), against NanoVDB's own converter. */
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

/* A .vdb streamed into NanoVDB leaf by leaf (vdb_stream.cpp, the default)
 * is the grid NanoVDB's own converter makes of it: the same voxels and
 * active states everywhere (tiles and background included), as float and
 * as Fp16 (the same codes), and the same samples. A grid of several
 * thousand leaves, so that the stream runs in several batches. */
static void test_streamed_load_matches_nanovdb_converter(void **state)
{
    (void)state;
    char path[512];
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    tu_tmp(path, sizeof path, "streamed.vdb");
    remove(path);
    static const sdft_quant quants[2] = {SDFT_QUANT_NONE, SDFT_QUANT_FP16};
    for (int q = 0; q < 2; q++) {
        sdft_grid *g[2] = {NULL, NULL}; /* converted, streamed */
        sdft_grid_options converted = sdft_grid_options_defaults(), streamed = converted;
        converted.stream = 0;
        open_figure_twice("streamed.vdb", 256, quants[q], converted, streamed, path, sizeof path, g);
        pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(g[1]->buf, g[1]->grid);
        print_message("%s: %llu leaves, %zu bytes streamed, %zu converted\n", sdft_grid_type_name(g[1]),
                      (unsigned long long)pnanovdb_tree_get_node_count_leaf(g[1]->buf, tree), g[1]->size, g[0]->size);
        assert_true(pnanovdb_tree_get_node_count_leaf(g[1]->buf, tree) > 2048);
        assert_string_equal(sdft_grid_type_name(g[1]), sdft_grid_type_name(g[0]));
        assert_int_equal(g[1]->size, g[0]->size);
        assert_string_equal(sdft_grid_name(g[1]), sdft_grid_name(g[0]));
        assert_memory_equal(g[1]->w2i, g[0]->w2i, sizeof g[0]->w2i);
        same_voxels(g[0], g[1]);
        sdft_scratch s0, s1;
        sdft_field f0 = sdft_grid_field(g[0], SDFT_GRID_BOUND_FAR), f1 = sdft_grid_field(g[1], SDFT_GRID_BOUND_FAR);
        sdft_scratch_init(&f0, &s0);
        sdft_scratch_init(&f1, &s1);
        tu_rng r = tu_rng_seed(31);
        for (int i = 0; i < 20000; i++) {
            sdft_vec3 p = sdft_v3(tu_uniform(&r, sc->field.bounds.lo.x, sc->field.bounds.hi.x),
                                  tu_uniform(&r, sc->field.bounds.lo.y, sc->field.bounds.hi.y),
                                  tu_uniform(&r, sc->field.bounds.lo.z, sc->field.bounds.hi.z));
            assert_true(f0.distance(f0.ctx, &s0, p) == f1.distance(f1.ctx, &s1, p));
        }
        sdft_grid_free(g[0]);
        sdft_grid_free(g[1]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_streamed_load_matches_nanovdb_converter),
    };
    return cmocka_run_group_tests_name("vdb_stream", tests, NULL, NULL);
}
