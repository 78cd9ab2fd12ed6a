/* mesh2sdf's part of the mesh component (src/mesh/tool/mesh_tool.h): a set
 * of files reserved before the work and written together, nothing left
 * behind when it is freed or fails; a conversion planned as it is built;
 * grids' signs checked against the exact winding number; the sample counts
 * and the sidecar's name. The truth is computed here: brute-force winding
 * numbers and distances, directory listings, file magic numbers. */
#define _POSIX_C_SOURCE 200809L /* setenv, opendir */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "mesh_lib_support.h"
#include "mesh_support.h"
#include "mesh_tool.h"
#include "sdftrace/mesh.h"
#include "sdftrace/vdb.h"
#include "testutil.h"

#define SUZANNE SDFT_MESH_DIR "/suzanne.obj"
#define SPOT SDFT_MESH_DIR "/spot.obj"

/* A fresh empty folder under the tests' temporary folder. */
static void fresh_dir(char *dir, size_t len, const char *name)
{
    char out[512];
    tu_tmp(dir, len, name);
    tu_run(out, sizeof out, "rm -rf '%s' && mkdir -p '%s'", dir, dir);
}

/* How many entries a folder holds, dot files included. */
static int entries(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* --------------------------------------------------------------- file sets */

/* Reserving makes one hidden temporary file per destination (two for an
 * .npy) and nothing at the destinations; freeing removes them all. */
static void reserved_then_freed_leaves_nothing(void **state)
{
    (void)state;
    char dir[256], vdb[320], npy[320];
    fresh_dir(dir, sizeof dir, "files_freed");
    snprintf(vdb, sizeof vdb, "%s/a.vdb", dir);
    snprintf(npy, sizeof npy, "%s/a.npy", dir);
    const mesh_file files[] = {{vdb, SDFT_MESH_FORMAT_VDB}, {npy, SDFT_MESH_FORMAT_NPY}};
    mesh_files *set = NULL;
    char msg[256] = "";
    assert_int_equal(mesh_files_reserve(files, 2, &set, msg, sizeof msg), SDFT_OK);
    assert_int_equal(entries(dir), 3);
    assert_false(exists(vdb));
    assert_false(exists(npy));
    mesh_files_free(set);
    assert_int_equal(entries(dir), 0);
}

/* A folder that is missing fails at reservation, before any work, and
 * leaves the other destinations' temporaries removed. */
static void missing_folder_fails_first(void **state)
{
    (void)state;
    char dir[256], ok[320], bad[320];
    fresh_dir(dir, sizeof dir, "files_missing");
    snprintf(ok, sizeof ok, "%s/ok.vdb", dir);
    snprintf(bad, sizeof bad, "%s/no/such/folder/x.nvdb", dir);
    const mesh_file files[] = {{ok, SDFT_MESH_FORMAT_VDB}, {bad, SDFT_MESH_FORMAT_NVDB}};
    mesh_files *set = (mesh_files *)&set;
    char msg[256] = "";
    assert_int_equal(mesh_files_reserve(files, 2, &set, msg, sizeof msg), SDFT_EIO);
    assert_null(set);
    assert_non_null(strstr(msg, "No such file"));
    assert_int_equal(entries(dir), 0);
}

/* A write that fails after the reservation (one destination's folder is
 * gone by then) replaces nothing and leaves no temporary file in the
 * other folder. */
static void failed_write_leaves_nothing(void **state)
{
    (void)state;
    char dir[256], gone[256], vdb[320], npy[320], out[512], msg[256] = "";
    fresh_dir(dir, sizeof dir, "files_failed");
    fresh_dir(gone, sizeof gone, "files_gone");
    snprintf(vdb, sizeof vdb, "%s/a.vdb", dir);
    snprintf(npy, sizeof npy, "%s/a.npy", gone);
    const mesh_file files[] = {{vdb, SDFT_MESH_FORMAT_VDB}, {npy, SDFT_MESH_FORMAT_NPY}};
    mesh_files *set = NULL;
    assert_int_equal(mesh_files_reserve(files, 2, &set, msg, sizeof msg), SDFT_OK);
    assert_int_equal(entries(dir), 1);
    tu_run(out, sizeof out, "rm -rf '%s'", gone);
    sdft_mesh *m = load_with(SUZANNE, NULL);
    sdft_mesh_grid *g = grid_of(m, 24);
    assert_int_equal(mesh_files_write_grid(set, g, 0, msg, sizeof msg), SDFT_EIO);
    assert_int_equal(entries(dir), 0);
    mesh_files_free(set);
    sdft_mesh_grid_free(g);
    sdft_mesh_free(m);
}

/* The planned box is the built one, found without building; sizes the
 * limits or the memory refuse are refused here too, with their codes. */
static void planned_as_built(void **state)
{
    (void)state;
    char msg[256] = "";
    sdft_mesh *m = load_with(SPOT, NULL);
    sdft_mesh_grid_params p = sdft_mesh_grid_params_defaults();
    p.res = 40;
    p.band = 2;
    sdft_mesh_grid_box planned, built;
    assert_int_equal(mesh_grid_plan(m, &p, &planned, msg, sizeof msg), SDFT_OK);
    sdft_mesh_grid *g = NULL;
    assert_int_equal(sdft_mesh_to_grid(m, &p, &g, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_grid_get_box(g, &built, msg, sizeof msg), SDFT_OK);
    assert_memory_equal(planned.dims, built.dims, sizeof built.dims);
    assert_memory_equal(planned.origin, built.origin, sizeof built.origin);
    assert_true(planned.voxel_size == built.voxel_size);
    assert_true(planned.background == built.background);
    sdft_mesh_grid_free(g);

    p.voxel_size = 1e-6; /* far more than 4096 voxels a side */
    assert_int_equal(mesh_grid_plan(m, &p, &planned, msg, sizeof msg), SDFT_EINVAL);
    p.voxel_size = 0;
    p.res = 2000;
    p.full = 1; /* 8 billion voxels: over the dense limit */
    assert_int_equal(mesh_grid_plan(m, &p, &planned, msg, sizeof msg), SDFT_EINVAL);
    p.full = 0;
    setenv("SDFT_MEMORY_LIMIT", "1000000", 1);
    assert_int_equal(mesh_grid_plan(m, &p, &planned, msg, sizeof msg), SDFT_ENOMEM);
    assert_non_null(strstr(msg, "needs ~"));
    unsetenv("SDFT_MEMORY_LIMIT");
    sdft_mesh_free(m);
}

/* Written together: every destination in place, named as reserved whatever
 * its extension (an OpenVDB file under .level), the .npy's array the dense
 * copy, no temporary left; the set is spent after. */
static void written_together(void **state)
{
    (void)state;
    char dir[256], level[320], nvdb[320], npy[320], json[320];
    fresh_dir(dir, sizeof dir, "files_written");
    snprintf(level, sizeof level, "%s/g.level", dir);
    snprintf(nvdb, sizeof nvdb, "%s/g.nvdb", dir);
    snprintf(npy, sizeof npy, "%s/g.npy", dir);
    snprintf(json, sizeof json, "%s/g.json", dir);
    const mesh_file files[] = {
        {level, SDFT_MESH_FORMAT_VDB}, {nvdb, SDFT_MESH_FORMAT_NVDB}, {npy, SDFT_MESH_FORMAT_NPY}};
    mesh_files *set = NULL;
    char msg[256] = "";
    assert_int_equal(mesh_files_reserve(files, 3, &set, msg, sizeof msg), SDFT_OK);
    sdft_mesh *m = load_with(SUZANNE, NULL);
    sdft_mesh_grid *g = grid_of(m, 40);
    assert_int_equal(mesh_files_write_grid(set, g, 0, msg, sizeof msg), SDFT_OK);
    assert_int_equal(entries(dir), 4);
    assert_true(exists(json));
    assert_int_equal(mesh_files_write_grid(set, g, 0, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "already"));
    mesh_files_free(set);
    assert_int_equal(entries(dir), 4);

    /* OpenVDB's magic number (0x56444220, "VDB " little-endian) heads the
     * .level file, and NanoVDB's ("NanoVDB0") the .nvdb. */
    FILE *f = fopen(level, "rb");
    unsigned char head[8];
    assert_int_equal(fread(head, 1, 8, f), 8);
    fclose(f);
    assert_memory_equal(head, "\x20\x42\x44\x56", 4);
    f = fopen(nvdb, "rb");
    assert_int_equal(fread(head, 1, 8, f), 8);
    fclose(f);
    assert_memory_equal(head, "NanoVDB0", 8);

    /* The .npy's array is the dense copy, after its 64-byte aligned header. */
    sdft_mesh_grid_box box;
    assert_int_equal(sdft_mesh_grid_get_box(g, &box, msg, sizeof msg), SDFT_OK);
    const size_t n = (size_t)box.dims[0] * (size_t)box.dims[1] * (size_t)box.dims[2];
    float *dense = malloc(n * sizeof(float)), *read = malloc(n * sizeof(float));
    assert_int_equal(sdft_mesh_grid_dense(g, dense, n, msg, sizeof msg), SDFT_OK);
    f = fopen(npy, "rb");
    unsigned char pre[10];
    assert_int_equal(fread(pre, 1, 10, f), 10);
    const long data = 10 + pre[8] + 256 * pre[9];
    assert_int_equal(data % 64, 0);
    fseek(f, data, SEEK_SET);
    assert_int_equal(fread(read, sizeof(float), n, f), n);
    fclose(f);
    assert_memory_equal(read, dense, n * sizeof(float));
    free(dense);
    free(read);
    sdft_mesh_grid_free(g);
    sdft_mesh_free(m);
}

static void bad_file_sets(void **state)
{
    (void)state;
    char msg[256] = "";
    mesh_files *set = NULL;
    const mesh_file none[] = {{NULL, SDFT_MESH_FORMAT_VDB}};
    const mesh_file weird[] = {{"x.vdb", (sdft_mesh_format)9}};
    assert_int_equal(mesh_files_reserve(NULL, 1, &set, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(mesh_files_reserve(none, 0, &set, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(mesh_files_reserve(none, 1, &set, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(mesh_files_reserve(weird, 1, &set, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "format"));
    assert_null(set);
    assert_int_equal(mesh_files_write_grid(NULL, NULL, 0, msg, sizeof msg), SDFT_EINVAL);
    mesh_files_free(NULL);
}

/* --------------------------------------------------------------- sign check */

/* One grid right and one with every sign wrong (the mesh's faces reversed
 * and kept so: it is inside out, so nothing is inside), checked on the same
 * points: the right one has no wrong point, the wrong one has about as many
 * as the box has inside, by a brute-force Monte Carlo estimate here. */
static void sign_check_against_brute_force(void **state)
{
    (void)state;
    mesh bm = {0};
    assert_int_equal(read_obj(SPOT, &bm), 0);
    char dir[256], right[320], wrong[320], msg[256] = "";
    fresh_dir(dir, sizeof dir, "sign_check");
    snprintf(right, sizeof right, "%s/right.vdb", dir);
    snprintf(wrong, sizeof wrong, "%s/wrong.vdb", dir);

    sdft_mesh *m = load_with(SPOT, NULL);
    sdft_mesh_grid *g = grid_of(m, 48);
    assert_int_equal(sdft_mesh_grid_write(g, right, SDFT_MESH_FORMAT_VDB, 0, msg, sizeof msg), SDFT_OK);
    sdft_mesh_grid_free(g);

    int *reversed = malloc(sizeof(int) * 3 * (size_t)bm.nt);
    for (int t = 0; t < bm.nt; t++) {
        reversed[t * 3] = bm.t[t * 3];
        reversed[t * 3 + 1] = bm.t[t * 3 + 2];
        reversed[t * 3 + 2] = bm.t[t * 3 + 1];
    }
    sdft_mesh_params raw = sdft_mesh_params_defaults();
    raw.orient = 0;
    sdft_mesh *inside_out = NULL;
    assert_int_equal(sdft_mesh_from_arrays(bm.v, SDFT_MESH_FLOAT64, (size_t)bm.nv, reversed, SDFT_MESH_INT32,
                                           (size_t)bm.nt, &raw, &inside_out, msg, sizeof msg),
                     SDFT_OK);
    g = grid_of(inside_out, 48);
    assert_int_equal(sdft_mesh_grid_write(g, wrong, SDFT_MESH_FORMAT_VDB, 0, msg, sizeof msg), SDFT_OK);
    sdft_mesh_grid_free(g);

    const char *grids[] = {right, wrong};
    mesh_sign_counts checks[2];
    const int points = 4000;
    assert_int_equal(mesh_sign_check(m, grids, 2, points, checks, msg, sizeof msg), SDFT_OK);
    assert_int_equal(checks[0].clear, checks[1].clear);
    assert_true(checks[0].clear > (uint64_t)points / 2);
    assert_int_equal(checks[0].wrong, 0);

    /* The share of the grown box inside spot, by brute force. */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < bm.nv; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], bm.v[v * 3 + k]);
            hi[k] = fmax(hi[k], bm.v[v * 3 + k]);
        }
    tu_rng r = tu_rng_seed(7);
    int inside = 0;
    const int trials = 3000;
    for (int i = 0; i < trials; i++) {
        double q[3];
        for (int k = 0; k < 3; k++) {
            const double grow = 0.05 * (hi[k] - lo[k]);
            q[k] = tu_uniform(&r, (float)(lo[k] - grow), (float)(hi[k] + grow));
        }
        inside += winding(&bm, q) > 0.5;
    }
    const double share_inside = (double)inside / trials;
    const double share_wrong = (double)checks[1].wrong / (double)checks[1].clear;
    /* Clear points leave out a voxel's shell around the surface, which
     * holds more of the inside than of the outside: a wide tolerance. */
    assert_true(share_inside > 0.05);
    assert_true(fabs(share_wrong - share_inside) < 0.1);

    const char *missing[] = {"/nonexistent/grid.vdb"};
    assert_int_equal(mesh_sign_check(m, missing, 1, 100, checks, msg, sizeof msg), SDFT_EIO);
    assert_int_equal(mesh_sign_check(m, grids, 2, 0, checks, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(mesh_sign_check(m, grids, 0, 100, checks, msg, sizeof msg), SDFT_EINVAL);
    sdft_mesh_free(inside_out);
    sdft_mesh_free(m);
    free(reversed);
    mesh_free(&bm);
}

/* round(share n) uniform rows, the rest near, the first sigma's half
 * rounded up; and the rows say so: the uniform ones fill the cube around
 * the sphere, the near ones hug the surface. */
static void sample_counts(void **state)
{
    (void)state;
    sdft_mesh_sample_params p = sdft_mesh_sample_params_defaults();
    p.count = 1001;
    p.uniform_share = 0.06;
    size_t near0, near1, uniform;
    mesh_sample_counts(&p, &near0, &near1, &uniform);
    assert_int_equal(uniform, 60); /* 60.06 rounded */
    assert_int_equal(near0, 471);
    assert_int_equal(near1, 470);
    p.uniform_share = 1;
    mesh_sample_counts(&p, &near0, NULL, &uniform);
    assert_int_equal(uniform, 1001);
    assert_int_equal(near0, 0);
}

static void sidecar_names(void **state)
{
    (void)state;
    char out[64];
    assert_int_equal(mesh_sidecar_path("a/b.npy", out, sizeof out), 8);
    assert_string_equal(out, "a/b.json");
    assert_int_equal(mesh_sidecar_path("x.bin", out, sizeof out), 10);
    assert_string_equal(out, "x.bin.json");
    assert_int_equal(mesh_sidecar_path("long/name.npy", out, 5), 14);
    assert_string_equal(out, "long");
    assert_int_equal(mesh_sidecar_path("q.npy", NULL, 0), 6);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reserved_then_freed_leaves_nothing),
        cmocka_unit_test(missing_folder_fails_first),
        cmocka_unit_test(written_together),
        cmocka_unit_test(failed_write_leaves_nothing),
        cmocka_unit_test(planned_as_built),
        cmocka_unit_test(bad_file_sets),
        cmocka_unit_test(sign_check_against_brute_force),
        cmocka_unit_test(sample_counts),
        cmocka_unit_test(sidecar_names),
    };
    return cmocka_run_group_tests_name("mesh_tool", tests, NULL, NULL);
}
