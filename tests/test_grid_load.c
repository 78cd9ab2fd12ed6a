/* sdftrace tests — NanoVDB grids in from memory (src/grid/grid_load.c): a
 * transform's rounding noise dropped, a real entry kept (against the clean
 * grid, bit for bit), and a borrowed buffer read in place (against a copy). */
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

/* A writer that inverts a diagonal map as a general matrix can leave
 * rounding noise off the inverse's diagonal: the loader drops noise that
 * small (the grid keeps the diagonal specialisation and samples as the clean
 * grid does, bit for bit), but keeps an entry that is not noise. */
static void test_inverse_map_noise_is_dropped(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *clean = bake(&f, 40, 0, NULL);
    assert_true(clean->diagonal);
    size_t size;
    const void *data = sdft_grid_data(clean, &size);
    void *copy = malloc(size);
    assert_non_null(copy);
    const double scale = (double)clean->w2i[0];
    for (int noisy = 0; noisy < 2; noisy++) {
        memcpy(copy, data, size);
        /* the inverse map's entry (2, 1), in double (what the loader reads) and in float */
        const double off = noisy ? 1e-13 * scale : 1e-3 * scale;
        unsigned char *map = (unsigned char *)copy + PNANOVDB_GRID_OFF_MAP;
        memcpy(map + PNANOVDB_MAP_OFF_INVMATD + 8 * 7, &off, sizeof off);
        const float offf = (float)off;
        memcpy(map + PNANOVDB_MAP_OFF_INVMATF + 4 * 7, &offf, sizeof offf);
        sdft_grid *g;
        char msg[256];
        assert_int_equal(tu_open_buffer(copy, size, NULL, SDFT_GRID_COPY, NULL, &g, msg, sizeof msg), 0);
        assert_int_equal(g->diagonal, noisy);
        assert_true(noisy ? g->w2i[7] == 0.0f : g->w2i[7] != 0.0f);
        if (noisy) {
            sdft_scratch s, sc;
            const sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR),
                             cf = sdft_grid_field(clean, SDFT_GRID_BOUND_FAR);
            assert_ptr_equal(gf.distance, cf.distance);
            sdft_scratch_init(&gf, &s);
            sdft_scratch_init(&cf, &sc);
            tu_rng r = tu_rng_seed(17);
            for (int i = 0; i < 2000; i++) {
                const sdft_vec3 p =
                    sdft_v3(tu_uniform(&r, -1.2f, 1.2f), tu_uniform(&r, -1.2f, 1.2f), tu_uniform(&r, -1.2f, 1.2f));
                assert_true(gf.distance(gf.ctx, &s, p) == cf.distance(cf.ctx, &sc, p));
            }
        }
        sdft_grid_free(g);
    }
    free(copy);
    sdft_grid_free(clean);
}

/* ---- borrowed buffers ----------------------------------------------------------- */

/* A renderer's own NanoVDB bytes, borrowed in place: the grid reads them
 * (its data pointer is the caller's), samples and traces exactly as a
 * copy, picks a grid of a multi-grid buffer by name, and leaves the bytes
 * to their owner when freed (they sit inside a larger allocation, so a
 * free() of them would be an error AddressSanitizer reports). */
static void test_borrowed_buffer(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *first = bake(&f, 32, 0, NULL), *second = bake(&f, 24, 1, NULL);
    size_t n1, n2;
    const void *b1 = sdft_grid_data(first, &n1), *b2 = sdft_grid_data(second, &n2);
    assert_int_equal(n1 % 32, 0);
    unsigned char *block = aligned_alloc(32, 64 + n1 + n2);
    assert_non_null(block);
    unsigned char *mine = block + 64;
    memcpy(mine, b1, n1);
    memcpy(mine + n1, b2, n2);
    /* Grid names: both "sdf"; rename the second in its header to pick it. */
    memcpy(mine + n1 + PNANOVDB_GRID_OFF_GRID_NAME, "second", 7);

    char msg[256];
    sdft_grid *lent = NULL, *lent2 = NULL;
    assert_int_equal(tu_open_buffer(mine, n1 + n2, NULL, SDFT_GRID_BORROW, NULL, &lent, msg, sizeof msg), SDFT_OK);
    assert_int_equal(tu_open_buffer(mine, n1 + n2, "second", SDFT_GRID_BORROW, NULL, &lent2, msg, sizeof msg), SDFT_OK);
    size_t got;
    assert_ptr_equal(sdft_grid_data(lent, &got), mine);
    assert_int_equal(got, n1);
    assert_ptr_equal(sdft_grid_data(lent2, &got), mine + n1);
    assert_string_equal(sdft_grid_name(lent2), "second");
    same_voxels(first, lent);
    same_voxels(second, lent2);

    sdft_field fc = sdft_grid_field(first, SDFT_GRID_BOUND_FAR), fl = sdft_grid_field(lent, SDFT_GRID_BOUND_FAR);
    sdft_scratch sc, sl;
    sdft_scratch_init(&fc, &sc);
    sdft_scratch_init(&fl, &sl);
    const sdft_trace_params p = sdft_trace_defaults();
    tu_rng r = tu_rng_seed(21);
    int hits = 0;
    for (int i = 0; i < 200; i++) {
        sdft_vec3 d = sdft_normalize(sdft_v3(tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)));
        sdft_ray ray = {.org = sdft_scale(d, -3.0f), .tnear = 0, .dir = d, .tfar = INFINITY};
        ray.org.x += tu_uniform(&r, -0.3f, 0.3f);
        sdft_hit hc = sdft_trace(&fc, &sc, &ray, &p), hl = sdft_trace(&fl, &sl, &ray, &p);
        assert_memory_equal(&hc, &hl, sizeof hc);
        hits += hc.status == SDFT_HIT;
    }
    assert_true(hits > 100);
    sdft_grid_free(lent);
    sdft_grid_free(lent2);
    assert_memory_equal(mine, b1, n1); /* untouched, still the caller's */
    free(block);
    sdft_grid_free(first);
    sdft_grid_free(second);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_inverse_map_noise_is_dropped),
        cmocka_unit_test(test_borrowed_buffer),
    };
    return cmocka_run_group_tests_name("grid_load", tests, NULL, NULL);
}
