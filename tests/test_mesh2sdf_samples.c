/* mesh2sdf --samples and --query (convert/samples.cpp, convert/query.cpp,
 * convert/npy_read.cpp), held to truth computed here: every distance
 * against brute force over all triangles, every clear sign against a
 * brute-force winding number, the distribution's shares against the
 * binomial expectation, the sphere of --normalize against its definition;
 * the same bytes for any thread count and seed; queries in float32 and
 * float64, C and Fortran order; malformed .npy files and bad flags each one
 * line on stderr and nothing written. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_support.h"
#include "testutil.h"

/* A winding number this far from 1/2 decides the sign (the fast winding
 * number's error stays far below). */
#define CLEAR 0.1

/* ---------------------------------------------------------------- .npy */

/* A .npy file of format `version` (1, 2 or 3) with header dict `dict`
 * (padded as NumPy pads it) and `len` bytes of data. */
static void write_npy(const char *path, int version, const char *dict, const void *data, size_t len)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    const size_t pre = version == 1 ? 10 : 12;
    char header[1024];
    size_t n = (size_t)snprintf(header, sizeof header, "%s", dict);
    while ((pre + n + 1) % 64)
        header[n++] = ' ';
    header[n++] = '\n';
    unsigned char magic[12] = {0x93, 'N', 'U', 'M', 'P', 'Y', (unsigned char)version, 0};
    for (size_t i = 0; i < pre - 8; i++)
        magic[8 + i] = (unsigned char)(n >> (8 * i));
    fwrite(magic, 1, pre, f);
    fwrite(header, 1, n, f);
    if (len)
        fwrite(data, 1, len, f);
    fclose(f);
}

/* Reads mesh2sdf's float32 C-order output: shape (rows,) or (rows, cols). */
static float *read_npy(const char *path, int *rows, int *cols)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    unsigned char pre[10];
    assert_int_equal(fread(pre, 1, 10, f), 10);
    assert_memory_equal(pre, "\x93NUMPY\x01\x00", 8);
    const size_t hlen = pre[8] | (size_t)pre[9] << 8;
    char header[1024] = {0};
    assert_true(hlen < sizeof header);
    assert_int_equal(fread(header, 1, hlen, f), hlen);
    assert_non_null(strstr(header, "'descr': '<f4', 'fortran_order': False"));
    const char *shape = strstr(header, "'shape': (");
    assert_non_null(shape);
    *cols = 1;
    assert_true(sscanf(shape, "'shape': (%d, %d)", rows, cols) >= 1);
    const size_t count = (size_t)*rows * (size_t)*cols;
    float *data = malloc(count * sizeof *data);
    assert_int_equal(fread(data, sizeof *data, count, f), count);
    assert_int_equal(fgetc(f), EOF);
    fclose(f);
    return data;
}

/* ------------------------------------------------------------- meshes */

static void mesh_path(char *buf, size_t len, const char *name) { snprintf(buf, len, "%s/%s.obj", SDFT_MESH_DIR, name); }

static void load(const char *name, mesh *m)
{
    char path[1024];
    mesh_path(path, sizeof path, name);
    assert_int_equal(read_obj(path, m), 0);
    assert_true(m->nt > 0);
}

/* DeepSDF's sphere, from its definition: the centre of the bounding box of
 * the vertices faces use, 1.03 times the farthest of them. */
static double sphere_of(const mesh *m, double *centre)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, far = 0;
    for (int i = 0; i < 3 * m->nt; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m->v[3 * m->t[i] + k]);
            hi[k] = fmax(hi[k], m->v[3 * m->t[i] + k]);
        }
    for (int k = 0; k < 3; k++)
        centre[k] = 0.5 * (lo[k] + hi[k]);
    for (int i = 0; i < 3 * m->nt; i++) {
        const double *p = &m->v[3 * m->t[i]];
        const double d[3] = {p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]};
        far = fmax(far, sqrt(dot3(d, d)));
    }
    return 1.03 * far;
}

/* The mesh NAME read here, and its sphere's radius (centre in `centre`). */
static double load_with_sphere(const char *name, mesh *m, double *centre)
{
    load(name, m);
    return sphere_of(m, centre);
}

/* mesh2sdf NAME.obj ARGS must succeed; its output in `out`. */
static void run_ok(const char *name, const char *args)
{
    char path[1024], out[8192];
    mesh_path(path, sizeof path, name);
    const int rc = tu_run(out, sizeof out, "%s '%s' --quiet %s", SDFT_MESH2SDF, path, args);
    if (rc != 0)
        fail_msg("mesh2sdf %s %s failed (%d): %s", name, args, rc, out);
}

