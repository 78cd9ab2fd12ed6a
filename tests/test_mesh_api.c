/* The mesh component's C API (sdftrace/mesh.h), held to truth computed
 * here and to the converter's own files: distances against brute force
 * over every triangle, winding numbers against summed solid angles, one
 * mesh queried from several threads at once; the queries' values, the
 * samples' rows and the grids' .npy and .nvdb bytes against what mesh2sdf
 * writes for the same options; bad arguments refused with their code and a
 * line; long calls (queries of many points too) cancelled from their
 * progress callback. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_lib_support.h"
#include "mesh_support.h"
#include "mesh_tool.h"
#include "sdftrace/mesh.h"
#include "testutil.h"

#define SUZANNE SDFT_MESH_DIR "/suzanne.obj"
#define SPOT SDFT_MESH_DIR "/spot.obj"

/* A winding number this far from 1/2 decides the sign. */
#define CLEAR 0.1

/* The brute-force mesh of a file (read here, not by the library). */
static mesh read_mesh(const char *path)
{
    mesh m = {0};
    assert_int_equal(read_obj(path, &m), 0);
    return m;
}

/* n random points in the box of m grown by a quarter on each side. */
static double *random_points(const mesh *m, int n, uint64_t seed)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < m->nv; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m->v[v * 3 + k]);
            hi[k] = fmax(hi[k], m->v[v * 3 + k]);
        }
    tu_rng r = tu_rng_seed(seed);
    double *p = malloc(sizeof(double) * 3 * (size_t)n);
    for (int i = 0; i < n * 3; i++) {
        const int k = i % 3;
        const double pad = 0.25 * (hi[k] - lo[k]);
        p[i] = tu_uniform(&r, (float)(lo[k] - pad), (float)(hi[k] + pad));
    }
    return p;
}

static sdft_mesh *load(const char *path)
{
    sdft_mesh *m = NULL;
    char msg[256] = "";
    assert_int_equal(sdft_mesh_load(path, NULL, &m, msg, sizeof msg), SDFT_OK);
    assert_non_null(m);
    return m;
}

/* Distances and winding numbers at points in float64 C order, against
 * brute force: the distance to float precision everywhere, the sign where
 * the winding number is clear. */
static void distances_match_brute_force(void **state)
{
    (void)state;
    mesh b = read_mesh(SUZANNE);
    sdft_mesh *m = load(SUZANNE);
    enum { N = 400 };
    double *p = random_points(&b, N, 1);
    float d[N], w[N], w2[N];
    sdft_mesh_points pts = {.data = p, .type = SDFT_MESH_FLOAT64, .count = N};
    char msg[256] = "";
    assert_int_equal(sdft_mesh_signed_distance(m, &pts, d, w, NULL, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_winding_number(m, &pts, w2, NULL, msg, sizeof msg), SDFT_OK);
    int clear = 0;
    for (int i = 0; i < N; i++) {
        const double truth = mesh_distance(&b, &p[i * 3]);
        assert_true(fabs(fabs(d[i]) - truth) <= 1e-5 * (1 + truth));
        const double wt = winding(&b, &p[i * 3]);
        assert_true(fabs(w[i] - wt) < 0.02);
        assert_true(w2[i] == w[i]);
        if (fabs(wt - 0.5) > CLEAR) {
            assert_true((d[i] < 0) == (wt > 0.5));
            clear++;
        }
    }
    assert_true(clear > N / 2);
    free(p);
    sdft_mesh_free(m);
    mesh_free(&b);
}

/* The same points as float32 in Fortran order (strides of an (n, 3)
 * array stored column by column) give the same answers as float32 rows. */
static void strided_points(void **state)
{
    (void)state;
    mesh b = read_mesh(SUZANNE);
    sdft_mesh *m = load(SUZANNE);
    enum { N = 100 };
    double *p = random_points(&b, N, 2);
    float rows[N * 3], columns[N * 3], d1[N], d2[N];
    for (int i = 0; i < N; i++)
        for (int k = 0; k < 3; k++)
            rows[i * 3 + k] = columns[k * N + i] = (float)p[i * 3 + k];
    sdft_mesh_points a = {.data = rows, .type = SDFT_MESH_FLOAT32, .count = N};
    sdft_mesh_points f = {.data = columns, .type = SDFT_MESH_FLOAT32, .count = N, .stride = {4, 4 * N}};
    assert_int_equal(sdft_mesh_signed_distance(m, &a, d1, NULL, NULL, NULL, 0), SDFT_OK);
    assert_int_equal(sdft_mesh_signed_distance(m, &f, d2, NULL, NULL, NULL, 0), SDFT_OK);
    assert_memory_equal(d1, d2, sizeof d1);
    for (int i = 0; i < N; i++) {
        const double q[3] = {rows[i * 3], rows[i * 3 + 1], rows[i * 3 + 2]};
        assert_true(fabs(fabs(d1[i]) - mesh_distance(&b, q)) <= 1e-5 * (1 + fabs(d1[i])));
    }
    free(p);
    sdft_mesh_free(m);
    mesh_free(&b);
}

/* A mesh from arrays (float64 vertices, int64 faces) is the file's mesh:
 * the same counts and the same distances. */
static void arrays_as_the_file(void **state)
{
    (void)state;
    mesh b = read_mesh(SUZANNE);
    int64_t *faces = malloc(sizeof(int64_t) * 3 * (size_t)b.nt);
    for (int i = 0; i < b.nt * 3; i++)
        faces[i] = b.t[i];
    sdft_mesh *a = NULL, *f = load(SUZANNE);
    char msg[256] = "";
    assert_int_equal(sdft_mesh_from_arrays(b.v, SDFT_MESH_FLOAT64, (size_t)b.nv, faces, SDFT_MESH_INT64, (size_t)b.nt,
                                           NULL, &a, msg, sizeof msg),
                     SDFT_OK);
    sdft_mesh_health ia, ifile;
    assert_int_equal(sdft_mesh_get_health(a, &ia, NULL, 0), SDFT_OK);
    assert_int_equal(sdft_mesh_get_health(f, &ifile, NULL, 0), SDFT_OK);
    assert_int_equal(ia.vertices, (uint64_t)b.nv);
    assert_int_equal(ia.triangles, ifile.triangles);
    assert_int_equal(ia.boundary_edges, ifile.boundary_edges);
    assert_int_equal(ia.welded_vertices, ifile.welded_vertices);
    assert_int_equal(ia.reoriented_faces, ifile.reoriented_faces);
    enum { N = 64 };
    double *p = random_points(&b, N, 3);
    float da[N], df[N];
    sdft_mesh_points pts = {.data = p, .type = SDFT_MESH_FLOAT64, .count = N};
    assert_int_equal(sdft_mesh_signed_distance(a, &pts, da, NULL, NULL, NULL, 0), SDFT_OK);
    assert_int_equal(sdft_mesh_signed_distance(f, &pts, df, NULL, NULL, NULL, 0), SDFT_OK);
    assert_memory_equal(da, df, sizeof da);
    free(p);
    free(faces);
    sdft_mesh_free(a);
    sdft_mesh_free(f);
    mesh_free(&b);
}

/* One mesh queried from several threads at once, its hierarchies built
 * by whichever query comes first: each thread's answers are the ones a
 * lone query gives. */
static void queried_from_threads(void **state)
{
    (void)state;
    mesh b = read_mesh(SUZANNE);
    sdft_mesh *m = load(SUZANNE);
    enum { N = 512, THREADS = 8 };
    double *p = random_points(&b, N, 4);
    float alone[N], together[N];
    int failures = 0;
#pragma omp parallel for num_threads(THREADS) reduction(+ : failures)
    for (int t = 0; t < THREADS; t++) {
        sdft_mesh_points part = {.data = p + t * (N / THREADS) * 3, .type = SDFT_MESH_FLOAT64, .count = N / THREADS};
        failures += sdft_mesh_signed_distance(m, &part, together + t * (N / THREADS), NULL, NULL, NULL, 0) != SDFT_OK;
    }
    assert_int_equal(failures, 0);
    sdft_mesh_points all = {.data = p, .type = SDFT_MESH_FLOAT64, .count = N};
    assert_int_equal(sdft_mesh_signed_distance(m, &all, alone, NULL, NULL, NULL, 0), SDFT_OK);
    assert_memory_equal(alone, together, sizeof alone);
    free(p);
    sdft_mesh_free(m);
    mesh_free(&b);
}

/* The bytes of a file after offset `skip`, and their count. */
static unsigned char *file_bytes(const char *path, size_t skip, size_t *len)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    const long size = ftell(f);
    assert_true(size >= (long)skip);
    fseek(f, (long)skip, SEEK_SET);
    *len = (size_t)size - skip;
    unsigned char *data = malloc(*len + 1);
    assert_int_equal(fread(data, 1, *len, f), *len);
    fclose(f);
    return data;
}

