/* sdftrace tests — the README's C example compiles, runs and finds the
 * torus; and the README shows exactly this code, so neither can rot. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "testutil.h"

#define main readme_example_main
#include "readme_example.c"
#undef main

static void test_example_runs(void **state)
{
    (void)state;
    assert_int_equal(readme_example_main(), 0);
}

static void test_readme_shows_the_example(void **state)
{
    (void)state;
    assert_true(tu_readme_shows("tests/readme_example.c"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_example_runs),
        cmocka_unit_test(test_readme_shows_the_example),
    };
    return cmocka_run_group_tests_name("readme_example", tests, NULL, NULL);
}
