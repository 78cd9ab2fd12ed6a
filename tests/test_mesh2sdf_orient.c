/* mesh2sdf's orientation (convert/orient.cpp): the five shared meshes made
 * inside out, with a share of their faces reversed, as unwelded soups, with
 * reversed duplicates of some faces, and all of that at once, must sign like
 * the original mesh: no point that the brute-force winding number of the
 * ORIGINAL calls clearly inside or outside, 3 or more voxels from its
 * surface, may get the wrong sign. Well-oriented meshes convert to the same
 * grid as with --orient none, bit for bit. The health counts are checked on
 * small meshes whose answers are known. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_support.h"
#include "testutil.h"

#define RES 64
#define POINTS 700

/* ------------------------------------------------------------ variants */

typedef enum { INSIDE_OUT, REVERSED_30, REVERSED_50, SOUP, DUPLICATED, EVERYTHING, VARIANTS } variant;
static const char *const variant_name[VARIANTS] = {"inside-out", "reversed-30", "reversed-50",
                                                   "soup",       "duplicated",  "everything"};

static void reverse(mesh *m, int t)
{
    const int b = m->t[3 * t + 1];
    m->t[3 * t + 1] = m->t[3 * t + 2];
    m->t[3 * t + 2] = b;
}

/* Every triangle with three vertices of its own. */
static void make_soup(const mesh *in, mesh *out)
{
    for (int t = 0; t < in->nt; t++) {
        for (int k = 0; k < 3; k++) {
            const double *p = &in->v[3 * in->t[3 * t + k]];
            mesh_vertex(out, p[0], p[1], p[2]);
        }
        mesh_triangle(out, 3 * t, 3 * t + 1, 3 * t + 2);
    }
}

/* `in` made into variant `v`, seeded. */
static void make_variant(const mesh *in, variant v, mesh *out)
{
    tu_rng rng = tu_rng_seed(1000 + (uint64_t)v);
    if (v == SOUP || v == EVERYTHING) {
        make_soup(in, out);
    } else {
        for (int i = 0; i < in->nv; i++)
            mesh_vertex(out, in->v[3 * i], in->v[3 * i + 1], in->v[3 * i + 2]);
        for (int t = 0; t < in->nt; t++)
            mesh_triangle(out, in->t[3 * t], in->t[3 * t + 1], in->t[3 * t + 2]);
    }
    const int n = out->nt;
    for (int t = 0; t < n; t++) {
        const float u = tu_uniform(&rng, 0, 1);
        if (v == INSIDE_OUT || (v == REVERSED_30 && u < 0.3f) || ((v == REVERSED_50 || v == EVERYTHING) && u < 0.5f))
            reverse(out, t);
    }
    if (v == DUPLICATED || v == EVERYTHING)
        for (int t = 0; t < n; t++)
            if (tu_uniform(&rng, 0, 1) < 0.1f) {
                /* A reversed copy on the same vertices (on the soup's, its own). */
                mesh_triangle(out, out->t[3 * t], out->t[3 * t + 2], out->t[3 * t + 1]);
            }
}

/* ------------------------------------------------------ the sign check */

typedef struct truth {
    int ijk[POINTS][3];
    int inside[POINTS]; /* 1 inside, 0 outside, -1 unclear or within 3 voxels */
    int clear, clear_inside;
} truth;

/* Random voxels of grid `g` judged by the original mesh's brute-force
 * winding number, kept where it is clear and the point is 3 or more voxels
 * from the surface. */
static void judge(const mesh *m, const dense *g, truth *tr)
{
    tu_rng rng = tu_rng_seed(77);
    tr->clear = tr->clear_inside = 0;
    for (int s = 0; s < POINTS; s++) {
        double p[3];
        for (int k = 0; k < 3; k++) {
            tr->ijk[s][k] = (int)tu_uniform(&rng, 0, (float)g->n[k]);
            if (tr->ijk[s][k] >= g->n[k])
                tr->ijk[s][k] = g->n[k] - 1;
        }
        dense_point(g, tr->ijk[s][0], tr->ijk[s][1], tr->ijk[s][2], p);
        const double w = winding(m, p);
        tr->inside[s] = -1;
        if ((w > 0.25 && w < 0.75) || mesh_distance(m, p) < 3 * g->h)
            continue;
        tr->inside[s] = w > 0.75;
        tr->clear++;
        tr->clear_inside += w > 0.75;
    }
}