/* The offset of a .npy file's data: its preamble and header. */
static size_t npy_data_offset(const char *path)
{
    size_t len;
    unsigned char *pre = file_bytes(path, 0, &len);
    assert_true(len >= 10);
    const size_t off = 10 + (pre[8] | (size_t)pre[9] << 8);
    free(pre);
    return off;
}

/* Writes n points as an (n, 3) float64 C-order .npy file, NumPy's format 1.0. */
static void write_points_npy(const char *path, const double *p, int n)
{
    char header[128];
    int len = snprintf(header, sizeof header, "{'descr': '<f8', 'fortran_order': False, 'shape': (%d, 3), }", n);
    while ((10 + len + 1) % 64)
        header[len++] = ' ';
    header[len++] = '\n';
    const unsigned char magic[10] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0, (unsigned char)len, 0};
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fwrite(magic, 1, sizeof magic, f);
    fwrite(header, 1, (size_t)len, f);
    fwrite(p, sizeof(double), 3 * (size_t)n, f);
    fclose(f);
}

/* Distances and winding numbers are the values mesh2sdf --query --winding
 * writes for the same points: rows (d, w), float32. */
static void queries_as_the_cli(void **state)
{
    (void)state;
    mesh b = read_mesh(SUZANNE);
    enum { N = 300 };
    double *p = random_points(&b, N, 6);
    char in[256], out_npy[256], out[512];
    write_points_npy(tu_tmp(in, sizeof in, "mesh_api_points.npy"), p, N);
    tu_tmp(out_npy, sizeof out_npy, "mesh_api_query.npy");
    assert_int_equal(
        tu_run(out, sizeof out, "%s %s --query %s %s --winding --quiet", SDFT_MESH2SDF, SUZANNE, in, out_npy), 0);
    size_t len;
    float *cli = (float *)file_bytes(out_npy, npy_data_offset(out_npy), &len);
    assert_int_equal(len, N * 2 * sizeof(float));
    sdft_mesh *m = load(SUZANNE);
    float d[N], w[N];
    sdft_mesh_points pts = {.data = p, .type = SDFT_MESH_FLOAT64, .count = N};
    assert_int_equal(sdft_mesh_signed_distance(m, &pts, d, w, NULL, NULL, 0), SDFT_OK);
    for (int i = 0; i < N; i++) {
        assert_memory_equal(&d[i], &cli[2 * i], sizeof(float));
        assert_memory_equal(&w[i], &cli[2 * i + 1], sizeof(float));
    }
    free(cli);
    free(p);
    sdft_mesh_free(m);
    mesh_free(&b);
}

/* The samples are the rows mesh2sdf --samples writes, and each row's
 * distance is the brute-force distance at its point. */
static void samples_as_the_cli(void **state)
{
    (void)state;
    char out[512], npy[256];
    tu_tmp(npy, sizeof npy, "mesh_api_samples.npy");
    assert_int_equal(tu_run(out, sizeof out, "%s %s --samples 5000 %s --seed 7 --quiet", SDFT_MESH2SDF, SUZANNE, npy),
                     0);
    size_t len;
    unsigned char *cli = file_bytes(npy, npy_data_offset(npy), &len);
    assert_int_equal(len, 5000 * 4 * sizeof(float));
    sdft_mesh *m = load(SUZANNE);
    sdft_mesh_sample_params p = sdft_mesh_sample_params_defaults();
    p.count = 5000;
    p.seed = 7;
    float *rows = malloc(len);
    char msg[256] = "";
    assert_int_equal(sdft_mesh_samples(m, &p, rows, 5000 * 4, msg, sizeof msg), SDFT_OK);
    assert_memory_equal(rows, cli, len);
    mesh b = read_mesh(SUZANNE);
    for (int i = 0; i < 5000; i += 25) {
        const double q[3] = {rows[i * 4], rows[i * 4 + 1], rows[i * 4 + 2]};
        const double truth = mesh_distance(&b, q);
        assert_true(fabs(fabs(rows[i * 4 + 3]) - truth) <= 1e-5 * (1 + truth));
        const double wt = winding(&b, q);
        if (fabs(wt - 0.5) > CLEAR)
            assert_true((rows[i * 4 + 3] < 0) == (wt > 0.5));
    }
    free(rows);
    free(cli);
    mesh_free(&b);
    sdft_mesh_free(m);
}

static void assert_same_file(const char *a, const char *b)
{
    size_t la, lb;
    unsigned char *x = file_bytes(a, 0, &la), *y = file_bytes(b, 0, &lb);
    assert_int_equal(la, lb);
    assert_memory_equal(x, y, la);
    free(x);
    free(y);
}

/* A grid's .npy, its sidecar and its .nvdb are the bytes mesh2sdf writes
 * with the same options; the dense copy is the .npy's array, the
 * tracer's grid samples the same values at voxel centres, and the values
 * near the surface are the brute-force distances. */
