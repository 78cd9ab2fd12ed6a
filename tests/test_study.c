/* sdftrace tests — the study (bench/study): a rerun of a row's command line
 * through `sdftrace render --json` gives that row's counts to the last
 * digit, on the procedural scene and on both grids, for a fresh small run
 * and for the results committed in bench/results/; and bad arguments get
 * one line and a non-zero exit, from the program and from bench/study.sh. */
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

/* Field `col` (0-based) of a CSV line whose fields hold no commas, but for a
 * last, quoted one: copied into buf without its quotes. */
static const char *csv_field(const char *line, int col, char *buf, size_t len)
{
    const char *p = line;
    for (int k = 0; k < col && p; k++)
        p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL;
    assert_non_null(p);
    const char *end = *p == '"' ? strchr(p + 1, '"') : strpbrk(p, ",\n");
    if (*p == '"')
        p++;
    size_t n = end ? (size_t)(end - p) : strlen(p);
    assert_true(n < len);
    memcpy(buf, p, n);
    buf[n] = '\0';
    return buf;
}

static int csv_column(const char *header, const char *name)
{
    char buf[64];
    for (int col = 0; col < 40; col++)
        if (!strcmp(csv_field(header, col, buf, sizeof buf), name))
            return col;
    fail_msg("no column %s", name);
    return -1;
}

/* The text after "key": in a JSON line, up to the next comma or brace. */
static const char *json_text(const char *json, const char *key, char *buf, size_t len)
{
    char pattern[64];
    snprintf(pattern, sizeof pattern, "\"%s\": ", key);
    const char *p = strstr(json, pattern);
    assert_non_null(p);
    p += strlen(pattern);
    size_t n = strcspn(p, ",}");
    assert_true(n < len);
    memcpy(buf, p, n);
    buf[n] = '\0';
    return buf;
}

/* A row's field by its column's name in the header. */
static const char *row_field(const char *header, const char *line, const char *name, char *buf, size_t len)
{
    return csv_field(line, csv_column(header, name), buf, len);
}

/* Opens a results CSV and reads its header line. */
static FILE *csv_open(const char *path, char *header, size_t len)
{
    FILE *f = fopen(path, "r");
    if (!f)
        fail_msg("cannot read %s", path);
    assert_non_null(fgets(header, (int)len, f));
    return f;
}

/* Runs `cmd`, a row's command line, and fails unless it prints the row's
 * counts digit for digit; `what` names the row's file in the message. */
static void rerun_row(const char *header, const char *line, const char *cmd, const char *what)
{
    static const char *const keys[] = {"mean_steps", "mean_primary_steps", "mean_cone_steps", "steps"};
    if (tu_run(out, sizeof out, "%s 2>&1", cmd))
        fail_msg("'%s' failed: %s", cmd, out);
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++) {
        char got[32], want[32];
        if (strcmp(json_text(out, keys[k], got, sizeof got), row_field(header, line, keys[k], want, sizeof want)))
            fail_msg("'%s' gives %s %s, %s says %s", cmd, keys[k], got, what, want);
    }
}

