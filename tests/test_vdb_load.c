/* sdftrace tests — grid files in by path (src/vdb/vdb_open.c,
 * src/vdb/vdb_load.cpp, src/grid/grid_choose.h): .vdb and .nvdb round trips
 * against the baked grid, voxel for voxel, the grid each name picks in files
 * made by OpenVDB's and NanoVDB's own tools, and every error. */
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
#include <omp.h>

#include "grid_internal.h"
#include "grid_support.h"
#include "sdftrace/grid.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/sdf.h"
#include "sdftrace/vdb.h"
#include "testutil.h"

/* ---- round trips ------------------------------------------------------------------- */

static void round_trip(const char *file)
{
    char path[512], msg[256];
    tu_tmp(path, sizeof path, file);
    remove(path);
    sdft_field f = spheres_field();
    sdft_grid *mem = bake(&f, 40, 0, path);
    assert_true(tu_file_exists(path));
    sdft_grid *disk = NULL;
    int rc = tu_open_file(path, NULL, SDFT_QUANT_NONE, &disk, msg, sizeof msg);
    if (rc)
        print_error("%s\n", msg);
    assert_int_equal(rc, 0);
    assert_string_equal(sdft_grid_name(disk), "sdf");
    assert_true(sdft_grid_is_level_set(disk));
    same_voxels(mem, disk);
    sdft_grid_free(mem);
    sdft_grid_free(disk);
}

static void test_round_trip_vdb(void **state)
{
    (void)state;
    round_trip("roundtrip.vdb");
}

static void test_round_trip_nvdb(void **state)
{
    (void)state;
    round_trip("roundtrip.nvdb");
}

/* ---- a .vdb loaded whole: the reader process's grid --------------------------------- */

/* Whether the bytes at p lie in a mapping of the shared file the reader
 * process writes (vdb_load.cpp), as /proc/self/maps names it. */
static int in_reader_mapping(const void *p)
{
    FILE *maps = fopen("/proc/self/maps", "r");
    assert_non_null(maps);
    char line[1024];
    int found = 0;
    while (!found && fgets(line, sizeof line, maps)) {
        unsigned long lo, hi;
        if (sscanf(line, "%lx-%lx", &lo, &hi) == 2 && (uintptr_t)p >= lo && (uintptr_t)p < hi)
            found = strstr(line, "memfd:sdftrace-grid") != NULL;
    }
    fclose(maps);
    return found;
}

typedef struct progress_seen {
    float last;
    int calls, decreased, stop_at; /* stop_at > 0: say stop on that call */
} progress_seen;

static int watch_progress(void *user, float done)
{
    progress_seen *p = user;
    p->decreased |= done < p->last;
    p->last = done;
    return ++p->calls == p->stop_at;
}

/* Loaded whole (streamed, not deferred), a .vdb grid is the one the reader
 * process wrote into a shared file, mapped here without a copy: with 1, 2
 * or 5 threads the same bytes, the voxels of NanoVDB's own converter (the
 * whole OpenVDB grid in this process), and the same voxels deferred (this
 * process reading the file itself); its progress climbs to 1, and a
 * callback that says stop stops it. */
