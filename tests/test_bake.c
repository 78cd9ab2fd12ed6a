/* sdftrace tests — `sdftrace bake` and `render --grid` from the command line:
 * outputs OpenVDB's and NanoVDB's own tools accept, and every bad input as
 * one line, a non-zero exit and no file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "sdftrace/config.h"
#include "testutil.h"

static char out[16384];

static void test_help(void **state)
{
    (void)state;
    assert_int_equal(tu_run(out, sizeof out, "%s bake --help", SDFT_CLI), 0);
    assert_non_null(strstr(out, "--band"));
    assert_non_null(strstr(out, "--full"));
    assert_non_null(strstr(out, "--fp16"));
    assert_non_null(strstr(out, "--quiet"));
    assert_int_equal(tu_run(out, sizeof out, "%s --help", SDFT_CLI), 0);
    assert_non_null(strstr(out, "bake"));
    assert_int_equal(tu_run(out, sizeof out, "%s render --help", SDFT_CLI), 0);
    assert_non_null(strstr(out, "--grid FILE"));
}

/* A bad command line: non-zero, one line naming the problem, no file. */
static void bad(const char *args, const char *file, const char *needle)
{
    char path[512];
    tu_tmp(path, sizeof path, file);
    remove(path);
    int rc = tu_run(out, sizeof out, "%s bake %s -o %s", SDFT_CLI, args, path);
    print_message("bake %s -> %d: %s", args, rc, out);
    assert_int_not_equal(rc, 0);
    assert_int_equal(tu_lines(out), 1);
    assert_non_null(strstr(out, needle));
    assert_false(tu_file_exists(path));
}

static void test_bad_input(void **state)
{
    (void)state;
    bad("--scene temple --res 0", "a.vdb", "--res");
    bad("--scene temple --res 1025", "a.vdb", "--res");
    bad("--scene temple --res 12x", "a.vdb", "--res");
    bad("--scene nosuch --res 16", "a.vdb", "unknown scene");
    bad("--scene temple --res 16", "a.exr", ".vdb or .nvdb");
    bad("--scene temple --res 16 --band 2 --full", "a.vdb", "exclude");
    bad("--scene temple --res 16 --band -1", "a.vdb", "--band");
    bad("--res 16", "a.vdb", "--scene");
    bad("--scene temple --res 16 --frobnicate", "a.vdb", "unknown option");
    int rc = tu_run(out, sizeof out, "%s bake --scene temple --res 16 -o /nonexistent-dir/a.vdb", SDFT_CLI);
    assert_int_not_equal(rc, 0);
    assert_int_equal(tu_lines(out), 1);
    assert_non_null(strstr(out, "cannot write"));
}

/* A bake says what it made in one line, and nothing with --quiet; the file
 * is written either way. */
static void test_quiet(void **state)
{
    (void)state;
    char vdb[512];
    tu_tmp(vdb, sizeof vdb, "quiet.vdb");
    for (int quiet = 0; quiet < 2; quiet++) {
        remove(vdb);
        assert_int_equal(
            tu_run(out, sizeof out, "%s bake --scene temple --res 16 -o %s%s", SDFT_CLI, vdb, quiet ? " --quiet" : ""),
            0);
        assert_int_equal(tu_lines(out), quiet ? 0 : 1);
        assert_true(tu_file_exists(vdb));
    }
}