static void test_rows_rerun_exactly(void **state)
{
    (void)state;
    const char *grids = SDFT_TEST_TMP "/study-grids", *res = SDFT_TEST_TMP "/study-out";
    assert_int_equal(tu_run(out, sizeof out, "rm -rf %s %s && mkdir -p %s %s", grids, res, grids, res), 0);
    for (int full = 0; full < 2; full++)
        assert_int_equal(tu_run(out, sizeof out, "%s bake --scene temple --res 32%s -o %s/temple-%s-32.nvdb", SDFT_CLI,
                                full ? " --full" : "", grids, full ? "full" : "band"),
                         0);
    int rc = tu_run(out, sizeof out,
                    "%s --out %s --grids %s --res 32 --width 40 --height 24 --repeats 1 --sweep 0 --scenes temple "
                    "--caps 1000,16 --parts table,keinert --cli %s --row-exr %s/study-row.exr --quiet",
                    SDFT_STUDY, res, grids, SDFT_CLI, SDFT_TEST_TMP);
    if (rc)
        fail_msg("study failed: %s", out);

    char path[512];
    snprintf(path, sizeof path, "%s/results.csv", res);
    static char header[4096], line[8192];
    FILE *f = csv_open(path, header, sizeof header);
    /* A few small rows of each kind: every representation, with and without
     * shadows, both caps, and one of Keinert's screen-space rows. */
    int checked = 0, seen[3][2][2] = {{{0}}}, screen_space = 0, rows = 0;
    while (fgets(line, sizeof line, f)) {
        rows++;
        char rep[32], shadows[8], cap[16], ss[8], cmd[4096];
        row_field(header, line, "representation", rep, sizeof rep);
        row_field(header, line, "shadows", shadows, sizeof shadows);
        row_field(header, line, "max_steps", cap, sizeof cap);
        row_field(header, line, "screen_space", ss, sizeof ss);
        const int r = !strcmp(rep, "procedural") ? 0 : !strcmp(rep, "band") ? 1 : 2, s = atoi(shadows);
        const int k = !strcmp(cap, "16");
        const int take = *ss == '1' ? !screen_space++ : !seen[r][s][k]++;
        if (!take)
            continue;
        rerun_row(header, line, row_field(header, line, "command", cmd, sizeof cmd), "the study's row");
        checked++;
    }
    fclose(f);
    assert_int_equal(checked, 3 * 2 * 2 + 1);
    assert_int_equal(rows, 3 * 2 * 2 * 6 + 12); /* the table's rows and Keinert's */
    print_message("%d of %d rows rerun through sdftrace render: the same counts\n", checked, rows);
}

/* A copy of src in dst with every `from` replaced by `to`. */
static void replace_all(char *dst, size_t len, const char *src, const char *from, const char *to)
{
    size_t n = 0;
    for (const char *hit; (hit = strstr(src, from)); src = hit + strlen(from)) {
        n += (size_t)snprintf(dst + n, len - n, "%.*s%s", (int)(hit - src), src, to);
        assert_true(n < len);
    }
    n += (size_t)snprintf(dst + n, len - n, "%s", src);
    assert_true(n < len);
}

/* A command line of the committed results, run here: `build/sdftrace` is
 * this build's, the grids and the image go to the test's folder. */
static void committed_command(char *dst, size_t len, const char *cmd, const char *dir)
{
    static char a[8192], b[8192];
    char grids[512], exr[512];
    snprintf(grids, sizeof grids, "%s/", dir);
    snprintf(exr, sizeof exr, "%s/row.exr", dir);
    replace_all(a, sizeof a, cmd, "build/sdftrace ", SDFT_CLI " ");
    replace_all(b, sizeof b, a, "build/study-grids/", grids);
    replace_all(dst, len, b, "/tmp/study-row.exr", exr);
}

/* Bakes the grid a committed row renders (`--grid PATH`), as the committed
 * bakes.csv says it was baked; returns 0 for a procedural row. */
static int bake_committed_grid(const char *cmd, const char *dir)
{
    const char *grid = strstr(cmd, "--grid ");
    if (!grid)
        return 0;
    char path[512];
    assert_int_equal(sscanf(grid, "--grid %511s", path), 1);
    static char header[1024], line[4096], bake[4096], run[8192];
    FILE *f = csv_open(SDFT_SOURCE_DIR "/bench/results/bakes.csv", header, sizeof header);
    int found = 0;
    while (!found && fgets(line, sizeof line, f)) {
        row_field(header, line, "command", bake, sizeof bake);
        const size_t n = strlen(bake), k = strlen(path);
        found = n >= k && !strcmp(bake + n - k, path);
    }
    fclose(f);
    if (!found)
        fail_msg("bench/results/bakes.csv has no bake of %s", path);
    committed_command(run, sizeof run, bake, dir);
    const char *file = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    if (tu_run(out, sizeof out, "test -s %s/%s || %s --quiet 2>&1", dir, file, run))
        fail_msg("'%s' failed: %s", run, out);
    return 1;
}

