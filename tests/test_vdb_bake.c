/* sdftrace tests — baking a field (src/vdb/bake.cpp): every bad input refused
 * with a reason and no file written. */
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

static void test_bake_errors(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_bake_params p = sdft_bake_defaults();
    char msg[256], path[512];
    tu_tmp(path, sizeof path, "never.vdb");
    remove(path);
    p.res = 0;
    assert_int_not_equal(sdft_bake(&f, &p, path, NULL, NULL, msg, sizeof msg), 0);
    assert_non_null(strstr(msg, "resolution"));
    p.res = 1025;
    assert_int_not_equal(sdft_bake(&f, &p, path, NULL, NULL, msg, sizeof msg), 0);
    p.res = 16;
    assert_int_not_equal(sdft_bake(&f, &p, "/nonexistent-dir/x.vdb", NULL, NULL, msg, sizeof msg), 0);
    assert_non_null(strstr(msg, "cannot write"));
    assert_int_not_equal(sdft_bake(&f, &p, tu_tmp(path, sizeof path, "x.exr"), NULL, NULL, msg, sizeof msg), 0);
    assert_false(tu_file_exists(path));
    /* A box holding no surface bakes nothing, and says so. */
    sdft_field far = f;
    far.bounds = (sdft_aabb){{5, 5, 5}, {6, 6, 6}};
    tu_tmp(path, sizeof path, "never.vdb");
    assert_int_equal(sdft_bake(&far, &p, path, NULL, NULL, msg, sizeof msg), SDFT_EEMPTY);
    assert_false(tu_file_exists(path));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bake_errors),
    };
    return cmocka_run_group_tests_name("vdb_bake", tests, NULL, NULL);
}