/* Points of `tr` whose sign `g` gets wrong. */
static int wrong_signs(const truth *tr, const dense *g)
{
    int wrong = 0;
    for (int s = 0; s < POINTS; s++)
        if (tr->inside[s] >= 0)
            wrong += (dense_at(g, tr->ijk[s][0], tr->ijk[s][1], tr->ijk[s][2]) < 0) != tr->inside[s];
    return wrong;
}

static void check_mesh(const char *name)
{
    char in[1024], off[512], file[256], flags[64];
    snprintf(in, sizeof in, "%s/%s.obj", SDFT_MESH_DIR, name);
    mesh m = {0};
    assert_int_equal(read_obj(in, &m), 0);
    snprintf(flags, sizeof flags, "--res %d", RES);
    dense original = {0};
    snprintf(file, sizeof file, "%s-original", name);
    convert(in, file, flags, &original);
    truth *tr = malloc(sizeof *tr);
    judge(&m, &original, tr);
    assert_true(tr->clear > POINTS / 2 && tr->clear_inside > tr->clear / 50);
    assert_int_equal(wrong_signs(tr, &original), 0);
    for (int v = 0; v < VARIANTS; v++) {
        mesh bad = {0};
        make_variant(&m, (variant)v, &bad);
        snprintf(file, sizeof file, "%s-%s.off", name, variant_name[v]);
        tu_tmp(off, sizeof off, file);
        write_off(off, &bad);
        mesh_free(&bad);
        dense g = {0};
        snprintf(file, sizeof file, "%s-%s", name, variant_name[v]);
        convert(off, file, flags, &g);
        assert_memory_equal(g.n, original.n, sizeof g.n);
        const int wrong = wrong_signs(tr, &g);
        printf("%s %s %d^3: %d clear points 3+ voxels from the surface (%d inside), %d wrong sign\n", name,
               variant_name[v], RES, tr->clear, tr->clear_inside, wrong);
        assert_int_equal(wrong, 0);
        /* Without orienting, the inside-out mesh is wrong: the check can fail. */
        if (v == INSIDE_OUT) {
            dense raw = {0};
            snprintf(file, sizeof file, "%s-%s-raw", name, variant_name[v]);
            snprintf(flags, sizeof flags, "--res %d --orient none", RES);
            convert(off, file, flags, &raw);
            snprintf(flags, sizeof flags, "--res %d", RES);
            const int raw_wrong = wrong_signs(tr, &raw);
            printf("%s %s --orient none: %d wrong sign\n", name, variant_name[v], raw_wrong);
            assert_true(raw_wrong > tr->clear / 20);
            free(raw.data);
        }
        free(g.data);
    }
    free(tr);
    free(original.data);
    mesh_free(&m);
}

/* One of the shared meshes, named by the test's state. */
static void test_orient(void **state) { check_mesh((const char *)*state); }

/* Well-oriented meshes are left as they are: the same grid, narrow band and
 * dense, with and without orienting (suzanne too, though one of its faces
 * folds back onto another, a reversed duplicate that orienting drops: the
 * one left is where the pair was). */
static void test_well_oriented_unchanged(void **state)
{
    (void)state;
    const char *names[] = {"spot", "stanford-bunny", "teapot", "suzanne", "fandisk"};
    for (int i = 0; i < 5; i++) {
        char in[1024], file[256];
        snprintf(in, sizeof in, "%s/%s.obj", SDFT_MESH_DIR, names[i]);
        for (int full = 0; full < 2; full++) {
            dense a = {0}, b = {0};
            snprintf(file, sizeof file, "%s-outward-%d", names[i], full);
            convert(in, file, full ? "--res 48 --full" : "--res 48", &a);
            snprintf(file, sizeof file, "%s-none-%d", names[i], full);
            convert(in, file, full ? "--res 48 --full --orient none" : "--res 48 --orient none", &b);
            assert_memory_equal(a.n, b.n, sizeof a.n);
            assert_memory_equal(a.data, b.data, sizeof(float) * (size_t)a.n[0] * a.n[1] * a.n[2]);
            free(a.data);
            free(b.data);
        }
    }
}

/* ------------------------------------------------------- health counts */

static const double cube_v[8][3] = {{-.5, -.5, -.5}, {.5, -.5, -.5}, {.5, .5, -.5}, {-.5, .5, -.5},
                                    {-.5, -.5, .5},  {.5, -.5, .5},  {.5, .5, .5},  {-.5, .5, .5}};
/* Outward counter-clockwise quads. */
static const int cube_q[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};

/* Writes a cube of half-size s at the origin as OBJ quads after `first`
 * vertices already written: quad q reversed where bit q of `flip` is set. */