/* The committed results describe the code as it is: a few rows of
 * bench/results/results.csv, on the temple's 1024^3 band and full grid
 * (the cones beyond the paper on both, the papers' counting on the band;
 * auto-relaxed, with the shadow ray) and on the procedural temple, rerun
 * through `sdftrace render` on grids baked here as bench/results/bakes.csv
 * says, count what the file says to the last digit. When a change moves
 * them, `make bench` makes the results to commit. */
static void test_committed_rows_rerun_exactly(void **state)
{
    (void)state;
    const char *dir = SDFT_TEST_TMP "/committed-rows";
    assert_int_equal(tu_run(out, sizeof out, "rm -rf %s && mkdir -p %s", dir, dir), 0);
    static char header[4096], line[8192];
    FILE *f = csv_open(SDFT_SOURCE_DIR "/bench/results/results.csv", header, sizeof header);
    int checked = 0, grids = 0;
    while (fgets(line, sizeof line, f)) {
        char scene[32], rep[32], method[32], param[16], shadows[8], cap[16], ss[8], cones[8];
        row_field(header, line, "scene", scene, sizeof scene);
        row_field(header, line, "representation", rep, sizeof rep);
        row_field(header, line, "method", method, sizeof method);
        row_field(header, line, "param", param, sizeof param);
        row_field(header, line, "shadows", shadows, sizeof shadows);
        row_field(header, line, "max_steps", cap, sizeof cap);
        row_field(header, line, "screen_space", ss, sizeof ss);
        row_field(header, line, "cones", cones, sizeof cones);
        /* auto 0.3 on the temple, shadows, 1000 steps, ε: the papers' row on
         * the procedural scene and the band, the cones' row on both grids */
        const int papers = !strcmp(cones, "0");
        if (strcmp(scene, "temple") || strcmp(method, "auto") || strcmp(param, "0.3") || strcmp(shadows, "1") ||
            strcmp(cap, "1000") || strcmp(ss, "0") || (papers && !strcmp(rep, "full")) ||
            (!papers && !strcmp(rep, "procedural")))
            continue;
        static char row[8192], run[8192];
        row_field(header, line, "command", row, sizeof row);
        grids += bake_committed_grid(row, dir);
        committed_command(run, sizeof run, row, dir);
        rerun_row(header, line, run, "bench/results/results.csv (stale: rerun make bench and commit bench/results/)");
        checked++;
    }
    fclose(f);
    assert_int_equal(grids, 3);   /* the band's two rows and the full grid's */
    assert_int_equal(checked, 4); /* and the procedural row */
    print_message("%d committed rows (%d on grids) rerun through sdftrace render: the same counts\n", checked, grids);
}

/* Every file the study writes goes through the atomic writer: the mode the
 * umask gives (as sdftrace's and mesh2sdf's outputs), no temporary left. */
static void test_files_get_the_umask_mode(void **state)
{
    (void)state;
    const char *res = SDFT_TEST_TMP "/study-mode";
    static const unsigned masks[] = {022, 027, 002};
    static const char *const files[] = {"results.csv",
                                        "table.md",
                                        "fig1.txt",
                                        "fig2-temple-procedural.dat",
                                        "fig1-temple-procedural-auto0.3-steps.u32",
                                        "fig1-temple-procedural-relaxed-bv1.5-fallbacks.u32"};
    for (size_t m = 0; m < sizeof masks / sizeof masks[0]; m++) {
        assert_int_equal(tu_run(out, sizeof out, "rm -rf %s && mkdir -p %s", res, res), 0);
        int rc = tu_run(out, sizeof out,
                        "umask %03o && %s --out %s --reps procedural --parts table --scenes temple --caps 1000 "
                        "--width 8 --height 6 --repeats 1 --sweep 0 --quiet",
                        masks[m], SDFT_STUDY, res);
        if (rc)
            fail_msg("study failed: %s", out);
        for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
            char path[512];
            snprintf(path, sizeof path, "%s/%s", res, files[k]);
            if (tu_file_mode(path) != (int)(0666 & ~masks[m]))
                fail_msg("%s: mode %o under umask %03o", path, (unsigned)tu_file_mode(path), masks[m]);
            tu_assert_no_temporaries(res, files[k]);
        }
    }
}

