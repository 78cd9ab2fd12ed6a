/* sdftrace tests — the command line: help, scenes, every bad-input case
 * (non-zero exit, one line, no file), and the --json report's consistency. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "testutil.h"

static char out[1 << 16];

static void test_help_lists_every_option(void **state)
{
    (void)state;
    static const char *const flags[] = {"--scene",      "--method",       "--omega",      "--beta",          "--eps",
                                        "--max-steps",  "--width",        "--height",     "--camera",        "--fov",
                                        "--no-shadows", "--threads",      "-o ",          "--png",           "--json",
                                        "--heatmap",    "--screen-space", "--no-cones",   "--no-exact-root", "--papers",
                                        "--fp16",       "--quiet",        "--heatmap-max"};
    for (int which = 0; which < 2; which++) {
        assert_int_equal(tu_run(out, sizeof out, "%s %s", SDFT_CLI, which ? "render --help" : "--help"), 0);
        for (size_t i = 0; i < sizeof flags / sizeof flags[0]; i++)
            assert_non_null(strstr(out, flags[i]));
        assert_non_null(strstr(out, "default auto"));
        assert_non_null(strstr(out, "default 0.3"));
        assert_non_null(strstr(out, "default 1000"));
        assert_non_null(strstr(out, "default 1280"));
        assert_non_null(strstr(out, "default 720"));
    }
    assert_int_not_equal(tu_run(out, sizeof out, "%s", SDFT_CLI), 0);
    assert_int_not_equal(tu_run(out, sizeof out, "%s frobnicate", SDFT_CLI), 0);
    assert_int_equal(tu_lines(out), 1);
}

static void test_scenes(void **state)
{
    (void)state;
    assert_int_equal(tu_run(out, sizeof out, "%s scenes", SDFT_CLI), 0);
    assert_int_equal(tu_lines(out), 5);
    static const char *const names[] = {"temple", "figure", "dodecahedron", "city", "jewel"};
    for (int i = 0; i < 5; i++)
        assert_non_null(strstr(out, names[i]));
}

/* Every case: non-zero exit, exactly one line (stdout + stderr) naming the
 * problem, no file; and the same command without the bad option renders,
 * so no case passes by failing for another reason. */