/* Runs --samples N on `name` with extra flags into test file `file`. */
static float *samples(const char *name, int n, const char *flags, const char *file, char *npy, size_t npy_len)
{
    char args[2048];
    tu_tmp(npy, npy_len, file);
    snprintf(args, sizeof args, "--samples %d '%s' %s", n, npy, flags);
    run_ok(name, args);
    int rows, cols;
    float *data = read_npy(npy, &rows, &cols);
    assert_int_equal(rows, n);
    assert_int_equal(cols, 4);
    return data;
}

/* A value of a number key in a test file's JSON. */
static double sidecar_number(const char *npy, const char *key, int index)
{
    char json[1024];
    snprintf(json, sizeof json, "%.*s.json", (int)(strlen(npy) - 4), npy);
    char *text = tu_slurp(json);
    assert_non_null(text);
    const double v = json_number(text, key, index);
    free(text);
    return v;
}

/* ----------------------------------------------------- exact and signed */

/* Signed distance d at p against brute force: |d| the distance to the
 * nearest triangle within `tol`, and where the brute-force winding number
 * is clear, the sign. Returns 1 when the sign was checked. */
static int check_point(const mesh *m, const double *p, double d, double tol, const char *what, int row)
{
    const double truth = mesh_distance(m, p);
    if (fabs(fabs(d) - truth) > tol)
        fail_msg("%s row %d: |d| = %.9g, brute force %.9g", what, row, fabs(d), truth);
    const double w = winding(m, p);
    if (fabs(w - 0.5) < CLEAR)
        return 0;
    if ((d < 0) != (w > 0.5))
        fail_msg("%s row %d: d = %.9g but the winding number is %.6f", what, row, d, w);
    return 1;
}

/* Every row of a --samples run on spot and suzanne (suzanne is open: its
 * eyes are separate shells) against brute force. A row's position is
 * stored in float32, the distance was computed at the unrounded point: the
 * two differ by at most half a float32 ulp of the coordinates per axis. */
static void test_samples_exact(void **state)
{
    const char *name = *state;
    mesh m = {0};
    double centre[3];
    const double radius = load_with_sphere(name, &m, centre);
    char npy[512];
    const int n = 1500;
    float *rows = samples(name, n, "--threads 2", "exact.npy", npy, sizeof npy);
    const double tol = 1e-6 * (radius + sqrt(dot3(centre, centre)));
    int signed_rows = 0;
    for (int i = 0; i < n; i++) {
        const double p[3] = {rows[4 * i], rows[4 * i + 1], rows[4 * i + 2]};
        signed_rows += check_point(&m, p, rows[4 * i + 3], tol, name, i);
    }
    print_message("%s: %d samples exact, %d of them with a clear sign, all right\n", name, n, signed_rows);
    assert_true(signed_rows > n / 2);
    free(rows);
    mesh_free(&m);
}

/* ------------------------------------------------------- distribution */

/* k binomial standard deviations of a share of n trials with chance p. */
static double spread(double p, int n, double k) { return k * sqrt(p * (1 - p) / n); }

/* The shares (samples.h's layout: near rows first, the first sigma on even
 * rows, then the uniform ones). A near point is a point of the mesh moved
 * by a Gaussian step of standard deviation s per axis, so its distance is
 * at most the step's length, whose share below 3 s is the chi distribution
 * with 3 degrees of freedom's, 0.9707; a plane through the point leaves
 * the step's normal component, half-normal, whose share below s is
 * 0.6827: the spot's surface is nearly flat at the smaller sigma. Uniform
 * rows fill the sphere's cube, each half of each axis by half of them. */