static void grid_as_the_cli(void **state)
{
    (void)state;
    char out[512], cli_npy[256], cli_nvdb[256], cli_vdb[256], npy[256], nvdb[256], vdb[256], json[256], cli_json[256];
    tu_tmp(cli_npy, sizeof cli_npy, "mesh_api_cli.npy");
    tu_tmp(cli_json, sizeof cli_json, "mesh_api_cli.json");
    tu_tmp(cli_nvdb, sizeof cli_nvdb, "mesh_api_cli.nvdb");
    tu_tmp(cli_vdb, sizeof cli_vdb, "mesh_api_cli.vdb");
    tu_tmp(npy, sizeof npy, "mesh_api_lib.npy");
    tu_tmp(json, sizeof json, "mesh_api_lib.json");
    tu_tmp(nvdb, sizeof nvdb, "mesh_api_lib.nvdb");
    tu_tmp(vdb, sizeof vdb, "mesh_api_lib.vdb");
    assert_int_equal(tu_run(out, sizeof out, "%s %s -o %s --nvdb %s --npy %s --res 48 --band 2 --name suzanne --quiet",
                            SDFT_MESH2SDF, SUZANNE, cli_vdb, cli_nvdb, cli_npy),
                     0);
    sdft_mesh *m = load(SUZANNE);
    sdft_mesh_grid_params p = sdft_mesh_grid_params_defaults();
    p.res = 48;
    p.band = 2;
    p.name = "suzanne";
    sdft_mesh_grid *g = NULL;
    char msg[256] = "";
    assert_int_equal(sdft_mesh_to_grid(m, &p, &g, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_grid_write(g, npy, SDFT_MESH_FORMAT_NPY, 0, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_grid_write(g, nvdb, SDFT_MESH_FORMAT_NVDB, 0, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_grid_write(g, vdb, SDFT_MESH_FORMAT_VDB, 0, msg, sizeof msg), SDFT_OK);
    assert_same_file(npy, cli_npy);
    assert_same_file(nvdb, cli_nvdb);
    /* The sidecar names its array: the same but for the file name. */
    char *a = tu_slurp(json), *b = tu_slurp(cli_json);
    assert_non_null(strstr(a, "mesh_api_lib.npy"));
    assert_int_equal(strlen(a), strlen(b));
    free(a);
    free(b);

    sdft_mesh_grid_box box;
    assert_int_equal(sdft_mesh_grid_get_box(g, &box, NULL, 0), SDFT_OK);
    const size_t n = (size_t)box.dims[0] * (size_t)box.dims[1] * (size_t)box.dims[2];
    float *values = malloc(n * sizeof(float));
    assert_int_equal(sdft_mesh_grid_dense(g, values, n, msg, sizeof msg), SDFT_OK);
    size_t len;
    unsigned char *cli = file_bytes(cli_npy, npy_data_offset(cli_npy), &len);
    assert_int_equal(len, n * sizeof(float));
    assert_memory_equal(values, cli, len);

    sdft_grid *nano = NULL;
    assert_int_equal(sdft_mesh_grid_nano(g, &nano, msg, sizeof msg), SDFT_OK);
    const sdft_field f = sdft_grid_field(nano, SDFT_GRID_BOUND_NONE);
    sdft_scratch s;
    memset(&s, 0, sizeof s);
    sdft_scratch_init(&f, &s);
    mesh bm = read_mesh(SUZANNE);
    int near = 0;
    for (size_t v = 0; v < n; v += 97) {
        const int i = (int)(v / ((size_t)box.dims[1] * (size_t)box.dims[2]));
        const int j = (int)(v / (size_t)box.dims[2] % (size_t)box.dims[1]), k = (int)(v % (size_t)box.dims[2]);
        const double q[3] = {box.origin[0] + i * box.voxel_size, box.origin[1] + j * box.voxel_size,
                             box.origin[2] + k * box.voxel_size};
        const float at =
            sdft_grid_sample(nano, SDFT_GRID_BOUND_NONE, &s, sdft_v3((float)q[0], (float)q[1], (float)q[2]), NULL);
        assert_true(fabsf(at - values[v]) <= 1e-4f * box.voxel_size);
        if (fabsf(values[v]) < box.background * 0.999f) {
            const double truth = mesh_distance(&bm, q);
            assert_true(fabs(fabs(values[v]) - truth) <= 1e-4 * box.voxel_size);
            near++;
        }
    }
    assert_true(near > 0);
    mesh_free(&bm);
    free(cli);
    free(values);
    sdft_grid_free(nano);
    sdft_mesh_grid_free(g);
    sdft_mesh_free(m);
}

/* ---------------------------------------------------------------- settings */

/* The value of member `s` of params struct `p`, as a double (k: which of
 * an array's values). */
static double member(const void *p, const sdft_mesh_setting *s, int k)
{
    const char *at = (const char *)p + s->offset;
    int i;
    uint64_t u;
    double d;
    switch (s->kind) {
    case SDFT_MESH_SETTING_COUNT:
        memcpy(&u, at, sizeof u);
        return (double)u;
    case SDFT_MESH_SETTING_REAL:
        memcpy(&d, at + (size_t)k * sizeof d, sizeof d);
        return d;
    case SDFT_MESH_SETTING_TEXT:
        return *(const char *const *)(const void *)at ? 1 : 0;
    default:
        memcpy(&i, at, sizeof i);
        return i;
    }
}

/* Stores v into member `s` of params struct `p` (every value of an array). */
static void set_member(void *p, const sdft_mesh_setting *s, double v)
{
    char *at = (char *)p + s->offset;
    const int i = (int)v;
    const uint64_t u = (uint64_t)v;
    for (int k = 0; k < s->count; k++)
        if (s->kind == SDFT_MESH_SETTING_REAL)
            memcpy(at + (size_t)k * sizeof v, &v, sizeof v);
        else if (s->kind == SDFT_MESH_SETTING_COUNT)
            memcpy(at, &u, sizeof u);
        else
            memcpy(at, &i, sizeof i);
}

/* The call a params struct goes to, on a one-point query's scale:
 * SDFT_EINVAL, or anything else once its checks passed. */
static sdft_error call_with(sdft_mesh_settings_of of, const void *params, sdft_mesh *m)
{
    char msg[256] = "";
    sdft_error e = SDFT_OK;
    if (of == SDFT_MESH_SETTINGS_MESH) {
        sdft_mesh *out = NULL;
        e = sdft_mesh_load(SUZANNE, params, &out, msg, sizeof msg);
        sdft_mesh_free(out);
    } else if (of == SDFT_MESH_SETTINGS_GRID) {
        sdft_mesh_grid_box box;
        e = mesh_grid_plan(m, params, &box, msg, sizeof msg); /* mesh_tool.h: the checks, no grid built */
    } else {
        float rows[4 * 8];
        sdft_mesh_sample_params p;
        memcpy(&p, params, sizeof p);
        if (p.count > 8 && p.count <= SDFT_MESH_MAX_SAMPLES)
            p.count = 8; /* within the range, 8 rows are quick */
        e = sdft_mesh_samples(m, &p, rows, sizeof rows / sizeof *rows, msg, sizeof msg);
    }
    if (e == SDFT_EINVAL)
        assert_true(strlen(msg) > 0 && strchr(msg, '\n') == NULL);
    return e;
}

/* Every setting of every table: its defaults function gives its default,
 * the call that takes the params accepts the default and the ends of the
 * range, and refuses a value just past either end (or an unknown choice),
 * each in one line. Generic over the tables, so a setting added to one is
 * held to its range here without a word more. */
static void settings_default_and_range(void **state)
{
    (void)state;
    sdft_mesh *m = load(SUZANNE);
    const sdft_mesh_params mesh = sdft_mesh_params_defaults();
    const sdft_mesh_grid_params grid = sdft_mesh_grid_params_defaults();
    const sdft_mesh_sample_params samples = sdft_mesh_sample_params_defaults();
    const struct {
        sdft_mesh_settings_of of;
        const void *defaults;
        size_t size;
    } tables[] = {{SDFT_MESH_SETTINGS_MESH, &mesh, sizeof mesh},
                  {SDFT_MESH_SETTINGS_GRID, &grid, sizeof grid},
                  {SDFT_MESH_SETTINGS_SAMPLES, &samples, sizeof samples}};
    size_t n = 0, seen = 0;
    assert_null(sdft_mesh_settings((sdft_mesh_settings_of)9, &n));
    assert_int_equal(n, 0);
    for (size_t t = 0; t < 3; t++) {
        const sdft_mesh_setting *rows = sdft_mesh_settings(tables[t].of, &n);
        assert_non_null(rows);
        for (size_t r = 0; r < n; r++, seen++) {
            const sdft_mesh_setting *s = &rows[r];
            assert_true(s->offset < tables[t].size && s->doc && s->doc[0]);
            for (int k = 0; k < s->count; k++)
                assert_true(member(tables[t].defaults, s, k) == s->def[k]);
            unsigned char p[512];
            assert_true(tables[t].size <= sizeof p);
            memcpy(p, tables[t].defaults, tables[t].size);
            assert_int_not_equal(call_with(tables[t].of, p, m), SDFT_EINVAL);
            if (s->kind == SDFT_MESH_SETTING_CHOICE) {
                int names = 1;
                for (const char *c = s->choices; *c; c++)
                    names += *c == ' ';
                set_member(p, s, names);
                assert_int_equal(call_with(tables[t].of, p, m), SDFT_EINVAL);
                set_member(p, s, -1);
                assert_int_equal(call_with(tables[t].of, p, m), SDFT_EINVAL);
                continue;
            }
            if (s->kind != SDFT_MESH_SETTING_INT && s->kind != SDFT_MESH_SETTING_COUNT &&
                s->kind != SDFT_MESH_SETTING_REAL)
                continue;
            const double step = s->kind == SDFT_MESH_SETTING_REAL ? 1e-6 * (fabs(s->lo) + 1) : 1;
            if (!(s->flags & SDFT_MESH_SETTING_OPEN_LO) && s->lo >= 0 && s->lo < 1e6) {
                memcpy(p, tables[t].defaults, tables[t].size);
                set_member(p, s, s->lo);
                const sdft_error e = call_with(tables[t].of, p, m);
                assert_true(e != SDFT_EINVAL || tables[t].of == SDFT_MESH_SETTINGS_GRID); /* a box may not fit */
            }
            memcpy(p, tables[t].defaults, tables[t].size);
            const double below = (s->flags & SDFT_MESH_SETTING_OPEN_LO) ? s->lo : s->lo - step;
            set_member(p, s, below);
            /* an unsigned count cannot go below 0; an automatic default lies outside the range */
            if ((s->kind != SDFT_MESH_SETTING_COUNT || s->lo > 0) &&
                !((s->flags & SDFT_MESH_SETTING_AUTO) && below == s->def[0]))
                assert_int_equal(call_with(tables[t].of, p, m), SDFT_EINVAL);
            if (s->hi < 1e300) {
                memcpy(p, tables[t].defaults, tables[t].size);
                set_member(p, s, s->hi + step);
                assert_int_equal(call_with(tables[t].of, p, m), SDFT_EINVAL);
            }
            if (s->kind == SDFT_MESH_SETTING_REAL) {
                memcpy(p, tables[t].defaults, tables[t].size);
                set_member(p, s, NAN);
                assert_int_equal(call_with(tables[t].of, p, m), SDFT_EINVAL);
            }
        }
    }
    assert_true(seen >= 16);
    sdft_mesh_free(m);
}

/* Every setting reaches mesh2sdf: an option named for it (dashes for
 * underscores) in --help, but the two the page on settings names. */
static void settings_are_options(void **state)
{
    (void)state;
    char *out = malloc(65536);
    assert_int_equal(tu_run(out, 65536, "%s --help", SDFT_MESH2SDF), 0);
    for (int of = 0; of < 3; of++) {
        size_t n = 0;
        const sdft_mesh_setting *rows = sdft_mesh_settings((sdft_mesh_settings_of)of, &n);
        for (size_t r = 0; r < n; r++) {
            char flag[64];
            snprintf(flag, sizeof flag, "--%s", rows[r].name);
            for (char *c = flag + 2; *c; c++)
                *c = *c == '_' ? '-' : *c;
            if (of == SDFT_MESH_SETTINGS_SAMPLES && !strcmp(rows[r].name, "count"))
                snprintf(flag, sizeof flag, "--sample-count");
            if (!strstr(out, flag))
                fail_msg("mesh2sdf --help has no %s", flag);
        }
    }
    free(out);
}

/* ------------------------------------------------------- what calls report */

/* A mesh's timings (the hierarchies' only once a query built them), a
 * grid's surface, memory and winding time; an open sheet has no surface. */
static void reports(void **state)
{
    (void)state;
    char msg[256] = "";
    sdft_mesh *m = load_with(SPOT, NULL);
    sdft_mesh_timings info;
    assert_int_equal(sdft_mesh_get_timings(m, &info, msg, sizeof msg), SDFT_OK);
    assert_true(info.read_seconds > 0);
    assert_true(info.orient_seconds > 0);
    assert_true(info.index_seconds == 0);
    const double p[3] = {0, 0, 0};
    const sdft_mesh_points pts = {p, SDFT_MESH_FLOAT64, 1, {0, 0}};
    float d;
    assert_int_equal(sdft_mesh_signed_distance(m, &pts, &d, NULL, NULL, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_get_timings(m, &info, msg, sizeof msg), SDFT_OK);
    assert_true(info.index_seconds > 0);

    sdft_mesh_grid *g = grid_of(m, 32);
    sdft_mesh_grid_stats box;
    sdft_mesh_grid_timings took;
    assert_int_equal(sdft_mesh_grid_get_stats(g, &box, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_grid_get_timings(g, &took, msg, sizeof msg), SDFT_OK);
    assert_int_equal(box.surface, 1);
    /* A narrow band's leaves hold 512 floats each: at least 2 KiB per
     * 512 active voxels. */
    assert_true(box.memory_bytes >= box.active_voxels * 4);
    assert_true(took.seconds > 0 && took.winding_seconds > 0 && took.winding_seconds <= took.seconds);
    /* The winding tree is built before the band: a part of the whole. */
    assert_true(took.index_seconds > 0 && took.index_seconds < took.seconds);
    sdft_mesh_grid_free(g);

    sdft_mesh_grid_params unsigned_params = sdft_mesh_grid_params_defaults();
    unsigned_params.res = 32;
    unsigned_params.sign = SDFT_MESH_SIGN_NONE;
    assert_int_equal(sdft_mesh_to_grid(m, &unsigned_params, &g, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_grid_get_stats(g, &box, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_grid_get_timings(g, &took, msg, sizeof msg), SDFT_OK);
    assert_int_equal(box.surface, 0);
    assert_true(took.winding_seconds == 0);
    assert_true(took.index_seconds == 0); /* unsigned, not full: no hierarchy */
    sdft_mesh_grid_free(g);
    sdft_mesh_free(m);

    const float sheet[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const int32_t quad[] = {0, 1, 2, 0, 2, 3};
    sdft_mesh *open = NULL;
    assert_int_equal(
        sdft_mesh_from_arrays(sheet, SDFT_MESH_FLOAT32, 4, quad, SDFT_MESH_INT32, 2, NULL, &open, msg, sizeof msg),
        SDFT_OK);
    g = grid_of(open, 16);
    assert_int_equal(sdft_mesh_grid_get_stats(g, &box, msg, sizeof msg), SDFT_OK);
    assert_int_equal(box.surface, 0);
    assert_true(box.active_voxels > 0);
    sdft_mesh_grid_free(g);
    sdft_mesh_free(open);
}

/* One thread and scalar code give the answers of all cores and the widest
 * vectors: distances bit for bit (the same minimum over every triangle,
 * whatever the search's path) with the same sign wherever the winding
 * number is not within rounding of 1/2, samples byte for byte (their rows
 * do not depend on the thread count), grids to rounding. */
static void threads_and_simd_agree(void **state)
{
    (void)state;
    char msg[256] = "";
    sdft_mesh_params one = sdft_mesh_params_defaults();
    one.threads = 1;
    one.simd = SDFT_MESH_SIMD_NONE;
    sdft_mesh *a = load_with(SUZANNE, NULL), *b = load_with(SUZANNE, &one);

    enum { N = 3000 };
    double *p = malloc(sizeof(double) * 3 * N);
    tu_rng r = tu_rng_seed(11);
    for (int i = 0; i < 3 * N; i++)
        p[i] = tu_uniform(&r, -2, 2);
    const sdft_mesh_points pts = {p, SDFT_MESH_FLOAT64, N, {0, 0}};
    float *da = malloc(sizeof(float) * N), *db = malloc(sizeof(float) * N);
    float *wa = malloc(sizeof(float) * N), *wb = malloc(sizeof(float) * N);
    assert_int_equal(sdft_mesh_signed_distance(a, &pts, da, wa, NULL, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_signed_distance(b, &pts, db, wb, NULL, msg, sizeof msg), SDFT_OK);
    for (int i = 0; i < N; i++) {
        assert_true(fabsf(da[i]) == fabsf(db[i]));
        assert_true(fabsf(wa[i] - wb[i]) <= 1e-6f);
        if (fabsf(wa[i] - 0.5f) > 1e-5f)
            assert_true((da[i] < 0) == (db[i] < 0));
    }

    sdft_mesh_sample_params sp = sdft_mesh_sample_params_defaults();
    sp.count = 5000;
    sdft_mesh_params threads_only = sdft_mesh_params_defaults();
    threads_only.threads = 1;
    sdft_mesh *c = load_with(SUZANNE, &threads_only);
    float *ra = malloc(sizeof(float) * 4 * sp.count), *rc = malloc(sizeof(float) * 4 * sp.count);
    assert_int_equal(sdft_mesh_samples(a, &sp, ra, 4 * sp.count, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_samples(c, &sp, rc, 4 * sp.count, msg, sizeof msg), SDFT_OK);
    assert_memory_equal(ra, rc, sizeof(float) * 4 * sp.count);

    sdft_mesh_grid *ga = grid_of(a, 32), *gb = grid_of(b, 32);
    sdft_mesh_grid_box box;
    assert_int_equal(sdft_mesh_grid_get_box(ga, &box, msg, sizeof msg), SDFT_OK);
    const size_t n = (size_t)box.dims[0] * (size_t)box.dims[1] * (size_t)box.dims[2];
    float *va = malloc(n * sizeof(float)), *vb = malloc(n * sizeof(float));
    assert_int_equal(sdft_mesh_grid_dense(ga, va, n, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_grid_dense(gb, vb, n, msg, sizeof msg), SDFT_OK);
    for (size_t i = 0; i < n; i++)
        assert_true(fabsf(va[i] - vb[i]) <= 1e-4f * (float)box.voxel_size);

    sdft_mesh_params bad = sdft_mesh_params_defaults();
    bad.threads = -1;
    sdft_mesh *none = (sdft_mesh *)&none;
    assert_int_equal(sdft_mesh_load(SUZANNE, &bad, &none, msg, sizeof msg), SDFT_EINVAL);
    assert_null(none);
    bad = sdft_mesh_params_defaults();
    bad.simd = (sdft_mesh_simd)5;
    assert_int_equal(sdft_mesh_load(SUZANNE, &bad, &none, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "simd"));

    free(va), free(vb), free(ra), free(rc), free(da), free(db), free(wa), free(wb), free(p);
    sdft_mesh_grid_free(ga);
    sdft_mesh_grid_free(gb);
    sdft_mesh_free(a);
    sdft_mesh_free(b);
    sdft_mesh_free(c);
}

/* The health report's text and JSON: a closed tetrahedron given with one
 * face twice, reversed, and a vertex repeated; the counts are known from
 * how it is built. */
static void health_report(void **state)
{
    (void)state;
    const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0};
    const int32_t f[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 4, 2, 3, 1, 2, 0};
    sdft_mesh *m = NULL;
    char msg[256] = "", text[512], json[512];
    assert_int_equal(sdft_mesh_from_arrays(v, SDFT_MESH_FLOAT32, 5, f, SDFT_MESH_INT32, 5, NULL, &m, msg, sizeof msg),
                     SDFT_OK);
    sdft_mesh_health h;
    assert_int_equal(sdft_mesh_get_health(m, &h, msg, sizeof msg), SDFT_OK);
    /* vertex 4 is vertex 1 again; face 4 is face 0 reversed: dropped */
    assert_int_equal(h.welded_vertices, 1);
    assert_int_equal(h.duplicate_faces, 1);
    assert_int_equal(h.triangles, 4);
    const size_t n = sdft_mesh_health_text(&h, text, sizeof text);
    assert_int_equal(n, strlen(text));
    assert_string_equal(text, "5 vertices, 5 faces (4 triangles), 0 boundary edges, 0 non-manifold edges, 0 "
                              "degenerate faces skipped; 1 vertices welded, 1 duplicate faces dropped, 1 patches, 0 "
                              "faces reoriented, 0 patches turned outward");
    const size_t j = sdft_mesh_health_json(&h, json, sizeof json);
    assert_int_equal(j, strlen(json));
    assert_string_equal(
        json, "\"vertices\": 5, \"faces\": 5, \"triangles\": 4, \"degenerate_faces\": 0, "
              "\"boundary_edges\": 0, \"non_manifold_edges\": 0, \"skipped_faces\": 0, \"orient\": \"outward\", "
              "\"welded_vertices\": 1, \"duplicate_faces\": 1, \"patches\": 1, \"reoriented_faces\": 0, "
              "\"outward_patches\": 0, \"cavity_patches\": 0, \"ambiguous_patches\": 0, "
              "\"non_orientable_patches\": 0, \"evidence_patches\": 0, \"ambiguous_area\": 0");
    /* Every count under its own name, in words and in JSON. */
    const sdft_mesh_health d = {.vertices = 1,
                                .faces = 2,
                                .triangles = 3,
                                .degenerate_faces = 4,
                                .welded_vertices = 5,
                                .boundary_edges = 6,
                                .non_manifold_edges = 7,
                                .oriented = 1,
                                .duplicate_faces = 8,
                                .patches = 9,
                                .non_orientable_patches = 10,
                                .reoriented_faces = 11,
                                .outward_patches = 12,
                                .cavity_patches = 13,
                                .ambiguous_patches = 14};
    sdft_mesh_health_text(&d, text, sizeof text);
    assert_string_equal(text, "1 vertices, 2 faces (3 triangles), 6 boundary edges, 7 non-manifold edges, 4 "
                              "degenerate faces skipped; 5 vertices welded, 8 duplicate faces dropped, 9 patches, 11 "
                              "faces reoriented, 12 patches turned outward, 13 inward patches kept as cavity walls, 14 "
                              "open patches with no clear outside, 10 non-orientable patches");
    sdft_mesh_health_json(&d, json, sizeof json);
    assert_string_equal(
        json, "\"vertices\": 1, \"faces\": 2, \"triangles\": 3, \"degenerate_faces\": 4, "
              "\"boundary_edges\": 6, \"non_manifold_edges\": 7, \"skipped_faces\": 0, \"orient\": \"outward\", "
              "\"welded_vertices\": 5, \"duplicate_faces\": 8, \"patches\": 9, \"reoriented_faces\": 11, "
              "\"outward_patches\": 12, \"cavity_patches\": 13, \"ambiguous_patches\": 14, "
              "\"non_orientable_patches\": 10, \"evidence_patches\": 0, \"ambiguous_area\": 0");
    /* Cut short as snprintf cuts, the whole length returned; NULL counts. */
    char cut[8];
    assert_int_equal(sdft_mesh_health_text(&h, cut, sizeof cut), n);
    assert_string_equal(cut, "5 verti");
    assert_int_equal(sdft_mesh_health_text(&h, NULL, 0), n);
    sdft_mesh_free(m);

    sdft_mesh_params raw = sdft_mesh_params_defaults();
    raw.orient = 0;
    assert_int_equal(sdft_mesh_from_arrays(v, SDFT_MESH_FLOAT32, 5, f, SDFT_MESH_INT32, 4, &raw, &m, msg, sizeof msg),
                     SDFT_OK);
    assert_int_equal(sdft_mesh_get_health(m, &h, msg, sizeof msg), SDFT_OK);
    sdft_mesh_health_json(&h, json, sizeof json);
    assert_non_null(strstr(json, "\"orient\": \"none\""));
    assert_null(strstr(json, "patches"));
    sdft_mesh_frame fr;
    assert_int_equal(sdft_mesh_get_frame(m, &fr, msg, sizeof msg), SDFT_OK);
    for (int k = 0; k < 3; k++)
        assert_true(fr.lo[k] == 0 && fr.hi[k] == 1 && fr.centre[k] == 0.5);
    assert_true(fabs(fr.radius - 1.03 * sqrt(0.75)) < 1e-12);
    assert_int_equal(fr.normalized, 0);
    assert_int_equal(sdft_mesh_get_health(NULL, &h, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_mesh_get_frame(m, NULL, msg, sizeof msg), SDFT_EINVAL);
    sdft_mesh_free(m);
}

/* ---------------------------------------------------------------- bad input */

static const float kTriangle[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
static const int32_t kFaces[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};

static void expect_arrays(const void *v, sdft_mesh_dtype vt, size_t nv, const void *f, sdft_mesh_dtype ft, size_t nf,
                          sdft_error code, const char *words)
{
    sdft_mesh *m = (sdft_mesh *)&m;
    char msg[256] = "";
    assert_int_equal(sdft_mesh_from_arrays(v, vt, nv, f, ft, nf, NULL, &m, msg, sizeof msg), code);
    assert_null(m);
    assert_non_null(strstr(msg, words));
}

static void bad_arrays(void **state)
{
    (void)state;
    expect_arrays(NULL, SDFT_MESH_FLOAT32, 4, kFaces, SDFT_MESH_INT32, 4, SDFT_EINVAL, "vertices is NULL");
    expect_arrays(kTriangle, SDFT_MESH_FLOAT32, 4, NULL, SDFT_MESH_INT32, 4, SDFT_EINVAL, "faces is NULL");
    expect_arrays(kTriangle, SDFT_MESH_FLOAT32, 0, kFaces, SDFT_MESH_INT32, 4, SDFT_EINVAL, "no vertices");
    expect_arrays(kTriangle, SDFT_MESH_FLOAT32, 4, kFaces, SDFT_MESH_INT32, 0, SDFT_EINVAL, "no faces");
    expect_arrays(kTriangle, SDFT_MESH_INT32, 4, kFaces, SDFT_MESH_INT32, 4, SDFT_EINVAL, "float32 or float64");
    expect_arrays(kTriangle, SDFT_MESH_FLOAT32, 4, kFaces, SDFT_MESH_FLOAT32, 4, SDFT_EINVAL, "int32, uint32 or int64");
    const int32_t out_of_range[] = {0, 1, 4};
    expect_arrays(kTriangle, SDFT_MESH_FLOAT32, 4, out_of_range, SDFT_MESH_INT32, 1, SDFT_EINVAL, "vertex index 4");
    const int32_t negative[] = {0, -1, 2};
    expect_arrays(kTriangle, SDFT_MESH_FLOAT32, 4, negative, SDFT_MESH_INT32, 1, SDFT_EINVAL, "vertex index -1");
    float nan_vertex[12];
    memcpy(nan_vertex, kTriangle, sizeof nan_vertex);
    nan_vertex[7] = NAN;
    expect_arrays(nan_vertex, SDFT_MESH_FLOAT32, 4, kFaces, SDFT_MESH_INT32, 4, SDFT_EFORMAT,
                  "non-finite coordinate (vertex 2)");
    const int32_t flat[] = {0, 1, 1};
    expect_arrays(kTriangle, SDFT_MESH_FLOAT32, 4, flat, SDFT_MESH_INT32, 1, SDFT_EFORMAT,
                  "no non-degenerate triangles");
    /* A tetrahedron from uint32 faces: its volume's centre is inside. */
    sdft_mesh *m = NULL;
    assert_int_equal(
        sdft_mesh_from_arrays(kTriangle, SDFT_MESH_FLOAT32, 4, kFaces, SDFT_MESH_UINT32, 4, NULL, &m, NULL, 0),
        SDFT_OK);
    const float centre[3] = {0.2f, 0.2f, 0.2f};
    sdft_mesh_points pts = {.data = centre, .type = SDFT_MESH_FLOAT32, .count = 1};
    float d, w;
    assert_int_equal(sdft_mesh_signed_distance(m, &pts, &d, &w, NULL, NULL, 0), SDFT_OK);
    /* Inside, 0.2 from the three faces on the axes' planes (the slanted
     * one is (1 - 0.6) / sqrt(3) away). */
    assert_true(fabsf(d + 0.2f) < 1e-6f);
    assert_true(fabsf(w - 1.0f) < 1e-3f);
    sdft_mesh_free(m);
}

static void bad_files_and_calls(void **state)
{
    (void)state;
    sdft_mesh *m = NULL;
    char msg[256] = "", path[256];
    assert_int_equal(sdft_mesh_load(NULL, NULL, &m, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_mesh_load(SUZANNE, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_mesh_load("/nonexistent/x.obj", NULL, &m, msg, sizeof msg), SDFT_EIO);
    assert_non_null(strstr(msg, "/nonexistent/x.obj"));
    assert_int_equal(sdft_mesh_load("x.gltfz", NULL, &m, msg, sizeof msg), SDFT_EFORMAT);
    tu_tmp(path, sizeof path, "mesh_api_nan.obj");
    FILE *f = fopen(path, "w");
    fputs("v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n", f);
    fclose(f);
    assert_int_equal(sdft_mesh_load(path, NULL, &m, msg, sizeof msg), SDFT_EFORMAT);
    assert_null(m);
    assert_non_null(strstr(msg, "non-finite"));

    m = load(SUZANNE);
    float d[1];
    const float p[3] = {0, 0, 0};
    sdft_mesh_points pts = {.data = p, .type = SDFT_MESH_FLOAT32, .count = 1};
    assert_int_equal(sdft_mesh_signed_distance(NULL, &pts, d, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_mesh_signed_distance(m, NULL, d, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_mesh_signed_distance(m, &pts, NULL, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    pts.type = SDFT_MESH_INT32;
    assert_int_equal(sdft_mesh_winding_number(m, &pts, d, NULL, msg, sizeof msg), SDFT_EINVAL);
    pts.type = SDFT_MESH_FLOAT32;
    pts.count = 0;
    assert_int_equal(sdft_mesh_signed_distance(m, &pts, d, NULL, NULL, msg, sizeof msg), SDFT_OK);
    const float nan_point[3] = {NAN, 0, 0};
    sdft_mesh_points np = {.data = nan_point, .type = SDFT_MESH_FLOAT32, .count = 1};
    assert_int_equal(sdft_mesh_signed_distance(m, &np, d, NULL, NULL, msg, sizeof msg), SDFT_OK);
    assert_true(isnan(d[0]));

    sdft_mesh_sample_params sp = sdft_mesh_sample_params_defaults();
    float rows[8];
    sp.count = 2;
    assert_int_equal(sdft_mesh_samples(m, &sp, rows, 7, msg, sizeof msg), SDFT_EINVAL);
    sp.count = 0;
    assert_int_equal(sdft_mesh_samples(m, &sp, rows, 8, msg, sizeof msg), SDFT_EINVAL);
    sp.count = 2;
    sp.near_sigma[1] = NAN;
    assert_int_equal(sdft_mesh_samples(m, &sp, rows, 8, msg, sizeof msg), SDFT_EINVAL);
    sp = sdft_mesh_sample_params_defaults();
    sp.count = 2;
    sp.uniform_share = 1.5;
    assert_int_equal(sdft_mesh_samples(m, &sp, rows, 8, msg, sizeof msg), SDFT_EINVAL);

    sdft_mesh_grid_params gp = sdft_mesh_grid_params_defaults();
    sdft_mesh_grid *g = (sdft_mesh_grid *)&g;
    gp.res = 0;
    assert_int_equal(sdft_mesh_to_grid(m, &gp, &g, msg, sizeof msg), SDFT_EINVAL);
    assert_null(g);
    gp = sdft_mesh_grid_params_defaults();
    gp.band = -1;
    assert_int_equal(sdft_mesh_to_grid(m, &gp, &g, msg, sizeof msg), SDFT_EINVAL);
    gp = sdft_mesh_grid_params_defaults();
    gp.voxel_size = 1e-9; /* a box far above 4096 voxels a side */
    assert_int_equal(sdft_mesh_to_grid(m, &gp, &g, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "above the limit"));
    gp = sdft_mesh_grid_params_defaults();
    gp.res = 16;
    assert_int_equal(sdft_mesh_to_grid(m, &gp, &g, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_grid_write(g, "x.vdb", (sdft_mesh_format)7, 0, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_mesh_grid_write(g, NULL, SDFT_MESH_FORMAT_VDB, 0, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_mesh_grid_write(g, "/nonexistent/x.vdb", SDFT_MESH_FORMAT_VDB, 0, msg, sizeof msg), SDFT_EIO);
    assert_int_equal(sdft_mesh_grid_dense(g, rows, 8, msg, sizeof msg), SDFT_EINVAL);
    sdft_mesh_grid_free(g);
    sdft_mesh_free(m);
}

/* ---------------------------------------------------------------- progress */

typedef struct {
    int calls, stop_after;
    float last;
    int rising;
} listener;

static int listen(void *user, float done)
{
    listener *l = user;
    l->rising &= done >= l->last && done >= 0 && done <= 1;
    l->last = done;
    return ++l->calls > l->stop_after;
}

static void progress_and_cancel(void **state)
{
    (void)state;
    char msg[256] = "";
    /* Run whole, every call rising to 1. */
    listener whole = {.stop_after = 1 << 30, .rising = 1};
    sdft_mesh_params mp = sdft_mesh_params_defaults();
    mp.progress = listen;
    mp.progress_user = &whole;
    sdft_mesh *m = NULL;
    assert_int_equal(sdft_mesh_load(SUZANNE, &mp, &m, msg, sizeof msg), SDFT_OK);
    assert_true(whole.rising && whole.calls >= 2 && whole.last == 1.0f);

    listener grid = {.stop_after = 1 << 30, .rising = 1};
    sdft_mesh_grid_params gp = sdft_mesh_grid_params_defaults();
    gp.res = 64;
    gp.progress = listen;
    gp.progress_user = &grid;
    sdft_mesh_grid *g = NULL;
    assert_int_equal(sdft_mesh_to_grid(m, &gp, &g, msg, sizeof msg), SDFT_OK);
    assert_true(grid.rising && grid.calls >= 3);
    sdft_mesh_grid_free(g);

    /* Stopped after the first report: canceled, nothing returned. */
    listener stop = {.stop_after = 1, .rising = 1};
    gp.progress_user = &stop;
    assert_int_equal(sdft_mesh_to_grid(m, &gp, &g, msg, sizeof msg), SDFT_ECANCELED);
    assert_null(g);
    assert_non_null(strstr(msg, "canceled"));
    assert_int_equal(stop.calls, 2);

    listener stop_samples = {.stop_after = 0, .rising = 1};
    sdft_mesh_sample_params sp = sdft_mesh_sample_params_defaults();
    sp.count = 100;
    sp.progress = listen;
    sp.progress_user = &stop_samples;
    float rows[400];
    assert_int_equal(sdft_mesh_samples(m, &sp, rows, 400, msg, sizeof msg), SDFT_ECANCELED);

    listener stop_load = {.stop_after = 1, .rising = 1};
    mp.progress_user = &stop_load;
    sdft_mesh *m2 = (sdft_mesh *)&m2;
    assert_int_equal(sdft_mesh_load(SUZANNE, &mp, &m2, msg, sizeof msg), SDFT_ECANCELED);
    assert_null(m2);
    sdft_mesh_free(m);
}

/* n points uniform in [-1.5, 1.5]^3 around Suzanne (malloc'd, packed rows). */
static double *cube_points(int n, uint64_t seed)
{
    double *p = malloc(sizeof(double) * 3 * (size_t)n);
    tu_rng r = tu_rng_seed(seed);
    for (int i = 0; i < 3 * n; i++)
        p[i] = tu_uniform(&r, -1.5f, 1.5f);
    return p;
}

/* A query reports its progress rising to 1 and stops when told, with
 * SDFT_ECANCELED; its answers do not depend on being watched. */
static void queries_report_and_stop(void **state)
{
    (void)state;
    enum { N = 100000 };
    double *p = cube_points(N, 3);
    const sdft_mesh_points pts = {p, SDFT_MESH_FLOAT64, N, {0, 0}};
    float *watched = malloc(sizeof(float) * N), *plain = malloc(sizeof(float) * N);
    char msg[256] = "";
    sdft_mesh *m = load(SUZANNE);
    listener all = {.stop_after = 1 << 30, .rising = 1};
    sdft_mesh_query_params q = sdft_mesh_query_params_defaults();
    q.progress = listen;
    q.progress_user = &all;
    assert_int_equal(sdft_mesh_signed_distance(m, &pts, watched, NULL, &q, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_signed_distance(m, &pts, plain, NULL, NULL, msg, sizeof msg), SDFT_OK);
    assert_memory_equal(watched, plain, sizeof(float) * N);
    assert_true(all.calls >= 10 && all.rising && all.last == 1.0f);
    listener stop = {.stop_after = 1, .rising = 1};
    q.progress_user = &stop;
    assert_int_equal(sdft_mesh_winding_number(m, &pts, watched, &q, msg, sizeof msg), SDFT_ECANCELED);
    assert_non_null(strstr(msg, "cancel"));
    assert_int_equal(stop.calls, 2);
    sdft_mesh_free(m);
    free(p), free(watched), free(plain);
}

/* Notes whether a report came from a thread other than the caller's. */
typedef struct {
    pthread_t caller;
    int calls, elsewhere;
} thread_listener;

static int listen_thread(void *user, float done)
{
    (void)done;
    thread_listener *l = user; /* the library reports one at a time */
    l->calls++;
    l->elsewhere += !pthread_equal(pthread_self(), l->caller);
    return 0;
}

/* A query's threads and a draw's bound that call, over the mesh's (all
 * cores here): with 1, every report comes from the caller's thread; the
 * answers are the same for any count; a count out of range is refused. */
static void queries_and_samples_take_threads(void **state)
{
    (void)state;
    enum { N = 200000 };
    double *p = cube_points(N, 5);
    const sdft_mesh_points pts = {p, SDFT_MESH_FLOAT64, N, {0, 0}};
    float *one = malloc(sizeof(float) * N), *all = malloc(sizeof(float) * N);
    char msg[256] = "";
    sdft_mesh *m = load(SUZANNE);
    thread_listener heard = {.caller = pthread_self()};
    sdft_mesh_query_params q = sdft_mesh_query_params_defaults();
    assert_int_equal(q.threads, 0);
    q.progress = listen_thread;
    q.progress_user = &heard;
    q.threads = 1;
    assert_int_equal(sdft_mesh_signed_distance(m, &pts, one, NULL, &q, msg, sizeof msg), SDFT_OK);
    assert_true(heard.calls >= 10);
    assert_int_equal(heard.elsewhere, 0);
    assert_int_equal(sdft_mesh_signed_distance(m, &pts, all, NULL, NULL, msg, sizeof msg), SDFT_OK);
    assert_memory_equal(one, all, sizeof(float) * N);
    heard.calls = 0;
    assert_int_equal(sdft_mesh_winding_number(m, &pts, one, &q, msg, sizeof msg), SDFT_OK);
    assert_true(heard.calls >= 10);
    assert_int_equal(heard.elsewhere, 0);
    q.threads = -1;
    assert_int_equal(sdft_mesh_winding_number(m, &pts, one, &q, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "threads"));
    q.threads = 1025;
    assert_int_equal(sdft_mesh_signed_distance(m, &pts, one, NULL, &q, msg, sizeof msg), SDFT_EINVAL);

    sdft_mesh_sample_params sp = sdft_mesh_sample_params_defaults();
    assert_int_equal(sp.threads, 0);
    sp.count = 20000;
    float *rows_one = malloc(sizeof(float) * 4 * sp.count), *rows_all = malloc(sizeof(float) * 4 * sp.count);
    assert_int_equal(sdft_mesh_samples(m, &sp, rows_all, 4 * sp.count, msg, sizeof msg), SDFT_OK);
    sp.threads = 1;
    sp.progress = listen_thread;
    sp.progress_user = &heard;
    heard.calls = 0;
    assert_int_equal(sdft_mesh_samples(m, &sp, rows_one, 4 * sp.count, msg, sizeof msg), SDFT_OK);
    assert_true(heard.calls >= 10);
    assert_int_equal(heard.elsewhere, 0);
    assert_memory_equal(rows_one, rows_all, sizeof(float) * 4 * sp.count);
    sdft_mesh_free(m);
    free(p), free(one), free(all), free(rows_one), free(rows_all);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(distances_match_brute_force),
        cmocka_unit_test(strided_points),
        cmocka_unit_test(arrays_as_the_file),
        cmocka_unit_test(queried_from_threads),
        cmocka_unit_test(queries_as_the_cli),
        cmocka_unit_test(samples_as_the_cli),
        cmocka_unit_test(grid_as_the_cli),
        cmocka_unit_test(reports),
        cmocka_unit_test(threads_and_simd_agree),
        cmocka_unit_test(health_report),
        cmocka_unit_test(settings_default_and_range),
        cmocka_unit_test(settings_are_options),
        cmocka_unit_test(bad_arrays),
        cmocka_unit_test(bad_files_and_calls),
        cmocka_unit_test(progress_and_cancel),
        cmocka_unit_test(queries_report_and_stop),
        cmocka_unit_test(queries_and_samples_take_threads),
    };
    return cmocka_run_group_tests_name("mesh_api", tests, NULL, NULL);
}