static void test_whole_load_is_the_readers_grid(void **state)
{
    (void)state;
    char path[512], msg[256];
    tu_tmp(path, sizeof path, "reader.vdb");
    remove(path);
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid_free(bake(&sc->field, 256, 0, path));
    static const int threads[3] = {1, 2, 5};
    sdft_grid *g[3];
    const int was = omp_get_max_threads();
    for (int i = 0; i < 3; i++) {
        omp_set_num_threads(threads[i]);
        progress_seen seen = {0};
        sdft_grid_options o = sdft_grid_options_defaults();
        o.progress = watch_progress, o.progress_user = &seen;
        assert_int_equal(tu_open_with(path, NULL, &o, &g[i], msg, sizeof msg), SDFT_OK);
        size_t size;
        const void *data = sdft_grid_data(g[i], &size);
        assert_true(in_reader_mapping(data));
        assert_true(seen.calls > 0 && !seen.decreased && seen.last == 1.0f);
        if (i > 0) {
            size_t first_size;
            const void *first = sdft_grid_data(g[0], &first_size);
            assert_int_equal(size, first_size);
            assert_memory_equal(data, first, size);
        }
    }
    omp_set_num_threads(was);
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(g[0]->buf, g[0]->grid);
    print_message("%llu leaves\n", (unsigned long long)pnanovdb_tree_get_node_count_leaf(g[0]->buf, tree));
    assert_true(pnanovdb_tree_get_node_count_leaf(g[0]->buf, tree) > 2048); /* several batches */
    sdft_grid *other;
    sdft_grid_options converter = sdft_grid_options_defaults();
    converter.stream = 0;
    assert_int_equal(tu_open_with(path, NULL, &converter, &other, msg, sizeof msg), SDFT_OK);
    assert_false(in_reader_mapping(sdft_grid_data(other, NULL)));
    same_voxels(other, g[0]);
    sdft_grid_free(other);
    sdft_grid_options deferred = sdft_grid_options_defaults();
    deferred.defer = SDFT_DEFER_ALWAYS;
    assert_int_equal(tu_open_with(path, NULL, &deferred, &other, msg, sizeof msg), SDFT_OK);
    same_voxels(other, g[0]);
    assert_false(in_reader_mapping(sdft_grid_data(other, NULL)));
    sdft_grid_free(other);
    for (int i = 0; i < 3; i++)
        sdft_grid_free(g[i]);
    /* Stopped by its callback: no grid, SDFT_ECANCELED. */
    progress_seen stop = {.stop_at = 1};
    sdft_grid_options o = sdft_grid_options_defaults();
    o.progress = watch_progress, o.progress_user = &stop;
    sdft_grid *none = NULL;
    assert_int_equal(tu_open_with(path, NULL, &o, &none, msg, sizeof msg), SDFT_ECANCELED);
    assert_null(none);
}

/* ---- which grid: .vdb and .nvdb alike ----------------------------------------------- */

/* Files written by OpenVDB's vdb_tool and converted by NanoVDB's
 * nanovdb_convert, each grid in the same order: every selection gives the
 * same code and the same grid from both loaders, and the grid the rule
 * (include/sdftrace/grid.h) names. */
static void test_grid_selection_is_the_same_for_vdb_and_nvdb(void **state)
{
    (void)state;
    char vdb[512], nvdb[512], cmd_out[4096];
    static const struct {
        const char *tool_args; /* vdb_tool writes its stack top first */
        struct {
            const char *name; /* NULL: the default choice */
            sdft_error code;
            const char *picked;
        } cases[5];
    } files[2] = {
        {"-sphere radius=1 dim=32 name=ball -grad keep=1 -sphere radius=0.5 dim=32 name=s0 -ls2fog keep=0",
         /* ls2fog_s0 (fog), grad_ball (vec3), ball (level set) */
         {{NULL, SDFT_OK, "ball"},
          {"ls2fog_s0", SDFT_OK, "ls2fog_s0"},
          {"ball", SDFT_OK, "ball"},
          {"grad_ball", SDFT_ENOTSCALAR, NULL},
          {"nosuch", SDFT_ENOTFOUND, NULL}}},
        {"-sphere radius=1 dim=32 name=b -grad keep=0 -sphere radius=0.5 dim=32 name=s0 -ls2fog keep=0",
         /* ls2fog_s0 (fog), grad_b (vec3): no level set, the first scalar grid */
         {{NULL, SDFT_OK, "ls2fog_s0"},
          {"grad_b", SDFT_ENOTSCALAR, NULL},
          {"", SDFT_ENOTFOUND, NULL},
          {"ls2fog_s0", SDFT_OK, "ls2fog_s0"},
          {"b", SDFT_ENOTFOUND, NULL}}},
    };
    for (int k = 0; k < 2; k++) {
        tu_tmp(vdb, sizeof vdb, k ? "choose2.vdb" : "choose1.vdb");
        tu_tmp(nvdb, sizeof nvdb, k ? "choose2.nvdb" : "choose1.nvdb");
        remove(vdb), remove(nvdb);
        int rc = tu_run(cmd_out, sizeof cmd_out, "vdb_tool -quiet %s -o %s && nanovdb_convert -f %s %s",
                        files[k].tool_args, vdb, vdb, nvdb);
        if (rc)
            print_error("%s\n", cmd_out);
        assert_int_equal(rc, 0);
        for (int c = 0; c < 5; c++) {
            const char *name = files[k].cases[c].name;
            sdft_grid *gv = NULL, *gn = NULL;
            char mv[256] = "", mn[256] = "";
            const sdft_error rv = tu_open_file(vdb, name, SDFT_QUANT_NONE, &gv, mv, sizeof mv);
            const sdft_error rn = tu_open_nvdb(nvdb, name, &gn, mn, sizeof mn);
            print_message("%s '%s': .vdb %s %s | .nvdb %s %s\n", k ? "choose2" : "choose1", name ? name : "(null)",
                          sdft_error_name(rv), gv ? sdft_grid_name(gv) : mv, sdft_error_name(rn),
                          gn ? sdft_grid_name(gn) : mn);
            assert_int_equal(rv, files[k].cases[c].code);
            assert_int_equal(rn, files[k].cases[c].code);
            if (files[k].cases[c].picked) {
                assert_string_equal(sdft_grid_name(gv), files[k].cases[c].picked);
                assert_string_equal(sdft_grid_name(gn), files[k].cases[c].picked);
                assert_int_equal(sdft_grid_active_voxels(gv), sdft_grid_active_voxels(gn));
            }
            sdft_grid_free(gv);
            sdft_grid_free(gn);
        }
    }
}