static void test_distribution(void **state)
{
    (void)state;
    mesh m = {0};
    double centre[3];
    const double radius = load_with_sphere("spot", &m, centre);
    char npy[512];
    const int n = 12000;
    float *rows = samples("spot", n, "--seed 7", "shares.npy", npy, sizeof npy);
    const double sigma[2] = {0.070710678118654752 * radius, 0.022360679774997897 * radius};
    const int uniform = (int)floor(0.06 * n + 0.5), near = n - uniform;
    int within3[2] = {0, 0}, within1[2] = {0, 0}, count[2] = {0, 0}, a_within_3b = 0, uniform_near = 0;
    int below[3] = {0, 0, 0};
    for (int i = 0; i < n; i++) {
        const double d = fabs(rows[4 * i + 3]);
        if (i < near) {
            const int s = i % 2;
            count[s]++;
            within3[s] += d <= 3 * sigma[s];
            within1[s] += d <= sigma[s];
            a_within_3b += s == 0 && d <= 3 * sigma[1];
            continue;
        }
        for (int k = 0; k < 3; k++) {
            const double x = rows[4 * i + k] - centre[k];
            assert_true(fabs(x) <= radius * (1 + 1e-6));
            below[k] += x < 0;
        }
        uniform_near += d <= 3 * sigma[1];
    }
    assert_int_equal(count[0], (near + 1) / 2);
    assert_int_equal(count[1], near / 2);
    assert_int_equal((int)sidecar_number(npy, "\"uniform_samples\"", 0), uniform);
    for (int s = 0; s < 2; s++) {
        const double share3 = (double)within3[s] / count[s], share1 = (double)within1[s] / count[s];
        print_message("sigma %d: %.4f within 3 sigma (at least 0.9707), %.4f within 1 sigma (flat: 0.6827)\n", s,
                      share3, share1);
        assert_true(share3 >= 0.9707 - spread(0.9707, count[s], 4));
        assert_true(fabs(share1 - 0.6827) < 0.06 + spread(0.6827, count[s], 4));
    }
    /* The two scales differ: the wider one's points within 3 of the narrow
     * sigma, flat: P(|z| < 3 * sqrt(0.1)) = 0.657, far from 0.97. */
    const double a_share = (double)a_within_3b / count[0];
    print_message("wider sigma within 3 narrow sigmas: %.4f (flat: 0.657)\n", a_share);
    assert_true(a_share < 0.8);
    for (int k = 0; k < 3; k++)
        assert_true(fabs((double)below[k] / uniform - 0.5) < spread(0.5, uniform, 4));
    assert_true((double)uniform_near / uniform < 0.3);
    free(rows);

    /* --uniform-share 1 and 0, and sigmas of the caller's. */
    rows = samples("spot", 500, "--uniform-share 1", "all-uniform.npy", npy, sizeof npy);
    for (int i = 0; i < 500; i++)
        for (int k = 0; k < 3; k++)
            assert_true(fabs(rows[4 * i + k] - centre[k]) <= radius * (1 + 1e-6));
    free(rows);
    rows = samples("spot", 2000, "--uniform-share 0 --near-sigma 0.001,0.2", "wide.npy", npy, sizeof npy);
    int narrow = 0, wide = 0;
    for (int i = 0; i < 2000; i++) {
        const double d = fabs(rows[4 * i + 3]);
        if (i % 2 == 0)
            narrow += d <= 3 * 0.001 * radius;
        else
            wide += d <= 3 * 0.001 * radius;
    }
    assert_true(narrow >= 1000 * (0.9707 - spread(0.9707, 1000, 4)));
    assert_true(wide < 100);
    free(rows);
    mesh_free(&m);
}

/* --normalize: the sidecar's sphere is DeepSDF's, every point and distance
 * is in its unit frame, and mapped back it is exact in the mesh's. */
static void test_normalize(void **state)
{
    (void)state;
    mesh m = {0};
    double centre[3];
    const double radius = load_with_sphere("suzanne", &m, centre);
    char npy[512];
    const int n = 600;
    float *rows = samples("suzanne", n, "--normalize --uniform-share 0.5", "unit.npy", npy, sizeof npy);
    /* The file's vertices are read as float32 there, as doubles here. */
    assert_true(fabs(sidecar_number(npy, "\"radius\"", 0) - radius) < 1e-6 * radius);
    for (int k = 0; k < 3; k++)
        assert_true(fabs(sidecar_number(npy, "\"centre\"", k) - centre[k]) < 1e-6 * radius);
    for (int i = 0; i < n; i++) {
        double p[3];
        for (int k = 0; k < 3; k++) {
            assert_true(fabs(rows[4 * i + k]) <= 1 + 1e-6);
            p[k] = rows[4 * i + k] * radius + centre[k];
        }
        /* The mesh's float32 vertices are rounded again in the unit frame. */
        check_point(&m, p, rows[4 * i + 3] * radius, 1e-6 * radius, "normalized", i);
    }
    free(rows);
    mesh_free(&m);
}