static void test_bad_input(void **state)
{
    (void)state;
    static const char *const cases[][2] = {
        {"--scene nosuch", "unknown scene"},
        {"--method foo", "unknown method"},
        {"--method relaxed --omega 2", "omega"},
        {"--method relaxed --omega 0.9", "omega"},
        {"--method enhanced --omega 1.5", "omega"},
        {"--method enhanced --omega 0", "omega"},
        {"--beta 1", "beta"},
        {"--beta 0", "beta"},
        {"--beta nan", "--beta"},
        {"--omega inf --method relaxed", "--omega"},
        {"--width 0", "--width"},
        {"--width -5", "--width"},
        {"--width 12abc", "--width"},
        {"--width ' 12'", "--width"},
        {"--height 100000", "--height"},
        {"--width 16384 --height 16384", "pixels"},
        {"--eps -1", "--eps"},
        {"--eps nan", "--eps"},
        {"--eps 0", "eps"},
        {"--max-steps 0", "--max-steps"},
        {"--max-steps 2.5", "--max-steps"},
        {"--fov 0", "--fov"},
        {"--fov 180", "--fov"},
        {"--fov NaN", "--fov"},
        {"--camera 1,2,3", "--camera"},
        {"--camera 1,2,3,1,2,3", "--camera"},
        {"--camera 1,2,3,4,5,x", "--camera"},
        {"--threads -1", "--threads"},
        {"--bogus", "unknown option"},
        {"--heatmap bogus " SDFT_TEST_TMP "/cli_bad_heat.png", "--heatmap"},
        {"--png " SDFT_TEST_TMP "/no/such/dir/x.png", "cannot write"},
        {"--heatmap steps " SDFT_TEST_TMP "/no/such/dir/h.png", "cannot write"},
        {"--width", "needs a value"},
        {"--heatmap-max 40", "--heatmap-max needs --heatmap"},
        {"--heatmap-max 0 --heatmap steps " SDFT_TEST_TMP "/cli_bad_heat.png", "--heatmap-max"},
        {"--heatmap-max x --heatmap steps " SDFT_TEST_TMP "/cli_bad_heat.png", "--heatmap-max"},
        {"--heatmap steps " SDFT_TEST_TMP "/cli_bad_heat.png --heatmap-max", "needs a value"},
    };
    char exr[512];
    tu_tmp(exr, sizeof exr, "cli_bad.exr");
    remove(exr);
    assert_int_equal(
        tu_run(out, sizeof out, "%s render --scene dodecahedron --width 16 --height 9 -o %s", SDFT_CLI, exr), 0);
    assert_true(tu_file_exists(exr));
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        remove(exr);
        const char *scene = strstr(cases[i][0], "--scene") ? "" : "--scene dodecahedron";
        int rc =
            tu_run(out, sizeof out, "%s render %s --width 16 --height 9 -o %s %s", SDFT_CLI, scene, exr, cases[i][0]);
        if (rc == 0 || tu_lines(out) != 1 || tu_file_exists(exr) || !strstr(out, cases[i][1]))
            fail_msg("case '%s': rc %d, output '%s' (want one line naming '%s')", cases[i][0], rc, out, cases[i][1]);
    }
    assert_false(tu_file_exists(SDFT_TEST_TMP "/cli_bad_heat.png"));
    /* Missing -o, missing --scene, unwritable output. */
    assert_int_not_equal(tu_run(out, sizeof out, "%s render --scene city --width 8 --height 8", SDFT_CLI), 0);
    assert_int_equal(tu_lines(out), 1);
    assert_int_not_equal(tu_run(out, sizeof out, "%s render -o %s --width 8 --height 8", SDFT_CLI, exr), 0);
    assert_int_equal(tu_lines(out), 1);
    assert_false(tu_file_exists(exr));
    assert_int_not_equal(tu_run(out, sizeof out, "%s render --scene city -o %s/none/x.exr --width 8 --height 8",
                                SDFT_CLI, SDFT_TEST_TMP),
                         0);
    assert_int_equal(tu_lines(out), 1);
    assert_false(tu_file_exists(SDFT_TEST_TMP "/none/x.exr"));
}

/* The number after "key": in a one-line JSON object; NAN when absent. */
static double json_number(const char *json, const char *key)
{
    char pattern[64];
    snprintf(pattern, sizeof pattern, "\"%s\": ", key);
    const char *p = strstr(json, pattern);
    return p ? strtod(p + strlen(pattern), NULL) : NAN;
}

static void render_json(const char *args, char *json, size_t len)
{
    char exr[512], png[512], heat[512];
    tu_tmp(exr, sizeof exr, "cli_json.exr");
    tu_tmp(png, sizeof png, "cli_json.png");
    tu_tmp(heat, sizeof heat, "cli_json_heat.png");
    remove(exr), remove(png), remove(heat);
    /* stdout only: stderr of the inner command goes to /dev/null */
    int rc = tu_run(json, len, "{ %s render %s -o %s --png %s --heatmap fallbacks %s --json 2>/dev/null; }", SDFT_CLI,
                    args, exr, png, heat);
    assert_int_equal(rc, 0);
    assert_true(tu_file_exists(exr) && tu_file_exists(png) && tu_file_exists(heat));
}