/* ---- errors -------------------------------------------------------------------------- */

static void expect_error(const char *path, const char *name, int code, const char *needle)
{
    sdft_grid *g = (sdft_grid *)1;
    char msg[512] = "";
    int rc = tu_open_file(path, name, SDFT_QUANT_NONE, &g, msg, sizeof msg);
    print_message("%s -> %d: %s\n", path, rc, msg);
    assert_int_equal(rc, code);
    assert_null(g);
    assert_null(strchr(msg, '\n'));
    assert_non_null(strstr(msg, needle));
}

/* Writes the first `keep` bytes of src to dst, or garbage when keep is 0. */
static void copy_prefix(const char *src, const char *dst, long keep, int garble)
{
    FILE *in = fopen(src, "rb"), *out = fopen(dst, "wb");
    assert_non_null(in);
    assert_non_null(out);
    fseek(in, 0, SEEK_END);
    long size = ftell(in);
    rewind(in);
    char *buf = malloc((size_t)size);
    assert_int_equal(fread(buf, 1, (size_t)size, in), (size_t)size);
    if (garble)
        for (long i = keep; i < size; i += 7)
            buf[i] ^= 0x5a;
    fwrite(buf, 1, (size_t)(garble ? size : keep), out);
    free(buf);
    fclose(in);
    fclose(out);
}

static void test_errors(void **state)
{
    (void)state;
    char good_vdb[512], good_nvdb[512], bad[512], cmd_out[4096];
    sdft_field f = spheres_field();
    sdft_grid_free(bake(&f, 32, 0, tu_tmp(good_vdb, sizeof good_vdb, "good.vdb")));
    sdft_grid_free(bake(&f, 32, 0, tu_tmp(good_nvdb, sizeof good_nvdb, "good.nvdb")));

    expect_error(tu_tmp(bad, sizeof bad, "missing.vdb"), NULL, SDFT_EIO, "cannot open");
    expect_error(tu_tmp(bad, sizeof bad, "missing.nvdb"), NULL, SDFT_EIO, "cannot open");
    expect_error(good_vdb, "nosuch", SDFT_ENOTFOUND, "no grid named 'nosuch'");
    expect_error(good_nvdb, "nosuch", SDFT_ENOTFOUND, "no grid named 'nosuch'");

    copy_prefix(good_vdb, tu_tmp(bad, sizeof bad, "truncated.vdb"), 600, 0);
    expect_error(bad, NULL, SDFT_EFORMAT, "cannot read");
    copy_prefix(good_vdb, tu_tmp(bad, sizeof bad, "corrupt.vdb"), 0, 1);
    expect_error(bad, NULL, SDFT_EFORMAT, "cannot read");
    copy_prefix(good_nvdb, tu_tmp(bad, sizeof bad, "truncated.nvdb"), 2000, 0);
    expect_error(bad, NULL, SDFT_EFORMAT, "truncated");
    copy_prefix(good_nvdb, tu_tmp(bad, sizeof bad, "header.nvdb"), 100, 0);
    expect_error(bad, NULL, SDFT_EFORMAT, "truncated");
    copy_prefix(good_nvdb, tu_tmp(bad, sizeof bad, "corrupt.nvdb"), 0, 1);
    expect_error(bad, NULL, SDFT_EFORMAT, "");

    /* A Vec3f grid (the sphere's gradient), written by OpenVDB's own tools. */
    char vec[512], vecn[512];
    tu_tmp(vec, sizeof vec, "vec3.vdb");
    tu_tmp(vecn, sizeof vecn, "vec3.nvdb");
    remove(vec), remove(vecn);
    int rc = tu_run(cmd_out, sizeof cmd_out,
                    "vdb_tool -quiet -sphere radius=1 dim=32 name=ball -grad keep=0 -o %s && "
                    "nanovdb_convert -f %s %s",
                    vec, vec, vecn);
    if (rc)
        print_error("%s\n", cmd_out);
    assert_int_equal(rc, 0);
    expect_error(vec, NULL, SDFT_ENOTSCALAR, "no scalar grid");
    expect_error(vecn, NULL, SDFT_ENOTSCALAR, "no scalar grid");

    /* An empty level set: a sphere eroded away. */
    char empty[512];
    tu_tmp(empty, sizeof empty, "empty.vdb");
    remove(empty);
    rc = tu_run(cmd_out, sizeof cmd_out,
                "vdb_tool -quiet -sphere radius=0.1 voxel=0.05 name=gone -erode radius=4 -o %s", empty);
    assert_int_equal(rc, 0);
    expect_error(empty, NULL, SDFT_EEMPTY, "empty");

    sdft_grid *g = NULL;
    char msg[256];
    assert_int_not_equal(tu_open_file("plain.txt", NULL, SDFT_QUANT_NONE, &g, msg, sizeof msg), 0);
}