/* --------------------------------------------------------- reproducible */

static int same_file(const char *a, const char *b)
{
    char out[256];
    return tu_run(out, sizeof out, "cmp -s '%s' '%s'", a, b) == 0;
}

/* The same bytes for one thread, two and five (several chunks of rows,
 * searched in other groups and packets), and again; another seed gives
 * other points. */
static void test_reproducible(void **state)
{
    (void)state;
    char one[512], two[512], five[512], again[512], other[512];
    free(samples("spot", 10000, "--threads 1 --seed 3", "seed-1.npy", one, sizeof one));
    free(samples("spot", 10000, "--threads 2 --seed 3", "seed-2.npy", two, sizeof two));
    free(samples("spot", 10000, "--threads 5 --seed 3", "seed-5.npy", five, sizeof five));
    free(samples("spot", 10000, "--seed 3", "seed-again.npy", again, sizeof again));
    free(samples("spot", 10000, "--threads 2 --seed 4", "seed-other.npy", other, sizeof other));
    assert_true(same_file(one, two));
    assert_true(same_file(one, five));
    assert_true(same_file(one, again));
    assert_false(same_file(one, other));
}

/* --------------------------------------------------------------- query */

/* Points around suzanne, written as float32 and float64 in C and Fortran
 * order: each run gives the same answers, exact against brute force, and
 * with --winding the winding number beside them. */
static void test_query(void **state)
{
    (void)state;
    mesh m = {0};
    double centre[3];
    const double radius = load_with_sphere("suzanne", &m, centre);
    enum { N = 400 };
    static float f4[N * 3], f4t[N * 3];
    static double f8[N * 3], f8t[N * 3];
    tu_rng rng = tu_rng_seed(42);
    for (int i = 0; i < N; i++)
        for (int k = 0; k < 3; k++) {
            f4[3 * i + k] = (float)centre[k] + tu_uniform(&rng, -1, 1) * (float)radius;
            f8[3 * i + k] = f4[3 * i + k];
            f4t[k * N + i] = f4[3 * i + k];
            f8t[k * N + i] = f8[3 * i + k];
        }
    const struct {
        const char *file, *descr;
        int fortran, version;
        const void *data;
        size_t size;
    } inputs[] = {
        {"q-f4c.npy", "<f4", 0, 1, f4, sizeof f4},
        {"q-f8c.npy", "<f8", 0, 2, f8, sizeof f8},
        {"q-f4f.npy", "<f4", 1, 3, f4t, sizeof f4t},
        {"q-f8f.npy", "=f8", 1, 1, f8t, sizeof f8t},
    };
    float *first = NULL;
    for (size_t v = 0; v < sizeof inputs / sizeof *inputs; v++) {
        char in[512], out[512], dict[256], args[1200];
        tu_tmp(in, sizeof in, inputs[v].file);
        snprintf(out, sizeof out, "%.*s-out.npy", (int)(strlen(in) - 4), in);
        snprintf(dict, sizeof dict, "{'descr': '%s', 'fortran_order': %s, 'shape': (%d, 3), }", inputs[v].descr,
                 inputs[v].fortran ? "True" : "False", N);
        write_npy(in, inputs[v].version, dict, inputs[v].data, inputs[v].size);
        snprintf(args, sizeof args, "--query '%s' '%s' --winding", in, out);
        run_ok("suzanne", args);
        int rows, cols;
        float *got = read_npy(out, &rows, &cols);
        assert_int_equal(rows, N);
        assert_int_equal(cols, 2);
        if (!first) {
            first = got;
            continue;
        }
        assert_memory_equal(got, first, sizeof(float) * 2 * N);
        free(got);
    }
    double worst_w = 0;
    for (int i = 0; i < N; i++) {
        const double p[3] = {f8[3 * i], f8[3 * i + 1], f8[3 * i + 2]};
        check_point(&m, p, first[2 * i], 1e-6 * radius, "query", i);
        worst_w = fmax(worst_w, fabs(first[2 * i + 1] - winding(&m, p)));
    }
    print_message("query: %d points exact, winding numbers within %.2g of brute force\n", N, worst_w);
    assert_true(worst_w < 0.02);
    free(first);

    /* Without --winding: shape (N,), the same distances. */
    char in[512], out[512], args[1200];
    tu_tmp(in, sizeof in, "q-f4c.npy");
    tu_tmp(out, sizeof out, "q-plain.npy");
    snprintf(args, sizeof args, "--query '%s' '%s'", in, out);
    run_ok("suzanne", args);
    int rows, cols;
    float *plain = read_npy(out, &rows, &cols);
    assert_int_equal(rows, N);
    assert_int_equal(cols, 1);
    for (int i = 0; i < N; i++) {
        const double p[3] = {f8[3 * i], f8[3 * i + 1], f8[3 * i + 2]};
        check_point(&m, p, plain[i], 1e-6 * radius, "plain query", i);
    }
    free(plain);
    mesh_free(&m);
}

