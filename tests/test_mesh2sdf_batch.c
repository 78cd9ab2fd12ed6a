/* mesh2sdf --batch tests: a batch with a corrupt, an empty and a NaN mesh among
 * good ones (the report's rows against the meshes' own counts, the exit
 * status, the good grids against the exact distance to a box and byte for
 * byte against one-mesh runs, a rerun that converts nothing), --shard
 * covering every mesh exactly once for several N, and mpirun -np 2 giving
 * what one process gives. */
#define _POSIX_C_SOURCE 200809L /* strdup, strtok, st_mtim */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "mesh_support.h"
#include "testutil.h"

#define RES 16
#define PATH 4096 /* a path buffer */
#define BAND 3.0

/* ---------------------------------------------------------------- files */

/* printf into a buffer of PATH bytes; the text must fit. */
static __attribute__((format(printf, 2, 3))) char *path_of(char *buf, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    const int n = vsnprintf(buf, PATH, fmt, ap);
    va_end(ap);
    assert_true(n >= 0 && n < PATH);
    return buf;
}

/* A cube of side s centred on the origin, outward quads. */
static void write_cube(const char *path, double s)
{
    static const int q[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    for (int i = 0; i < 8; i++)
        fprintf(f, "v %g %g %g\n", (i & 1) == ((i >> 1) & 1) ? -s / 2 : s / 2, i & 2 ? s / 2 : -s / 2,
                i & 4 ? s / 2 : -s / 2);
    for (int i = 0; i < 6; i++)
        fprintf(f, "f %d %d %d %d\n", q[i][0] + 1, q[i][1] + 1, q[i][2] + 1, q[i][3] + 1);
    fclose(f);
}

/* The exact signed distance to the cube of side s. */
static double cube_sdf(double s, const double *p)
{
    double out = 0, in = -INFINITY;
    for (int k = 0; k < 3; k++) {
        const double d = fabs(p[k]) - s / 2;
        out += d > 0 ? d * d : 0;
        in = fmax(in, d);
    }
    return out > 0 ? sqrt(out) : in;
}

/* Every band voxel of the dense grid NPY against the exact distance to the
 * cube of side s; returns how many voxels the band has (|d| < background). */
static long check_cube_grid(const char *npy, double s)
{
    dense g;
    read_dense(npy, &g);
    long band = 0;
    for (int i = 0; i < g.n[0]; i++)
        for (int j = 0; j < g.n[1]; j++)
            for (int k = 0; k < g.n[2]; k++) {
                const float d = dense_at(&g, i, j, k);
                if (fabs(d) >= BAND * g.h * (1 - 1e-6))
                    continue;
                double p[3];
                dense_point(&g, i, j, k, p);
                if (fabs(d - cube_sdf(s, p)) > 1e-5 * s)
                    fail_msg("%s: voxel (%d,%d,%d) is %g, the cube's distance %g", npy, i, j, k, d, cube_sdf(s, p));
                band++;
            }
    free(g.data);
    return band;
}

static int same_bytes(const char *a, const char *b)
{
    char out[256];
    return tu_run(out, sizeof out, "cmp -s '%s' '%s'", a, b) == 0;
}

static long long mtime_ns(const char *path)
{
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    return (long long)st.st_mtim.tv_sec * 1000000000ll + st.st_mtim.tv_nsec;
}

/* A fresh folder under the test folder. */
static const char *fresh_dir(char *buf, size_t len, const char *name)
{
    tu_tmp(buf, len, name);
    assert_int_equal(tu_run(NULL, 0, "rm -rf '%s' && mkdir -p '%s'", buf, buf), 0);
    return buf;
}

/* --------------------------------------------------------------- report */

/* The line of REPORT whose "mesh" is `mesh` (a copy to free), or NULL. */
static char *report_row(const char *report_path, const char *mesh)
{
    char *text = tu_slurp(report_path);
    assert_non_null(text);
    char key[PATH];
    path_of(key, "{\"mesh\": \"%s\",", mesh);
    char *row = NULL;
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n"))
        if (strncmp(line, key, strlen(key)) == 0) {
            assert_null(row); /* one row a mesh */
            row = strdup(line);
        }
    free(text);
    return row;
}

/* A string field of a row ("null" when it is null). */
static void row_string(const char *row, const char *key, char *out, size_t len)
{
    char k[64];
    snprintf(k, sizeof k, "\"%s\": ", key);
    const char *s = strstr(row, k);
    assert_non_null(s);
    s += strlen(k);
    if (strncmp(s, "null", 4) == 0) {
        snprintf(out, len, "null");
        return;
    }
    assert_int_equal(*s, '"');
    const char *end = strchr(s + 1, '"');
    assert_non_null(end);
    snprintf(out, len, "%.*s", (int)(end - s - 1), s + 1);
}

static double row_number(const char *row, const char *key)
{
    char k[64];
    snprintf(k, sizeof k, "\"%s\"", key);
    return json_number(row, k, 0);
}

static int count_lines(const char *path)
{
    char *text = tu_slurp(path);
    assert_non_null(text);
    const int n = tu_lines(text);
    free(text);
    return n;
}

/* ---------------------------------------------------------------- setup */

/* DIR/in: two cubes with the same stem (sides 1 and 2), a corrupt mesh,
 * an empty one, one with a NaN coordinate, and spot from the shared meshes by its absolute path; LIST
 * names them with a comment and a blank line between. */
static void make_batch_input(const char *dir, char *list, size_t len)
{
    char path[PATH];
    path_of(path, "%s/in/sub", dir);
    assert_int_equal(tu_run(NULL, 0, "mkdir -p '%s'", path), 0);
    path_of(path, "%s/in/cube.obj", dir);
    write_cube(path, 1.0);
    path_of(path, "%s/in/sub/cube.obj", dir);
    write_cube(path, 2.0);
    path_of(path, "%s/in/corrupt.obj", dir);
    tu_assert_write_text(path, "v 0 0 0\nv 1 0 0\nthis is not an OBJ line\nf 1 2 9\n");
    path_of(path, "%s/in/empty.obj", dir);
    tu_assert_write_text(path, "");
    path_of(path, "%s/in/nan.obj", dir);
    tu_assert_write_text(path, "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
    snprintf(list, len, "%s/in/list.txt", dir);
    char text[2048];
    snprintf(text, sizeof text,
             "# meshes of the batch test\ncube.obj\ncorrupt.obj\n\n  %s/spot.obj  \nempty.obj\nsub/cube.obj\nnan.obj\n",
             SDFT_MESH_DIR);
    tu_assert_write_text(list, text);
}

static int run_batch(const char *list, const char *out_dir, const char *extra, char *log, size_t log_len)
{
    return tu_run(log, log_len, "%s --batch '%s' --out-dir '%s' --res %d --formats vdb,npy --quiet %s", SDFT_MESH2SDF,
                  list, out_dir, RES, extra);
}

/* The outputs of a converted mesh of the batch: NAME.vdb, .npy, .json. */
static void assert_outputs(const char *out_dir, const char *name, int present)
{
    static const char *const ext[] = {"vdb", "npy", "json"};
    for (int e = 0; e < 3; e++) {
        char path[PATH], file[128];
        path_of(path, "%s/%s.%s", out_dir, name, ext[e]);
        assert_int_equal(tu_file_exists(path), present);
        path_of(file, "%s.%s", name, ext[e]);
        tu_assert_no_temporaries(out_dir, file);
    }
}

/* ---------------------------------------------------------------- tests */

static void test_batch_report(void **state)
{
    (void)state;
    char dir[PATH], list[PATH], out[PATH], report[PATH], log[8192];
    fresh_dir(dir, sizeof dir, "batch");
    make_batch_input(dir, list, sizeof list);
    path_of(out, "%s/out", dir);
    path_of(report, "%s/report.jsonl", out);

    /* Some meshes failed: exit status 2, each failure one line on stderr. */
    const int rc = run_batch(list, out, "", log, sizeof log);
    assert_int_equal(rc, 2);
    assert_int_equal(tu_lines(log), 3);
    assert_non_null(strstr(log, "corrupt.obj"));
    assert_non_null(strstr(log, "empty.obj"));
    assert_non_null(strstr(log, "nan.obj"));
    assert_int_equal(count_lines(report), 6);
    tu_assert_no_temporaries(out, "report.jsonl");

    /* The failed rows: status, an error naming the file, no outputs. */
    const char *bad[] = {"corrupt.obj", "empty.obj", "nan.obj"};
    for (int i = 0; i < 3; i++) {
        char *row = report_row(report, bad[i]);
        assert_non_null(row);
        char value[PATH];
        row_string(row, "status", value, sizeof value);
        assert_string_equal(value, "failed");
        row_string(row, "error", value, sizeof value);
        assert_non_null(strstr(value, bad[i]));
        assert_non_null(strstr(row, "\"outputs\": []"));
        free(row);
    }
    assert_outputs(out, "corrupt", 0);
    assert_outputs(out, "empty", 0);
    assert_outputs(out, "nan", 0);

    /* The cubes: one stem, two names; their rows' counts are the cube's
     * (8 vertices, 6 quads, 12 triangles, closed); their grids are the
     * exact distance to the cube, and the row's voxels the band's. */
    const char *cubes[] = {"cube.obj", "sub/cube.obj"}, *names[] = {"cube", "cube-2"};
    for (int i = 0; i < 2; i++) {
        char *row = report_row(report, cubes[i]);
        assert_non_null(row);
        char value[PATH], npy[PATH];
        row_string(row, "status", value, sizeof value);
        assert_string_equal(value, "ok");
        row_string(row, "error", value, sizeof value);
        assert_string_equal(value, "null");
        assert_int_equal((int)row_number(row, "vertices"), 8);
        assert_int_equal((int)row_number(row, "faces"), 6);
        assert_int_equal((int)row_number(row, "triangles"), 12);
        assert_int_equal((int)row_number(row, "boundary_edges"), 0);
        assert_true(row_number(row, "seconds") >= 0);
        assert_outputs(out, names[i], 1);
        path_of(npy, "%s/%s.npy", out, names[i]);
        assert_int_equal((long)row_number(row, "voxels"), check_cube_grid(npy, i == 0 ? 1.0 : 2.0));
        path_of(value, "\"%s/%s.vdb\", \"%s\", ", out, names[i], npy);
        assert_non_null(strstr(row, value));
        free(row);
    }

    /* spot, named by its absolute path: its counts are the OBJ's. */
    char spot[PATH];
    path_of(spot, "%s/spot.obj", SDFT_MESH_DIR);
    mesh m = {0};
    assert_int_equal(read_obj(spot, &m), 0);
    char *row = report_row(report, spot);
    assert_non_null(row);
    assert_int_equal((int)row_number(row, "vertices"), m.nv);
    assert_int_equal((int)row_number(row, "triangles"), m.nt);
    mesh_free(&m);
    free(row);
    assert_outputs(out, "spot", 1);

    /* Every good output is the one-mesh run's, byte for byte (the .vdb
     * aside: OpenVDB gives each file a new UUID). */
    char single[PATH];
    path_of(single, "%s/single", dir);
    assert_int_equal(tu_run(NULL, 0, "mkdir -p '%s'", single), 0);
    const char *inputs[] = {"in/cube.obj", "in/sub/cube.obj", NULL}, *outs[] = {"cube", "cube-2", "spot"};
    for (int i = 0; i < 3; i++) {
        char in[PATH], a[PATH], b[PATH];
        if (inputs[i])
            path_of(in, "%s/%s", dir, inputs[i]);
        else
            path_of(in, "%s", spot);
        assert_int_equal(tu_run(log, sizeof log, "%s '%s' -o '%s/%s.vdb' --npy '%s/%s.npy' --res %d --quiet",
                                SDFT_MESH2SDF, in, single, outs[i], single, outs[i], RES),
                         0);
        for (int e = 0; e < 2; e++) {
            path_of(a, "%s/%s.%s", out, outs[i], e ? "json" : "npy");
            path_of(b, "%s/%s.%s", single, outs[i], e ? "json" : "npy");
            if (!same_bytes(a, b))
                fail_msg("%s differs from %s", a, b);
        }
    }

    /* A rerun converts nothing: every output keeps its time, every good
     * row stays as it was; the failures are tried again and fail again. */
    const char *good[] = {"cube.obj", "sub/cube.obj", spot};
    char *before[3];
    long long times[3];
    for (int i = 0; i < 3; i++) {
        char npy[PATH];
        path_of(npy, "%s/%s.npy", out, outs[i]);
        times[i] = mtime_ns(npy);
        before[i] = report_row(report, good[i]);
    }
    assert_int_equal(run_batch(list, out, "", log, sizeof log), 2);
    assert_int_equal(count_lines(report), 6);
    for (int i = 0; i < 3; i++) {
        char npy[PATH];
        path_of(npy, "%s/%s.npy", out, outs[i]);
        assert_true(mtime_ns(npy) == times[i]);
        char *after = report_row(report, good[i]);
        assert_string_equal(after, before[i]);
        free(after);
        free(before[i]);
    }

    /* An output gone: that mesh alone is converted again. */
    char gone[PATH];
    path_of(gone, "%s/cube-2.json", out);
    assert_int_equal(unlink(gone), 0);
    assert_int_equal(run_batch(list, out, "", log, sizeof log), 2);
    assert_true(tu_file_exists(gone));
    path_of(gone, "%s/cube-2.npy", out);
    assert_true(mtime_ns(gone) != times[1]);
    path_of(gone, "%s/cube.npy", out);
    assert_true(mtime_ns(gone) == times[0]);
}

/* Shards K = 0..N-1 of a list of 7 meshes, run at once into one folder:
 * each mesh in exactly one shard's report and converted once, for N = 1..4. */
static void test_shards(void **state)
{
    (void)state;
    enum { MESHES = 7 };
    char dir[PATH], list[PATH], path[PATH];
    fresh_dir(dir, sizeof dir, "batch-shards");
    path_of(list, "%s/list.txt", dir);
    FILE *f = fopen(list, "w");
    assert_non_null(f);
    for (int i = 0; i < MESHES; i++) {
        path_of(path, "%s/c%d.obj", dir, i);
        write_cube(path, 1.0 + i);
        fprintf(f, "c%d.obj\n", i);
    }
    fclose(f);
    for (int n = 1; n <= 4; n++) {
        char out[PATH], cmd[16384] = "";
        path_of(out, "%s/out-%d", dir, n);
        for (int k = 0; k < n; k++) {
            char one[PATH];
            path_of(one, "%s --batch '%s' --out-dir '%s' --res 12 --quiet --shard %d/%d & ", SDFT_MESH2SDF, list, out,
                    k, n);
            strcat(cmd, one);
        }
        /* every shard's exit status: 0 */
        strcat(cmd, "s=0; for j in $(jobs -p); do wait $j || s=1; done; exit $s");
        assert_int_equal(tu_run(NULL, 0, "%s", cmd), 0);
        int seen[MESHES] = {0};
        for (int k = 0; k < n; k++) {
            char report[PATH];
            if (n == 1)
                path_of(report, "%s/report.jsonl", out);
            else
                path_of(report, "%s/report.%d-of-%d.jsonl", out, k, n);
            for (int i = 0; i < MESHES; i++) {
                char mesh[PATH];
                path_of(mesh, "c%d.obj", i);
                char *row = report_row(report, mesh);
                if (row) {
                    seen[i]++;
                    assert_int_equal(i % n, k); /* the documented split: positions K, K+N ... */
                    free(row);
                }
            }
        }
        for (int i = 0; i < MESHES; i++) {
            assert_int_equal(seen[i], 1);
            char name[PATH];
            path_of(name, "c%d.vdb", i);
            path_of(path, "%s/%s", out, name);
            assert_true(tu_file_exists(path));
            tu_assert_no_temporaries(out, name);
        }
    }
}

/* mpirun -np 2: the same outputs and rows as one process. Open MPI's own
 * allocations are never freed, so the ranks run with LeakSanitizer off
 * (ASAN_OPTIONS=detect_leaks=0, for the mpirun child only). */
static void test_mpi_batch(void **state)
{
    (void)state;
    char log[8192];
    if (tu_run(NULL, 0, "command -v mpirun") != 0) {
        print_message("skipped: mpirun is not installed (openmpi-bin)\n");
        return;
    }
    char dir[PATH], list[PATH], one[PATH], two[PATH];
    fresh_dir(dir, sizeof dir, "batch-mpi");
    make_batch_input(dir, list, sizeof list);
    path_of(one, "%s/one", dir);
    path_of(two, "%s/two", dir);
    assert_int_equal(run_batch(list, one, "--threads 1", log, sizeof log), 2);
    const int rc = tu_run(log, sizeof log,
                          "ASAN_OPTIONS=detect_leaks=0 mpirun -np 2 --oversubscribe %s %s --batch '%s' --out-dir '%s' "
                          "--res %d --formats vdb,npy --quiet --threads 1",
                          geteuid() == 0 ? "--allow-run-as-root" : "", SDFT_MESH2SDF, list, two, RES);
    if (strstr(log, "built without MPI")) {
        print_message("skipped: this mesh2sdf was built without MPI\n");
        return;
    }
    if (rc != 2)
        fail_msg("mpirun gave %d, not 2: %s", rc, log);
    char r1[PATH], r2[PATH];
    path_of(r1, "%s/report.jsonl", one);
    path_of(r2, "%s/report.jsonl", two);
    assert_int_equal(count_lines(r2), 6);
    char spot[PATH];
    path_of(spot, "%s/spot.obj", SDFT_MESH_DIR);
    const char *meshes[] = {"cube.obj", "corrupt.obj", spot, "empty.obj", "sub/cube.obj", "nan.obj"};
    const char *names[] = {"cube", "corrupt", "spot", "empty", "cube-2", "nan"};
    for (int i = 0; i < 6; i++) {
        char *a = report_row(r1, meshes[i]), *b = report_row(r2, meshes[i]);
        assert_non_null(a);
        assert_non_null(b);
        char sa[PATH], sb[PATH];
        row_string(a, "status", sa, sizeof sa);
        row_string(b, "status", sb, sizeof sb);
        assert_string_equal(sa, sb);
        if (strcmp(sa, "ok") == 0) {
            assert_true(row_number(a, "voxels") == row_number(b, "voxels"));
            for (int e = 0; e < 2; e++) {
                char fa[PATH], fb[PATH];
                path_of(fa, "%s/%s.%s", one, names[i], e ? "json" : "npy");
                path_of(fb, "%s/%s.%s", two, names[i], e ? "json" : "npy");
                if (!same_bytes(fa, fb))
                    fail_msg("%s differs from %s", fa, fb);
            }
        }
        free(a);
        free(b);
    }
}

/* On a terminal (script(1)), a progress line counts the meshes up with the
 * time left; through a pipe, none; the help lists the batch's options. */
/* --formats samples: each mesh's training samples, the same bytes as a
 * one-mesh --samples run, beside its grid or alone; a rerun skips them. */
static void test_batch_samples(void **state)
{
    (void)state;
    char dir[PATH], list[PATH], out[PATH], single[PATH], path[PATH], log[8192];
    fresh_dir(dir, sizeof dir, "batch_samples");
    path_of(path, "%s/cube.obj", dir);
    write_cube(path, 1.0);
    path_of(list, "%s/list.txt", dir);
    char text[PATH];
    path_of(text, "cube.obj\n%s/spot.obj\n", SDFT_MESH_DIR);
    tu_assert_write_text(list, text);
    for (int both = 0; both < 2; both++) {
        path_of(out, "%s/out%d", dir, both);
        const char *formats = both ? "vdb,samples" : "samples";
        int rc = tu_run(log, sizeof log,
                        "%s --batch '%s' --out-dir '%s' --res %d --formats %s --sample-count 700 --seed 5 --quiet",
                        SDFT_MESH2SDF, list, out, RES, formats);
        assert_int_equal(rc, 0);
        const char *const names[2] = {"cube", "spot"};
        for (int m = 0; m < 2; m++) {
            path_of(single, "%s/single-%s.npy", dir, names[m]);
            if (both == 0) {
                path_of(path, m ? "%s/spot.obj" : "%s/cube.obj", m ? SDFT_MESH_DIR : dir);
                assert_int_equal(
                    tu_run(log, sizeof log, "%s '%s' --samples 700 '%s' --seed 5 --quiet", SDFT_MESH2SDF, path, single),
                    0);
            }
            path_of(path, "%s/%s.samples.npy", out, names[m]);
            assert_true(same_bytes(path, single));
            path_of(path, "%s/%s.samples.json", out, names[m]);
            assert_true(tu_file_exists(path));
            path_of(path, "%s/%s.vdb", out, names[m]);
            assert_int_equal(tu_file_exists(path), both);
        }
        char report[PATH], *row;
        path_of(report, "%s/report.jsonl", out);
        path_of(path, "%s/spot.obj", SDFT_MESH_DIR);
        row = report_row(report, path);
        assert_non_null(row);
        assert_true(row_number(row, "samples") == 700);
        assert_int_equal(strstr(row, "\"voxels\"") != NULL, both);
        free(row);
        /* A rerun with the same options converts nothing: the samples stay
         * as they were; with another seed they are drawn again. */
        path_of(path, "%s/cube.samples.npy", out);
        const long long before = mtime_ns(path);
        for (int seed = 5; seed <= 6; seed++) {
            rc = tu_run(log, sizeof log,
                        "%s --batch '%s' --out-dir '%s' --res %d --formats %s --sample-count 700 --seed %d --quiet",
                        SDFT_MESH2SDF, list, out, RES, formats, seed);
            assert_int_equal(rc, 0);
            assert_int_equal(mtime_ns(path) == before, seed == 5);
        }
    }
    /* Samples in a batch are asked for with --formats, not --samples. */
    assert_int_not_equal(
        tu_run(log, sizeof log, "%s --batch '%s' --out-dir '%s' --samples 10 x.npy", SDFT_MESH2SDF, list, out), 0);
    assert_non_null(strstr(log, "--formats samples"));
}

/* --normalize in a batch of grids and samples puts the samples in the
 * unit sphere, as a one-mesh --samples --normalize run writes them, and
 * leaves the grids in the mesh's units, as a batch without it writes
 * them. Samples that do not fit the memory are the mesh's failed row,
 * with nothing of it left in DIR. */
static void test_batch_normalize_and_memory(void **state)
{
    (void)state;
    char dir[PATH], list[PATH], out[PATH], plain[PATH], single[PATH], path[PATH], log[8192], text[PATH];
    fresh_dir(dir, sizeof dir, "batch_normalize");
    path_of(list, "%s/list.txt", dir);
    path_of(text, "%s/spot.obj\n", SDFT_MESH_DIR);
    tu_assert_write_text(list, text);
    path_of(out, "%s/normalized", dir);
    path_of(plain, "%s/plain", dir);
    assert_int_equal(tu_run(log, sizeof log,
                            "%s --batch '%s' --out-dir '%s' --res %d --formats npy,samples --sample-count 600 "
                            "--normalize --quiet",
                            SDFT_MESH2SDF, list, out, RES),
                     0);
    assert_int_equal(tu_run(log, sizeof log, "%s --batch '%s' --out-dir '%s' --res %d --formats npy --quiet",
                            SDFT_MESH2SDF, list, plain, RES),
                     0);
    path_of(single, "%s/single.npy", dir);
    path_of(path, "%s/spot.obj", SDFT_MESH_DIR);
    assert_int_equal(
        tu_run(log, sizeof log, "%s '%s' --samples 600 '%s' --normalize --quiet", SDFT_MESH2SDF, path, single), 0);
    path_of(path, "%s/spot.samples.npy", out);
    assert_true(same_bytes(path, single));
    char a[PATH], b[PATH];
    path_of(a, "%s/spot.npy", out);
    path_of(b, "%s/spot.npy", plain);
    assert_true(same_bytes(a, b));

    /* 100,000,000 samples under a 200 MB limit: refused before the mesh is
     * read, the row says how much they need, and DIR holds only the
     * report. */
    path_of(out, "%s/memory", dir);
    const int rc = tu_run(log, sizeof log,
                          "SDFT_MEMORY_LIMIT=200000000 %s --batch '%s' --out-dir '%s' --formats vdb,samples "
                          "--sample-count 100000000 --res %d 2>&1",
                          SDFT_MESH2SDF, list, out, RES);
    assert_int_equal(rc, 2);
    assert_non_null(strstr(log, "needs ~"));
    char listing[4096];
    assert_int_equal(tu_run(listing, sizeof listing, "ls -A '%s'", out), 0);
    assert_string_equal(listing, "report.jsonl\n");
}

static void test_batch_progress_and_help(void **state)
{
    (void)state;
    static char out[65536];
    assert_int_equal(tu_run(out, sizeof out, "%s --help", SDFT_MESH2SDF), 0);
    const char *flags[] = {"--batch LIST", "--out-dir DIR", "--formats", "--shard K/N", "mpirun"};
    for (size_t i = 0; i < sizeof flags / sizeof *flags; i++)
        if (!strstr(out, flags[i]))
            fail_msg("--help does not list %s", flags[i]);

    char dir[PATH], list[PATH], path[PATH];
    fresh_dir(dir, sizeof dir, "batch-progress");
    path_of(list, "%s/list.txt", dir);
    tu_assert_write_text(list, "a.obj\nb.obj\nc.obj\n");
    for (int i = 0; i < 3; i++) {
        path_of(path, "%s/%c.obj", dir, 'a' + i);
        write_cube(path, 1.0 + i);
    }
    assert_int_equal(tu_run(out, sizeof out, "%s --batch '%s' --out-dir '%s/piped' --res 12", SDFT_MESH2SDF, list, dir),
                     0);
    assert_null(strstr(out, "\r["));
    assert_int_equal(tu_lines(out), 4); /* a line a mesh, and the summary */
    assert_non_null(strstr(out, "3 converted, 0 skipped, 0 failed"));

    if (!tu_file_exists("/usr/bin/script") || tu_run(out, sizeof out, "script -qec true /dev/null") != 0) {
        print_message("skipped: no script(1) or no pseudo-terminal to give mesh2sdf a terminal\n");
        return;
    }
    assert_int_equal(tu_run(out, sizeof out, "script -qec \"%s --batch '%s' --out-dir '%s/tty' --res 12\" /dev/null",
                            SDFT_MESH2SDF, list, dir),
                     0);
    int next = 0;
    for (const char *f = strstr(out, "\r["); f; f = strstr(f + 2, "\r[")) {
        int percent = -1, done = -1, total = -1;
        const char *close = strchr(f, ']');
        assert_non_null(close);
        assert_true(sscanf(close + 1, " %d%% %d/%d meshes", &percent, &done, &total) == 3);
        assert_int_equal(total, 3);
        assert_int_equal(done, next); /* each count once, in order */
        assert_int_equal(percent, 100 * done / 3);
        if (done > 0)
            assert_non_null(strstr(close, " left"));
        next++;
    }
    assert_int_equal(next, 3); /* 0, 1 and 2 of 3; the bar is gone at the end */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_batch_report),
        cmocka_unit_test(test_shards),
        cmocka_unit_test(test_mpi_batch),
        cmocka_unit_test(test_batch_samples),
        cmocka_unit_test(test_batch_normalize_and_memory),
        cmocka_unit_test(test_batch_progress_and_help),
    };
    return cmocka_run_group_tests_name("mesh2sdf_batch", tests, NULL, NULL);
}