static void test_json_report(void **state)
{
    (void)state;
    char json[4096];
    render_json("--scene temple --method relaxed --width 48 --height 27 --threads 2", json, sizeof json);
    assert_int_equal(tu_lines(json), 1);
    assert_true(json[0] == '{' && strstr(json, "}\n") != NULL);
    assert_non_null(strstr(json, "\"method\": \"relaxed\""));
    assert_true(json_number(json, "omega") == 1.5);
    assert_true(fabs(json_number(json, "beta") - 0.3) < 1e-6);
    assert_true(json_number(json, "width") == 48 && json_number(json, "height") == 27);
    double primary = 48 * 27, rays = json_number(json, "rays"), hit = json_number(json, "hit_fraction");
    double nc = json_number(json, "nonconverged"), mean = json_number(json, "mean_steps");
    assert_true(json_number(json, "primary_rays") == primary);
    assert_true(rays >= primary && rays <= 2 * primary);
    assert_true(hit > 0.0 && hit <= 1.0 && nc >= 0.0 && nc <= 1.0 && hit + nc <= 1.0);
    assert_true(mean >= 1.0 && fabs(mean * primary - json_number(json, "steps")) < 1.0);
    assert_true(json_number(json, "mean_fallbacks") >= 0.0 && json_number(json, "ms") >= 0.0);
    /* Primary and shadow rays apart: they add up to the totals. */
    double primary_steps = json_number(json, "primary_steps"), shadow = json_number(json, "mean_shadow_steps");
    assert_true(primary_steps > 0.0 && primary_steps < json_number(json, "steps"));
    assert_true(fabs(json_number(json, "mean_primary_steps") * primary - primary_steps) < 1.0);
    assert_true(fabs(shadow * primary - (json_number(json, "steps") - primary_steps)) < 1.0 && shadow > 0.0);
    assert_true(json_number(json, "primary_fallbacks") <= json_number(json, "fallbacks"));
    assert_true(fabs(json_number(json, "mean_primary_fallbacks") * primary - json_number(json, "primary_fallbacks")) <
                1.0);

    /* The same counts with one thread. */
    char again[4096];
    render_json("--scene temple --method relaxed --width 48 --height 27 --threads 1", again, sizeof again);
    assert_true(json_number(again, "steps") == json_number(json, "steps"));
    assert_true(json_number(again, "fallbacks") == json_number(json, "fallbacks"));

    /* No shadows: one ray per pixel. Options override the defaults. */
    render_json("--scene dodecahedron --no-shadows --width 20 --height 10 --method enhanced --eps 0.001 --max-steps 64 "
                "--camera 0,2,9,0,0,0 --fov 50 --screen-space --heatmap-max 12",
                json, sizeof json);
    assert_true(json_number(json, "rays") == 200);
    assert_true(json_number(json, "primary_steps") == json_number(json, "steps"));
    assert_true(json_number(json, "mean_shadow_steps") == 0.0);
    assert_true(fabs(json_number(json, "omega") - 0.88) < 1e-6 && json_number(json, "max_steps") == 64);
    assert_non_null(strstr(json, "\"screen_space\": true"));
    assert_non_null(strstr(json, "\"cones\": true")); /* the default */
    assert_non_null(strstr(json, "\"exact_root\": true"));
    render_json("--scene dodecahedron --width 20 --height 10 --papers", json, sizeof json);
    assert_non_null(strstr(json, "\"cones\": false"));
    assert_non_null(strstr(json, "\"exact_root\": false"));
    assert_true(json_number(json, "cone_steps") == 0);
}

/* The bytes of the file at path, *size of them. */
static unsigned char *file_bytes(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    rewind(f);
    unsigned char *b = malloc(*size ? *size : 1);
    assert_non_null(b);
    assert_int_equal(fread(b, 1, *size, f), *size);
    fclose(f);
    return b;
}

/* --repeat N traces the frame N times in one process: the report counts
 * the first frame (the counts of a render of one frame), times the first,
 * the best and the warm frames and each phase before them, and the image
 * is the one frame's, byte for byte. */