static void put_cube(FILE *f, double s, int first, unsigned flip)
{
    for (int i = 0; i < 8; i++)
        fprintf(f, "v %g %g %g\n", 2 * s * cube_v[i][0], 2 * s * cube_v[i][1], 2 * s * cube_v[i][2]);
    for (int q = 0; q < 6; q++) {
        const int *c = cube_q[q];
        if (flip >> q & 1)
            fprintf(f, "f %d %d %d %d\n", first + c[3] + 1, first + c[2] + 1, first + c[1] + 1, first + c[0] + 1);
        else
            fprintf(f, "f %d %d %d %d\n", first + c[0] + 1, first + c[1] + 1, first + c[2] + 1, first + c[3] + 1);
    }
}

/* mesh2sdf --json on `path`, the output in `out`; returns the value of
 * "key" (with its quotes). */
static double json_count(const char *out, const char *key) { return json_number(out, key, 0); }

static void run_json(const char *path, const char *extra, char *out, size_t out_len)
{
    char vdb[512];
    tu_tmp(vdb, sizeof vdb, "health.vdb");
    const int rc = tu_run(out, out_len, "%s '%s' -o '%s' --res 24 --json %s", SDFT_MESH2SDF, path, vdb, extra);
    if (rc != 0)
        fail_msg("mesh2sdf failed (%d): %s", rc, out);
}

