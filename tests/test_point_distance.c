/* The point distances (src/mesh/distance/wide_tree.h: a wide bounding volume
 * hierarchy; AVX2 or scalar lanes, single points, seeds, packets, runs along
 * a list of points) held to brute force, through
 * tests/mesh_distance_probe.cpp: at points near, on, far and very far from
 * the repository's meshes and from slivers and triangles of no area, every
 * answer must equal the brute-force minimum of the same triangle formula
 * over every triangle bit for bit, and the distances must agree with this
 * file's own brute force (another formula: closest-point regions,
 * mesh_support.c) to rounding. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "mesh_support.h"
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Runs the probe on `path` with n points; the probe's own checks must all
 * hold, and its rows must be the brute-force distances of `m` (its
 * vertices rounded to float, as the library reads them) within `tolerance`
 * of the mesh's size and the distance. */
static void probe(const char *path, const mesh *m, int n, const char *flags, double tolerance)
{
    char out[512], rows_path[512];
    tu_tmp(rows_path, sizeof rows_path, "distance-probe.rows");
    const int rc = tu_run(out, sizeof out, "'%s' '%s' '%s' %d 5 %s", SDFT_DISTANCE_PROBE, path, rows_path, n, flags);
    printf("%s %s: %s", path, flags, out);
    assert_int_equal(rc, 0);
    int points = 0, mismatches[5] = {1, 1, 1, 1, 1};
    assert_int_equal(sscanf(out, "points=%d triangles=%*d brute=%d scalar=%d seeded=%d packets=%d along=%d", &points,
                            &mismatches[0], &mismatches[1], &mismatches[2], &mismatches[3], &mismatches[4]),
                     6);
    assert_int_equal(points, n);
    for (int i = 0; i < 5; i++)
        assert_int_equal(mismatches[i], 0);

    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, size = 0;
    for (int v = 0; v < m->nv; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m->v[3 * v + k]);
            hi[k] = fmax(hi[k], m->v[3 * v + k]);
        }
    for (int k = 0; k < 3; k++)
        size = fmax(size, hi[k] - lo[k]);
    FILE *f = fopen(rows_path, "rb");
    assert_non_null(f);
    double *rows = malloc(sizeof(double) * 4 * (size_t)n);
    assert_int_equal(fread(rows, sizeof(double) * 4, (size_t)n, f), (size_t)n);
    fclose(f);
    double worst = 0;
    for (int i = 0; i < n; i++) {
        const double *r = &rows[4 * i];
        const double truth = mesh_distance(m, r);
        worst = fmax(worst, fabs(r[3] - truth) / (size + truth));
    }
    printf("  largest difference from the closest-point brute force: %.2e of the size and distance\n", worst);
    assert_true(worst <= tolerance);
    free(rows);
}

static void repository_meshes(void **state)
{
    (void)state;
    const char *names[] = {"suzanne", "fandisk", "spot", "teapot"};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s.obj", SDFT_MESH_DIR, names[i]);
        mesh m = {0};
        assert_int_equal(read_obj(path, &m), 0);
        for (int v = 0; v < 3 * m.nv; v++)
            m.v[v] = (float)m.v[v];
        probe(path, &m, 1200, "", 1e-12);
        mesh_free(&m);
    }
}

/* A cube with slivers beside it (mesh_add_slivers: thinner than the
 * distance formula's threshold for a reliable normal, and just above it),
 * and, added by the probe, a segment, a triangle with a repeated corner and
 * a point. The corners are exact in float, so the probe and the brute force
 * see the same triangles. */
static void slivers_and_degenerate_triangles(void **state)
{
    (void)state;
    mesh m = {0};
    for (int i = 0; i < 8; i++)
        mesh_vertex(&m, i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
    const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                              {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (int f = 0; f < 12; f++)
        mesh_triangle(&m, faces[f][0], faces[f][1], faces[f][2]);
    mesh_add_slivers(&m);
    char off[512];
    tu_tmp(off, sizeof off, "distance-slivers.off");
    write_off(off, &m);
    /* The slivers above the threshold: their normals' error (about 3e-8). */
    probe(off, &m, 4000, "--degenerate", 1e-7);
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(repository_meshes),
        cmocka_unit_test(slivers_and_degenerate_triangles),
    };
    return cmocka_run_group_tests_name("mesh_distance", tests, NULL, NULL);
}