/* ----------------------------------------------------------- bad input */

/* mesh2sdf MESH ARGS must fail with one line naming `name` (if given), and
 * leave neither `out` nor its sidecar nor a temporary file. */
static void expect_failure(const char *args, const char *name, const char *out)
{
    char path[1024], text[8192];
    mesh_path(path, sizeof path, "suzanne");
    const int rc = tu_run(text, sizeof text, "%s '%s' %s", SDFT_MESH2SDF, path, args);
    if (rc == 0)
        fail_msg("mesh2sdf %s succeeded", args);
    if (tu_lines(text) != 1 || strncmp(text, "mesh2sdf: ", 10) != 0)
        fail_msg("mesh2sdf %s: want one 'mesh2sdf: ' line, got: %s", args, text);
    if (name && !strstr(text, name))
        fail_msg("mesh2sdf %s: the message does not name %s: %s", args, name, text);
    char json[1024];
    snprintf(json, sizeof json, "%.*s.json", (int)(strlen(out) - 4), out);
    assert_false(tu_file_exists(out));
    assert_false(tu_file_exists(json));
    tu_assert_no_temporaries(SDFT_TEST_TMP, strrchr(out, '/') + 1);
    tu_assert_no_temporaries(SDFT_TEST_TMP, strrchr(json, '/') + 1);
}

/* Each malformed points file: one line naming it, no output. */
static void test_bad_npy(void **state)
{
    (void)state;
    static const float xyz[8] = {0, 0, 0, 1, 1, 1, 0, 0}; /* and bytes past the (2, 3) array, for bad-long */
    static const float nan_xyz[6] = {0, 0, 0, 1, NAN, 1};
    const char *good = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }";
    const struct {
        const char *file, *dict;
        int version;
        const void *data;
        size_t len;
    } cases[] = {
        {"bad-dtype.npy", "{'descr': '<i4', 'fortran_order': False, 'shape': (2, 3), }", 1, xyz, 24},
        {"bad-endian.npy", "{'descr': '>f4', 'fortran_order': False, 'shape': (2, 3), }", 1, xyz, 24},
        {"bad-shape.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (3, 2), }", 1, xyz, 24},
        {"bad-vector.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (6,), }", 1, xyz, 24},
        {"bad-empty.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (0, 3), }", 1, xyz, 0},
        {"bad-short.npy", good, 1, xyz, 20},
        {"bad-long.npy", good, 2, xyz, 28},
        {"bad-lying.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (4611686018427387000, 3), }", 1, xyz, 24},
        {"bad-huge.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (99999999999999999999999, 3), }", 1, xyz,
         24},
        {"bad-key.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), 'extra': 1, }", 1, xyz, 24},
        {"bad-twice.npy", "{'descr': '<f4', 'descr': '<f4', 'shape': (2, 3), }", 1, xyz, 24},
        {"bad-missing.npy", "{'descr': '<f4', 'shape': (2, 3), }", 1, xyz, 24},
        {"bad-order.npy", "{'descr': '<f4', 'fortran_order': Maybe, 'shape': (2, 3), }", 1, xyz, 24},
        {"bad-syntax.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3) ", 1, xyz, 24},
        {"bad-nan.npy", good, 1, nan_xyz, 24},
        {"bad-version.npy", good, 4, xyz, 24},
        /* a newline in a key or in the dtype: the error stays one line */
        {"bad-key-newline.npy", "{'descr': '<f4', 'fortran_ord\ner': False, 'shape': (2, 3), }", 2, xyz, 24},
        {"bad-dtype-newline.npy", "{'descr': '<f\n4', 'fortran_order': False, 'shape': (2, 3), }", 3, xyz, 24},
    };
    char out[512], in[512], args[1200];
    tu_tmp(out, sizeof out, "bad-query-out.npy");
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        tu_tmp(in, sizeof in, cases[c].file);
        write_npy(in, cases[c].version, cases[c].dict, cases[c].data, cases[c].len);
        snprintf(args, sizeof args, "--query '%s' '%s'", in, out);
        expect_failure(args, cases[c].file, out);
    }
    /* Bad magic; a file cut inside its header; a header longer than the file. */
    const char *raw[] = {"NUMPY\x01\x00", "\x93NUMPY\x01\x00\x76\x00{'descr'", "\x93NUMPY\x01\x00\xff\xff{}\n", "",
                         "\x93NUM"};
    for (size_t r = 0; r < sizeof raw / sizeof *raw; r++) {
        char name[64];
        snprintf(name, sizeof name, "bad-raw-%zu.npy", r);
        tu_tmp(in, sizeof in, name);
        FILE *f = fopen(in, "wb");
        assert_non_null(f);
        fwrite(raw[r], 1, r == 0 ? 8 : strlen(raw[r]), f);
        fclose(f);
        snprintf(args, sizeof args, "--query '%s' '%s'", in, out);
        expect_failure(args, name, out);
    }
    snprintf(args, sizeof args, "--query '%s/no-such.npy' '%s'", SDFT_TEST_TMP, out);
    expect_failure(args, "no-such.npy", out);
    snprintf(args, sizeof args, "--query '%s' '%s'", SDFT_TEST_TMP, out);
    expect_failure(args, SDFT_TEST_TMP, out);
}