/* Bad arguments: one line, a non-zero exit, no results. */
static void test_bad_arguments(void **state)
{
    (void)state;
    const char *dir = SDFT_TEST_TMP "/study-bad";
    assert_int_equal(tu_run(out, sizeof out, "rm -rf %s && mkdir -p %s && chmod 555 %s", dir, dir, dir), 0);
    static const char *const cases[] = {
        "--scenes nosuch",
        "--scenes temple,nosuch",
        "--width 0",
        "--height -3",
        "--res 0",
        "--res 2048",
        "--repeats 0",
        "--sweep x",
        "--caps 0",
        "--caps ''",
        "--reps procedural,nosuch",
        "--parts nosuch",
        "--bogus",
        "--width",
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int rc = tu_run(out, sizeof out, "%s --out %s/out %s", SDFT_STUDY, SDFT_TEST_TMP, cases[i]);
        if (rc == 0 || tu_lines(out) != 1)
            fail_msg("case '%s': rc %d, output '%s'", cases[i], rc, out);
    }
    /* No --out; an unwritable one (unless root, who may write anywhere); a missing grid. */
    assert_int_not_equal(tu_run(out, sizeof out, "%s --scenes temple", SDFT_STUDY), 0);
    assert_int_equal(tu_lines(out), 1);
    assert_int_not_equal(tu_run(out, sizeof out, "%s --out %s/no/such/dir", SDFT_STUDY, SDFT_TEST_TMP), 0);
    assert_int_equal(tu_lines(out), 1);
    if (tu_run(NULL, 0, "test -w %s", dir) != 0) {
        assert_int_not_equal(tu_run(out, sizeof out, "%s --out %s", SDFT_STUDY, dir), 0);
        assert_int_equal(tu_lines(out), 1);
    }
    assert_int_not_equal(tu_run(out, sizeof out,
                                "%s --out %s --grids %s/none --res 16 --width 8 --height 8 --parts table --quiet",
                                SDFT_STUDY, SDFT_TEST_TMP, SDFT_TEST_TMP),
                         0);
    assert_int_equal(tu_lines(out), 1);
    assert_non_null(strstr(out, "none/temple-band-16.nvdb"));

    /* The driver checks the same before it bakes anything. */
    static const char *const driver[] = {"--bogus", "--out", "--build /no/such/build"};
    for (size_t i = 0; i < sizeof driver / sizeof driver[0]; i++) {
        int rc = tu_run(out, sizeof out, "sh %s %s", SDFT_STUDY_SH, driver[i]);
        if (rc == 0 || tu_lines(out) != 1)
            fail_msg("study.sh '%s': rc %d, output '%s'", driver[i], rc, out);
    }
    int rc = tu_run(out, sizeof out, "SCENES=nosuch sh %s --quick --build %s", SDFT_STUDY_SH, SDFT_BUILD_DIR);
    if (rc == 0 || tu_lines(out) != 1)
        fail_msg("study.sh with an unknown scene: rc %d, output '%s'", rc, out);
    rc = tu_run(out, sizeof out, "WIDTH=0 sh %s --quick --build %s", SDFT_STUDY_SH, SDFT_BUILD_DIR);
    if (rc == 0 || tu_lines(out) != 1)
        fail_msg("study.sh with width 0: rc %d, output '%s'", rc, out);
    tu_run(NULL, 0, "chmod 755 %s", dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows_rerun_exactly),
        cmocka_unit_test(test_committed_rows_rerun_exactly),
        cmocka_unit_test(test_files_get_the_umask_mode),
        cmocka_unit_test(test_bad_arguments),
    };
    return cmocka_run_group_tests_name("study", tests, NULL, NULL);
}