static void test_health_counts(void **state)
{
    (void)state;
    char path[512], out[8192];
    tu_tmp(path, sizeof path, "health.obj");

    /* A cube with two of its six quads reversed: one patch, their four
     * triangles turned back, nothing turned outward, a surface. */
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    put_cube(f, 0.5, 0, 1u << 1 | 1u << 4);
    fclose(f);
    run_json(path, "", out, sizeof out);
    assert_int_equal(json_count(out, "\"vertices\""), 8);
    assert_int_equal(json_count(out, "\"faces\""), 6);
    assert_int_equal(json_count(out, "\"triangles\""), 12);
    assert_int_equal(json_count(out, "\"patches\""), 1);
    assert_int_equal(json_count(out, "\"reoriented_faces\""), 4);
    assert_int_equal(json_count(out, "\"outward_patches\""), 0);
    assert_int_equal(json_count(out, "\"boundary_edges\""), 0);
    assert_int_equal(json_count(out, "\"non_manifold_edges\""), 0);
    assert_non_null(strstr(out, "\"surface\": true"));

    /* The whole cube inside out: every triangle turned, the patch outward
     * (its faces clear of the lattice's points, whose sign on a face would
     * be a toss). */
    f = fopen(path, "w");
    put_cube(f, 0.4937, 0, 63);
    fclose(f);
    run_json(path, "", out, sizeof out);
    assert_int_equal(json_count(out, "\"reoriented_faces\""), 12);
    assert_int_equal(json_count(out, "\"outward_patches\""), 1);
    assert_non_null(strstr(out, "\"surface\": true"));
    /* ... and without orienting, no voxel is inside: said, not silent. */
    run_json(path, "--orient none", out, sizeof out);
    assert_non_null(strstr(out, "\"surface\": false"));
    assert_non_null(strstr(out, "warning: no voxel of the band is inside"));
    assert_null(strstr(out, "\"patches\""));

    /* Two nested cubes, the inner one facing in (a hollow box): two
     * patches, the inner kept as a cavity's wall. */
    f = fopen(path, "w");
    put_cube(f, 0.5, 0, 0);
    put_cube(f, 0.3, 8, 63);
    fclose(f);
    run_json(path, "", out, sizeof out);
    assert_int_equal(json_count(out, "\"vertices\""), 16);
    assert_int_equal(json_count(out, "\"patches\""), 2);
    assert_int_equal(json_count(out, "\"reoriented_faces\""), 0);
    assert_int_equal(json_count(out, "\"cavity_patches\""), 1);
    assert_int_equal(json_count(out, "\"outward_patches\""), 0);
    /* Both inside out: the outer one turned outward, and then the inner. */
    f = fopen(path, "w");
    put_cube(f, 0.5, 0, 63);
    put_cube(f, 0.3, 8, 0);
    fclose(f);
    run_json(path, "", out, sizeof out);
    assert_int_equal(json_count(out, "\"patches\""), 2);
    assert_int_equal(json_count(out, "\"outward_patches\""), 1);
    assert_int_equal(json_count(out, "\"reoriented_faces\""), 12);

    /* A cube soup: 36 vertices, each triangle its own, welded into one
     * closed patch of 8 vertices; a reversed duplicate of one triangle. */
    f = fopen(path, "w");
    for (int q = 0; q < 6; q++)
        for (int k = 0; k < 2; k++) {
            const int *c = cube_q[q];
            const int tri[3] = {c[0], c[1 + k], c[2 + k]};
            for (int i = 0; i < 3; i++)
                fprintf(f, "v %g %g %g\n", cube_v[tri[i]][0], cube_v[tri[i]][1], cube_v[tri[i]][2]);
            fprintf(f, "f %d %d %d\n", 6 * q + 3 * k + 1, 6 * q + 3 * k + 2, 6 * q + 3 * k + 3);
        }
    fprintf(f, "f 1 3 2\n");
    fclose(f);
    run_json(path, "", out, sizeof out);
    assert_int_equal(json_count(out, "\"vertices\""), 36);
    assert_int_equal(json_count(out, "\"faces\""), 13);
    assert_int_equal(json_count(out, "\"welded_vertices\""), 28);
    assert_int_equal(json_count(out, "\"duplicate_faces\""), 1);
    assert_int_equal(json_count(out, "\"patches\""), 1);
    assert_int_equal(json_count(out, "\"boundary_edges\""), 0);
    assert_int_equal(json_count(out, "\"non_manifold_edges\""), 0);
    assert_int_equal(json_count(out, "\"reoriented_faces\""), 0);

    /* A flat square: an open patch with no clear outside, said. */
    f = fopen(path, "w");
    fprintf(f, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    fclose(f);
    run_json(path, "", out, sizeof out);
    assert_int_equal(json_count(out, "\"ambiguous_patches\""), 1);
    assert_true(json_count(out, "\"ambiguous_voxels\"") > 0);
    assert_non_null(strstr(out, "warning: 1 open patches have no clear outside"));
}

/* The loader keeps the file's faces on the file's vertices: a mesh with
 * faces reversed at random reads as many vertices as it has (OpenMesh's
 * own mesh would split it along every reversed face). */
static void test_reads_what_was_written(void **state)
{
    (void)state;
    char in[1024], off[512], out[8192];
    snprintf(in, sizeof in, "%s/spot.obj", SDFT_MESH_DIR);
    mesh m = {0}, bad = {0};
    assert_int_equal(read_obj(in, &m), 0);
    make_variant(&m, REVERSED_30, &bad);
    tu_tmp(off, sizeof off, "spot-reversed-30-read.off");
    write_off(off, &bad);
    run_json(off, "", out, sizeof out);
    assert_int_equal(json_count(out, "\"vertices\""), m.nv);
    assert_int_equal(json_count(out, "\"faces\""), m.nt);
    assert_int_equal(json_count(out, "\"welded_vertices\""), 0);
    assert_int_equal(json_count(out, "\"patches\""), 1);
    assert_int_equal(json_count(out, "\"boundary_edges\""), 0);
    assert_int_equal(json_count(out, "\"non_manifold_edges\""), 0);
    int reversed = 0;
    for (int t = 0; t < m.nt; t++)
        reversed += bad.t[3 * t + 1] != m.t[3 * t + 1];
    assert_int_equal(json_count(out, "\"reoriented_faces\""), reversed);
    mesh_free(&m);
    mesh_free(&bad);
}

static void test_bad_orient_flag(void **state)
{
    (void)state;
    char out[4096], in[1024], vdb[512];
    snprintf(in, sizeof in, "%s/spot.obj", SDFT_MESH_DIR);
    tu_tmp(vdb, sizeof vdb, "bad-orient.vdb");
    assert_int_not_equal(tu_run(out, sizeof out, "%s '%s' -o '%s' --orient sideways", SDFT_MESH2SDF, in, vdb), 0);
    assert_non_null(strstr(out, "--orient must be none or outward"));
    assert_int_equal(tu_lines(out), 1);
    assert_false(tu_file_exists(vdb));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_orient_flag),
        cmocka_unit_test(test_health_counts),
        cmocka_unit_test(test_reads_what_was_written),
        cmocka_unit_test(test_well_oriented_unchanged),
        cmocka_unit_test_prestate(test_orient, "spot"),
        cmocka_unit_test_prestate(test_orient, "fandisk"),
        cmocka_unit_test_prestate(test_orient, "suzanne"),
        cmocka_unit_test_prestate(test_orient, "teapot"),
        cmocka_unit_test_prestate(test_orient, "stanford-bunny"),
    };
    return cmocka_run_group_tests_name("mesh2sdf_orient", tests, NULL, NULL);
}
