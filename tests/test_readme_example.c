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

#define main readme_example_main
#include "readme_example.c"
#undef main

/* The whole of a file, NUL-terminated; NULL if unreadable. */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    size_t got = fread(s, 1, (size_t)n, f);
    s[got] = '\0';
    fclose(f);
    return s;
}

static void test_example_runs(void **state)
{
    (void)state;
    assert_int_equal(readme_example_main(), 0);
}

static void test_readme_shows_the_example(void **state)
{
    (void)state;
    /* This file sits in ROOT/tests/; the README in ROOT. */
    char root[4096], path[4200];
    snprintf(root, sizeof root, "%s", __FILE__);
    char *cut = strstr(root, "tests/test_readme_example.c");
    assert_non_null(cut);
    if (cut == root)
        strcpy(root, "./");
    else
        *cut = '\0';
    snprintf(path, sizeof path, "%s/README.md", root);
    char *readme = slurp(path);
    snprintf(path, sizeof path, "%s/tests/readme_example.c", root);
    char *example = slurp(path);
    assert_non_null(readme);
    assert_non_null(example);
    assert_non_null(strstr(readme, example));
    free(readme);
    free(example);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_example_runs),
        cmocka_unit_test(test_readme_shows_the_example),
    };
    return cmocka_run_group_tests_name("readme_example", tests, NULL, NULL);
}