static void test_repeat_report(void **state)
{
    (void)state;
    char one[8192], three[8192], exr[2][512], grid[512];
    tu_tmp(exr[0], sizeof exr[0], "repeat1.exr");
    tu_tmp(exr[1], sizeof exr[1], "repeat3.exr");
    const char *view = "--scene temple --width 48 --height 27 --threads 2 --json --quiet";
    assert_int_equal(tu_run(one, sizeof one, "%s render %s -o %s", SDFT_CLI, view, exr[0]), 0);
    assert_int_equal(tu_run(three, sizeof three, "%s render %s --repeat 3 -o %s", SDFT_CLI, view, exr[1]), 0);
    assert_true(json_number(one, "frames") == 1 && json_number(three, "frames") == 3);
    static const char *const counts[] = {"steps", "primary_steps", "cone_steps", "fallbacks", "hit_fraction", "rays"};
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++)
        assert_true(json_number(one, counts[i]) == json_number(three, counts[i]));
    const double first = json_number(three, "first_frame_ms"), best = json_number(three, "best_frame_ms"),
                 warm = json_number(three, "warm_frame_ms");
    assert_true(first == json_number(three, "ms"));
    assert_true(best > 0.0 && best <= first && warm >= best);
    assert_true(best == (warm < first ? warm : first));
    assert_non_null(strstr(one, "\"warm_frame_ms\": null"));
    assert_true(json_number(three, "wall_ms") >= json_number(three, "open_ms") + first + warm);
    size_t size[2];
    unsigned char *bytes[2] = {file_bytes(exr[0], &size[0]), file_bytes(exr[1], &size[1])};
    assert_int_equal(size[0], size[1]);
    assert_memory_equal(bytes[0], bytes[1], size[0]);
    free(bytes[0]), free(bytes[1]);
    /* A grid's phases: `bake` stores its tables, so none is built. */
    tu_tmp(grid, sizeof grid, "repeat.nvdb");
    assert_int_equal(tu_run(one, sizeof one, "%s bake --scene figure --res 48 -o %s --quiet", SDFT_CLI, grid), 0);
    assert_int_equal(tu_run(one, sizeof one,
                            "%s render --grid %s --scene figure --width 32 --height 18 --json --quiet "
                            "--repeat 2 -o %s",
                            SDFT_CLI, grid, exr[0]),
                     0);
    assert_non_null(strstr(one, "\"far_bound_stored\": true"));
    assert_non_null(strstr(one, "\"hull_stored\": true"));
    assert_true(json_number(one, "far_bound_ms") < 1.0 && json_number(one, "hull_ms") < 1.0);
    assert_true(json_number(one, "read_ms") >= 0.0 && json_number(one, "directory_ms") >= 0.0);
    /* No frame at all is a bad option. */
    assert_int_equal(tu_run(one, sizeof one, "%s render %s --repeat 0 -o %s 2>&1", SDFT_CLI, view, exr[0]), 2);
    assert_int_equal(tu_lines(one), 1);
}

/* A render says what it made on stderr, one line, unless --quiet. */
static void test_summary_line(void **state)
{
    (void)state;
    char exr[512];
    tu_tmp(exr, sizeof exr, "cli_summary.exr");
    assert_int_equal(tu_run(out, sizeof out, "%s render --scene figure --width 32 --height 18 -o %s", SDFT_CLI, exr),
                     0);
    assert_int_equal(tu_lines(out), 1);
    assert_non_null(strstr(out, "32x18"));
    assert_non_null(strstr(out, "% hit"));
    assert_non_null(strstr(out, exr));
    assert_int_equal(
        tu_run(out, sizeof out, "%s render --scene figure --width 32 --height 18 -o %s --quiet", SDFT_CLI, exr), 0);
    assert_int_equal(tu_lines(out), 0);
    /* --fp16 converts a .vdb; anything else is a one-line error. */
    assert_int_not_equal(tu_run(out, sizeof out, "%s render --scene figure --fp16 -o %s", SDFT_CLI, exr), 0);
}

/* Outputs get the mode a plain fopen would, 0666 less the umask, under two
 * umasks (so neither 0600 nor a fixed 0644 passes). */
static void test_output_modes(void **state)
{
    (void)state;
    static const int masks[] = {027, 002};
    char exr[512], png[512], heat[512];
    tu_tmp(exr, sizeof exr, "cli_mode.exr");
    tu_tmp(png, sizeof png, "cli_mode.png");
    tu_tmp(heat, sizeof heat, "cli_mode_heat.png");
    for (int m = 0; m < 2; m++) {
        remove(exr), remove(png), remove(heat);
        int rc = tu_run(out, sizeof out,
                        "umask %03o && %s render --scene dodecahedron --width 16 --height 9 -o %s --png %s "
                        "--heatmap steps %s",
                        masks[m], SDFT_CLI, exr, png, heat);
        assert_int_equal(rc, 0);
        const int want = 0666 & ~masks[m];
        assert_int_equal(tu_file_mode(exr), want);
        assert_int_equal(tu_file_mode(png), want);
        assert_int_equal(tu_file_mode(heat), want);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_output_modes), cmocka_unit_test(test_help_lists_every_option),
        cmocka_unit_test(test_scenes),       cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_json_report),  cmocka_unit_test(test_repeat_report),
        cmocka_unit_test(test_summary_line),
    };
    return cmocka_run_group_tests_name("cli", tests, NULL, NULL);
}