/* Bad values of the new flags, and flags out of their mode. */
static void test_bad_flags(void **state)
{
    (void)state;
    char out[512], args[1200];
    tu_tmp(out, sizeof out, "bad-flag-out.npy");
    const char *cases[][2] = {
        {"--samples 0 '%s'", "--samples"},
        {"--samples -5 '%s'", "--samples"},
        {"--samples 2.5 '%s'", "--samples"},
        {"--samples nan '%s'", "--samples"},
        {"--samples 100000001 '%s'", "--samples"},
        {"--samples 10 '%s' --near-sigma -0.1,0.2", "--near-sigma"},
        {"--samples 10 '%s' --near-sigma 0,0.2", "--near-sigma"},
        {"--samples 10 '%s' --near-sigma nan,0.2", "--near-sigma"},
        {"--samples 10 '%s' --near-sigma 0.1", "--near-sigma"},
        {"--samples 10 '%s' --uniform-share -0.1", "--uniform-share"},
        {"--samples 10 '%s' --uniform-share 1.5", "--uniform-share"},
        {"--samples 10 '%s' --uniform-share nan", "--uniform-share"},
        {"--samples 10 '%s' --seed -1", "--seed"},
        {"--samples 10 '%s' --winding", "--winding"},
        {"--samples 10 '%s' -o x.vdb", "-o"},
        {"--query in.npy '%s' --seed 3", "--seed"},
        {"--query in.npy '%s' --samples 10 y.npy", "not both"},
        {"--query in.npy '%s' --sign flood", "--sign"},
        {"--query in.npy", "--query"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        snprintf(args, sizeof args, cases[c][0], out);
        expect_failure(args, cases[c][1], out);
    }
}

/* --help lists the flags of both modes, and the renamed count of
 * --check-sign. */
static void test_help(void **state)
{
    (void)state;
    char out[16384];
    assert_int_equal(tu_run(out, sizeof out, "%s --help", SDFT_MESH2SDF), 0);
    const char *flags[] = {"--samples N OUT.npy",
                           "--query POINTS.npy OUT.npy",
                           "--near-sigma",
                           "--uniform-share",
                           "--seed",
                           "--normalize",
                           "--winding",
                           "--check-points",
                           "0.0707107,0.0223607",
                           "0.06"};
    for (size_t i = 0; i < sizeof flags / sizeof *flags; i++)
        if (!strstr(out, flags[i]))
            fail_msg("--help does not show %s", flags[i]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_help),
        cmocka_unit_test(test_bad_flags),
        cmocka_unit_test(test_bad_npy),
        cmocka_unit_test_prestate(test_samples_exact, "suzanne"),
        cmocka_unit_test_prestate(test_samples_exact, "spot"),
        cmocka_unit_test(test_distribution),
        cmocka_unit_test(test_normalize),
        cmocka_unit_test(test_reproducible),
        cmocka_unit_test(test_query),
    };
    return cmocka_run_group_tests_name("mesh2sdf_samples", tests, NULL, NULL);
}