/* Every prefix of a .vdb file is refused the same way: OpenVDB reads
 * uninitialized lengths past the end of a file, so a truncation it met
 * itself could allocate, loop or fail differently on each run. Two files:
 * one grid written by sdftrace, three by OpenVDB's vdb_tool (a prefix
 * may end inside any of them). */
static void test_every_truncation_is_refused(void **state)
{
    (void)state;
    char files[2][512], cut[512], cmd_out[4096];
    sdft_field f = spheres_field();
    sdft_grid_free(bake(&f, 32, 0, tu_tmp(files[0], sizeof files[0], "whole1.vdb")));
    tu_tmp(files[1], sizeof files[1], "whole3.vdb");
    remove(files[1]);
    int rc = tu_run(cmd_out, sizeof cmd_out,
                    "vdb_tool -quiet -sphere radius=1 dim=32 name=a -sphere radius=0.5 dim=24 name=b "
                    "-sphere radius=0.7 dim=40 name=c -o %s",
                    files[1]);
    if (rc)
        print_error("%s\n", cmd_out);
    assert_int_equal(rc, 0);
    tu_tmp(cut, sizeof cut, "cut.vdb");
    for (int k = 0; k < 2; k++) {
        FILE *in = fopen(files[k], "rb");
        assert_non_null(in);
        fseek(in, 0, SEEK_END);
        const long size = ftell(in);
        fclose(in);
        int refused = 0;
        /* every byte of the header and descriptors, then steps through the grids */
        for (long keep = 0; keep < size; keep += keep < 1024 ? 1 : 1 + size / 97) {
            copy_prefix(files[k], cut, keep, 0);
            sdft_grid *g = (sdft_grid *)1;
            char msg[512] = "";
            const sdft_error e = tu_open_file(cut, NULL, SDFT_QUANT_NONE, &g, msg, sizeof msg);
            if (e != SDFT_EFORMAT || !strstr(msg, "cannot read"))
                print_error("%ld of %ld bytes: %s %s\n", keep, size, sdft_error_name(e), msg);
            assert_int_equal(e, SDFT_EFORMAT);
            assert_null(g);
            assert_non_null(strstr(msg, "cannot read"));
            refused++;
        }
        print_message("%s: %d prefixes of %ld bytes refused\n", files[k], refused, size);
        sdft_grid *g = NULL;
        char msg[512] = "";
        assert_int_equal(tu_open_file(files[k], NULL, SDFT_QUANT_NONE, &g, msg, sizeof msg), SDFT_OK);
        sdft_grid_free(g);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_vdb),
        cmocka_unit_test(test_round_trip_nvdb),
        cmocka_unit_test(test_whole_load_is_the_readers_grid),
        cmocka_unit_test(test_grid_selection_is_the_same_for_vdb_and_nvdb),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_every_truncation_is_refused),
    };
    return cmocka_run_group_tests_name("vdb_load", tests, NULL, NULL);
}