static void test_vdb_accepted_by_openvdb_tools(void **state)
{
    (void)state;
    char vdb[512], ppm[512], exr[512];
    tu_tmp(vdb, sizeof vdb, "dodeca.vdb");
    tu_tmp(ppm, sizeof ppm, "dodeca_vdb_render.ppm");
    tu_tmp(exr, sizeof exr, "dodeca_grid.exr");
    remove(vdb), remove(ppm), remove(exr);
    assert_int_equal(
        tu_run(out, sizeof out, "%s bake --scene dodecahedron --res 64 --grid-name dodeca -o %s", SDFT_CLI, vdb), 0);
    assert_non_null(strstr(out, "baked dodecahedron"));
    assert_int_equal(tu_run(out, sizeof out, "vdb_print -l %s", vdb), 0);
    assert_non_null(strstr(out, "dodeca"));
    assert_non_null(strstr(out, "level set"));
    assert_int_equal(tu_run(out, sizeof out, "vdb_render %s %s -res 64x36 -name dodeca", vdb, ppm), 0);
    assert_true(tu_file_exists(ppm));

    /* render --grid: alone (its own framing) and from the scene's camera. */
    assert_int_equal(tu_run(out, sizeof out, "%s render --grid %s --width 64 --height 36 -o %s", SDFT_CLI, vdb, exr),
                     0);
    assert_true(tu_file_exists(exr));
    remove(exr);
    assert_int_equal(tu_run(out, sizeof out,
                            "%s render --grid %s --scene dodecahedron --width 64 --height 36 --json -o %s", SDFT_CLI,
                            vdb, exr),
                     0);
    assert_non_null(strstr(out, "\"hit_fraction\""));
    remove(exr);
    assert_int_not_equal(tu_run(out, sizeof out, "%s render --grid %s --grid-name nosuch -o %s", SDFT_CLI, vdb, exr),
                         0);
    assert_int_equal(tu_lines(out), 1);
    assert_false(tu_file_exists(exr));
    assert_int_not_equal(tu_run(out, sizeof out, "%s render --grid %s/missing.vdb -o %s", SDFT_CLI, SDFT_TEST_TMP, exr),
                         0);
    assert_int_equal(tu_lines(out), 1);
    assert_false(tu_file_exists(exr));
}

static void test_nvdb_accepted_by_nanovdb_tools(void **state)
{
    (void)state;
    char nvdb[512], half[512];
    tu_tmp(nvdb, sizeof nvdb, "figure.nvdb");
    tu_tmp(half, sizeof half, "figure16.nvdb");
    remove(nvdb), remove(half);
    assert_int_equal(tu_run(out, sizeof out, "%s bake --scene figure --res 48 -o %s", SDFT_CLI, nvdb), 0);
    assert_int_equal(tu_run(out, sizeof out, "nanovdb_validate %s", nvdb), 0);
    assert_int_equal(tu_run(out, sizeof out, "nanovdb_print %s", nvdb), 0);
    assert_non_null(strstr(out, "sdf"));
    assert_int_equal(tu_run(out, sizeof out, "%s bake --scene figure --res 48 --fp16 -o %s", SDFT_CLI, half), 0);
    assert_int_equal(tu_run(out, sizeof out, "nanovdb_validate %s", half), 0);
    assert_int_equal(tu_run(out, sizeof out, "nanovdb_print %s", half), 0);
    assert_non_null(strstr(out, "Float16"));
}

/* A bake's file gets the mode a plain fopen would, 0666 less the umask
 * (it used to keep mkstemp's 0600), under two umasks. */
static void test_output_modes(void **state)
{
    (void)state;
    static const int masks[] = {027, 002};
    static const char *const files[] = {"mode.vdb", "mode.nvdb"};
    for (int m = 0; m < 2; m++)
        for (int f = 0; f < 2; f++) {
            char path[512];
            tu_tmp(path, sizeof path, files[f]);
            remove(path);
            assert_int_equal(tu_run(out, sizeof out, "umask %03o && %s bake --scene dodecahedron --res 16 -o %s",
                                    masks[m], SDFT_CLI, path),
                             0);
            assert_int_equal(tu_file_mode(path), 0666 & ~masks[m]);
        }
}

/* --version: the library's version, which is the project's. */
static void test_version(void **state)
{
    (void)state;
    char want[64];
    snprintf(want, sizeof want, "sdftrace %s\n", SDFT_VERSION_STRING);
    assert_int_equal(tu_run(out, sizeof out, "%s --version", SDFT_CLI), 0);
    assert_string_equal(out, want);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_output_modes),
        cmocka_unit_test(test_version),
        cmocka_unit_test(test_help),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_quiet),
        cmocka_unit_test(test_vdb_accepted_by_openvdb_tools),
        cmocka_unit_test(test_nvdb_accepted_by_nanovdb_tools),
    };
    return cmocka_run_group_tests_name("bake", tests, NULL, NULL);
}
