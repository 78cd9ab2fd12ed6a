/* mesh2sdf tests: distances against exact formulas (cube, icosphere), the
 * sign against a brute-force winding number on the five shared meshes, a
 * round trip through `sdftrace render --grid`, and every bad-input case.
 * Grids are read back through mesh2sdf's --npy output and its JSON sidecar. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_support.h"
#include "sdftrace/config.h"
#include "testutil.h"

#define BAND 3.0

/* ---------------------------------------------------------------- meshes */

/* Unit cube [-0.5, 0.5]^3, outward counter-clockwise faces, as quads. */
static const double cube_v[8][3] = {{-.5, -.5, -.5}, {.5, -.5, -.5}, {.5, .5, -.5}, {-.5, .5, -.5},
                                    {-.5, -.5, .5},  {.5, -.5, .5},  {.5, .5, .5},  {-.5, .5, .5}};
static const int cube_q[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};

static void make_cube(mesh *m)
{
    for (int i = 0; i < 8; i++)
        mesh_vertex(m, cube_v[i][0], cube_v[i][1], cube_v[i][2]);
    for (int q = 0; q < 6; q++) {
        mesh_triangle(m, cube_q[q][0], cube_q[q][1], cube_q[q][2]);
        mesh_triangle(m, cube_q[q][0], cube_q[q][2], cube_q[q][3]);
    }
}

static void write_cube_obj(const char *path, int skip_faces, int degenerate)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    for (int i = 0; i < 8; i++)
        fprintf(f, "v %g %g %g\n", cube_v[i][0], cube_v[i][1], cube_v[i][2]);
    for (int q = skip_faces; q < 6; q++)
        fprintf(f, "f %d %d %d %d\n", cube_q[q][0] + 1, cube_q[q][1] + 1, cube_q[q][2] + 1, cube_q[q][3] + 1);
    /* Zero-area faces on three collinear vertices of their own (OpenMesh
     * itself drops faces that repeat a vertex index). */
    if (degenerate > 0)
        fprintf(f, "v 2 2 2\nv 3 3 3\nv 4 4 4\n");
    for (int d = 0; d < degenerate; d++)
        fprintf(f, d % 2 ? "f 11 10 9\n" : "f 9 10 11\n");
    fclose(f);
}

static void write_ply(const char *path, const mesh *m)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f,
            "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
            "element face %d\nproperty list uchar int vertex_indices\nend_header\n",
            m->nv, m->nt);
    for (int i = 0; i < m->nv; i++)
        fprintf(f, "%.9g %.9g %.9g\n", m->v[3 * i], m->v[3 * i + 1], m->v[3 * i + 2]);
    for (int i = 0; i < m->nt; i++)
        fprintf(f, "3 %d %d %d\n", m->t[3 * i], m->t[3 * i + 1], m->t[3 * i + 2]);
    fclose(f);
}

/* Binary little-endian PLY whose first coordinate is `poison`. */
static void write_binary_ply(const char *path, const mesh *m, float poison)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fprintf(f,
            "ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
            "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n",
            m->nv, m->nt);
    for (int i = 0; i < m->nv; i++)
        for (int k = 0; k < 3; k++) {
            float x = i == 0 && k == 0 ? poison : (float)m->v[3 * i + k];
            fwrite(&x, 4, 1, f);
        }
    for (int i = 0; i < m->nt; i++) {
        unsigned char three = 3;
        fwrite(&three, 1, 1, f);
        for (int k = 0; k < 3; k++) {
            int32_t idx = m->t[3 * i + k];
            fwrite(&idx, 4, 1, f);
        }
    }
    fclose(f);
}

/* Binary STL; `poison` replaces the first coordinate with that value. */
static void write_stl(const char *path, const mesh *m, float poison, int use_poison)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    char header[80] = "mesh2sdf test";
    fwrite(header, 1, 80, f);
    uint32_t n = (uint32_t)m->nt;
    fwrite(&n, 4, 1, f);
    for (int i = 0; i < m->nt; i++) {
        float rec[12] = {0};
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++)
                rec[3 + 3 * c + k] = (float)m->v[3 * m->t[3 * i + c] + k];
        if (use_poison && i == 0)
            rec[3] = poison;
        uint16_t attr = 0;
        fwrite(rec, 4, 12, f);
        fwrite(&attr, 2, 1, f);
    }
    fclose(f);
}

/* Icosahedron subdivided `levels` times, vertices pushed to the unit sphere. */
static void make_icosphere(mesh *m, int levels)
{
    const double p = (1.0 + sqrt(5.0)) / 2.0;
    const double base[12][3] = {{-1, p, 0},  {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                                {0, -1, -p}, {0, 1, -p}, {p, 0, -1},  {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
    const int faces[20][3] = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                              {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                              {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int i = 0; i < 12; i++) {
        double l = sqrt(base[i][0] * base[i][0] + base[i][1] * base[i][1] + base[i][2] * base[i][2]);
        mesh_vertex(m, base[i][0] / l, base[i][1] / l, base[i][2] / l);
    }
    for (int i = 0; i < 20; i++)
        mesh_triangle(m, faces[i][0], faces[i][1], faces[i][2]);
    for (int l = 0; l < levels; l++) {
        mesh next = {0};
        for (int i = 0; i < m->nv; i++)
            mesh_vertex(&next, m->v[3 * i], m->v[3 * i + 1], m->v[3 * i + 2]);
        for (int t = 0; t < m->nt; t++) {
            int c[3], mid[3];
            for (int k = 0; k < 3; k++)
                c[k] = m->t[3 * t + k];
            for (int k = 0; k < 3; k++) {
                /* Midpoints are not shared between triangles: the soup has
                 * duplicated vertices along edges, which mesh2sdf welds. */
                const double *a = &m->v[3 * c[k]], *b = &m->v[3 * c[(k + 1) % 3]];
                double x = a[0] + b[0], y = a[1] + b[1], z = a[2] + b[2], len = sqrt(x * x + y * y + z * z);
                mid[k] = next.nv;
                mesh_vertex(&next, x / len, y / len, z / len);
            }
            mesh_triangle(&next, c[0], mid[0], mid[2]);
            mesh_triangle(&next, c[1], mid[1], mid[0]);
            mesh_triangle(&next, c[2], mid[2], mid[1]);
            mesh_triangle(&next, mid[0], mid[1], mid[2]);
        }
        mesh_free(m);
        *m = next;
    }
}

/* Meshes whose winding number crosses 1/2 away from the surface, where a
 * flood fill leaks through holes and one winding number per tile speaks for
 * the tile's centre only. A band of the sphere of radius r between polar
 * angles th0 and th1 (radians), nth rings by nph segments, facing outward
 * (inward when `inward`); quad (i, j) is left out where `hole(i, j)`; with
 * th0 = 0 a pole vertex closes the top. */
typedef int (*hole_fn)(int i, int j);

static void add_sphere_band(mesh *m, double r, double th0, double th1, int nth, int nph, int inward, hole_fn hole)
{
    const int pole = th0 == 0, first = m->nv;
    if (pole)
        mesh_vertex(m, 0, 0, r);
    for (int i = pole; i <= nth; i++) {
        const double th = th0 + (th1 - th0) * i / nth;
        for (int j = 0; j < nph; j++) {
            const double ph = 2 * 3.14159265358979323846 * j / nph;
            mesh_vertex(m, r * sin(th) * cos(ph), r * sin(th) * sin(ph), r * cos(th));
        }
    }
#define RING(i, j) ((i) == 0 && pole ? first : first + pole + ((i)-pole) * nph + ((j) % nph))
    for (int i = 0; i < nth; i++)
        for (int j = 0; j < nph; j++) {
            if (hole && hole(i, j))
                continue;
            const int a = RING(i, j), b = RING(i, j + 1), c = RING(i + 1, j + 1), d = RING(i + 1, j);
            const int t[2][3] = {{a, d, c}, {a, c, b}};
            for (int k = 0; k < 2 - (i == 0 && pole); k++)
                if (inward)
                    mesh_triangle(m, t[k][0], t[k][2], t[k][1]);
                else
                    mesh_triangle(m, t[k][0], t[k][1], t[k][2]);
        }
#undef RING
}

/* An insect's thin double-walled open shell: two nearly parallel sheets, the
 * outer facing out and the inner facing in, with the same large windows cut
 * through both, so the wall between them is inside. */
static int window(int i, int j) { return (i / 3) % 2 == 1 && (j / 4) % 3 == 1; }

static void make_double_wall(mesh *m)
{
    add_sphere_band(m, 1.0, 0, 2.4, 12, 24, 0, window);
    add_sphere_band(m, 0.85, 0, 2.4, 12, 24, 1, window);
}

/* Three open hemispherical cups nested in one another. */
static void make_nested_cups(mesh *m)
{
    for (int c = 0; c < 3; c++)
        add_sphere_band(m, 1.0 - 0.25 * c, 0, 1.5707963267948966, 8, 20, 0, NULL);
}

/* A closed sphere but for a slit two segments wide down its side and two
 * small holes at its poles. */
static int slit(int i, int j) { return j < 2 && i >= 2 && i <= 9; }

static void make_slit_sphere(mesh *m) { add_sphere_band(m, 1.0, 0.05, 3.14159265358979323846 - 0.05, 12, 24, 0, slit); }

/* Eight open discs of radius 1 stacked a little apart, all facing the same
 * way (pages of a book): the winding number runs from 4 below the stack to
 * -4 above it around the rim, so it crosses 1/2 steeply off the band, inside
 * single tiles. Heights avoid lattice points. */
static void make_sheet_stack(mesh *m)
{
    for (int c = 0; c < 8; c++) {
        const double z = 0.0317 * c + 0.0071;
        const int first = m->nv, rings = 3, segments = 16;
        mesh_vertex(m, 0, 0, z);
        for (int i = 1; i <= rings; i++)
            for (int j = 0; j < segments; j++) {
                const double r = (double)i / rings, ph = 2 * 3.14159265358979323846 * j / segments;
                mesh_vertex(m, r * cos(ph), r * sin(ph), z);
            }
#define DISC(i, j) ((i) == 0 ? first : first + 1 + ((i)-1) * segments + ((j) % segments))
        for (int i = 0; i < rings; i++)
            for (int j = 0; j < segments; j++) {
                if (i == 0) {
                    mesh_triangle(m, first, DISC(1, j), DISC(1, j + 1));
                    continue;
                }
                mesh_triangle(m, DISC(i, j), DISC(i + 1, j), DISC(i + 1, j + 1));
                mesh_triangle(m, DISC(i, j), DISC(i + 1, j + 1), DISC(i, j + 1));
            }
#undef DISC
    }
}

/* ------------------------------------------------------- exact geometry */

static double box_sdf(const double *p)
{
    double q[3], out = 0, in = -INFINITY;
    for (int k = 0; k < 3; k++) {
        q[k] = fabs(p[k]) - 0.5;
        out += q[k] > 0 ? q[k] * q[k] : 0;
        in = fmax(in, q[k]);
    }
    return sqrt(out) + fmin(in, 0.0);
}

/* ------------------------------------------------------ reading grids */

/* Compares every voxel whose exact distance is within the band (less half
 * a voxel) with the exact signed distance; returns the largest error in
 * voxels and how many voxels were compared. */
typedef double (*exact_fn)(const void *ctx, const double *p);

static double band_error(const dense *g, exact_fn exact, const void *ctx, double band, long *compared)
{
    double worst = 0;
    *compared = 0;
    for (int i = 0; i < g->n[0]; i++)
        for (int j = 0; j < g->n[1]; j++)
            for (int k = 0; k < g->n[2]; k++) {
                double p[3];
                dense_point(g, i, j, k, p);
                double d = exact(ctx, p);
                if (fabs(d) > (band - 0.5) * g->h)
                    continue;
                double err = fabs(dense_at(g, i, j, k) - d) / g->h;
                if (err > worst)
                    worst = err;
                (*compared)++;
            }
    return worst;
}

static double exact_box(const void *ctx, const double *p)
{
    (void)ctx;
    return box_sdf(p);
}

static double exact_mesh(const void *ctx, const double *p) { return mesh_sdf((const mesh *)ctx, p); }

/* ------------------------------------------------------------- tests */

static void test_cube_distances(void **state)
{
    (void)state;
    char obj[512];
    tu_tmp(obj, sizeof obj, "cube.obj");
    write_cube_obj(obj, 0, 0);
    dense g = {0};
    convert(obj, "cube", "--res 64", &g);
    assert_int_equal(g.n[0], 64);
    long n;
    double worst = band_error(&g, exact_box, NULL, BAND, &n);
    printf("cube (obj, quads) 64^3: %ld band voxels, worst error %.4f voxel\n", n, worst);
    free(g.data);
    assert_true(n > 10000);
    assert_true(worst <= 0.05);

    /* The same cube as OFF, densely (--full): every voxel of the box. */
    mesh m = {0};
    make_cube(&m);
    char off[512];
    tu_tmp(off, sizeof off, "cube.off");
    write_off(off, &m);
    convert(off, "cube_full", "--res 48 --full", &g);
    worst = band_error(&g, exact_box, NULL, 1e9, &n);
    printf("cube (off) 48^3 --full: %ld voxels, worst error %.4f voxel\n", n, worst);
    const long all = (long)g.n[0] * g.n[1] * g.n[2];
    free(g.data);
    mesh_free(&m);
    assert_int_equal(n, all);
    assert_true(worst <= 0.05);
}

static void test_icosphere_distances(void **state)
{
    (void)state;
    mesh m = {0};
    make_icosphere(&m, 2);
    char ply[512], stl[512];
    tu_tmp(ply, sizeof ply, "icosphere.ply");
    tu_tmp(stl, sizeof stl, "icosphere.stl");
    write_ply(ply, &m);
    write_stl(stl, &m, 0, 0);

    dense g = {0};
    convert(ply, "icosphere", "--res 64", &g);
    long n;
    double worst = band_error(&g, exact_mesh, &m, BAND, &n);
    printf("icosphere (ply) 64^3: %ld band voxels, worst error %.4f voxel\n", n, worst);
    free(g.data);
    g.data = NULL;
    if (n <= 10000 || worst > 0.05)
        mesh_free(&m);
    assert_true(n > 10000);
    assert_true(worst <= 0.05);

    convert(stl, "icosphere_full", "--res 40 --full --sign winding", &g);
    worst = band_error(&g, exact_mesh, &m, 1e9, &n);
    printf("icosphere (stl) 40^3 --full: %ld voxels, worst error %.4f voxel\n", n, worst);
    free(g.data);
    mesh_free(&m);
    assert_true(worst <= 0.05);
}

/* The level-set convention sdftrace's grid bounds rest on (the tree bound in
 * src/grid/grid_sample.c, the far bound in src/grid/grid_bound.c): no stored
 * value, the +-background of voxels outside the band included, exceeds the
 * true distance. Returns the largest excess |value| - |exact| in voxels. */
static double convention_excess(const dense *g, exact_fn exact, const void *ctx)
{
    double worst = -INFINITY;
    for (int i = 0; i < g->n[0]; i++)
        for (int j = 0; j < g->n[1]; j++)
            for (int k = 0; k < g->n[2]; k++) {
                double p[3];
                dense_point(g, i, j, k, p);
                double excess = (fabs(dense_at(g, i, j, k)) - fabs(exact(ctx, p))) / g->h;
                if (excess > worst)
                    worst = excess;
            }
    return worst;
}

static void test_band_never_overstates_distance(void **state)
{
    (void)state;
    char obj[512], ply[512];
    tu_tmp(obj, sizeof obj, "cube_convention.obj");
    write_cube_obj(obj, 0, 0);
    dense g = {0};
    convert(obj, "cube_convention", "--res 64", &g);
    double cube = convention_excess(&g, exact_box, NULL);
    free(g.data);

    mesh m = {0};
    make_icosphere(&m, 2);
    tu_tmp(ply, sizeof ply, "icosphere_convention.ply");
    write_ply(ply, &m);
    g = (dense){0};
    convert(ply, "icosphere_convention", "--res 48", &g);
    double sphere = convention_excess(&g, exact_mesh, &m);
    free(g.data);
    mesh_free(&m);
    printf("largest |value| - |exact distance|: cube %.4f, icosphere %.4f voxel\n", cube, sphere);
    assert_true(cube <= 0.01);
    assert_true(sphere <= 0.01);
}

/* At random voxels of a 96^3 grid, the brute-force winding number decides
 * clearly inside (> 0.75) or outside (< 0.25); the grid's sign must agree on
 * at least 99.9% of them. */
static void check_sign(const char *name, int samples)
{
    char in[1024];
    snprintf(in, sizeof in, "%s/%s.obj", SDFT_MESH_DIR, name);
    mesh m = {0};
    assert_int_equal(read_obj(in, &m), 0);
    assert_true(m.nt > 0);
    dense g = {0};
    convert(in, name, "--res 96", &g);
    tu_rng rng = tu_rng_seed(7);
    int clear = 0, wrong = 0, inside = 0;
    for (int s = 0; s < samples; s++) {
        int ijk[3];
        for (int k = 0; k < 3; k++) {
            ijk[k] = (int)tu_uniform(&rng, 0, (float)g.n[k]);
            if (ijk[k] >= g.n[k])
                ijk[k] = g.n[k] - 1;
        }
        double p[3];
        dense_point(&g, ijk[0], ijk[1], ijk[2], p);
        double w = winding(&m, p);
        if (w > 0.25 && w < 0.75)
            continue;
        clear++;
        inside += w > 0.75;
        int grid_inside = dense_at(&g, ijk[0], ijk[1], ijk[2]) < 0;
        if (grid_inside != (w > 0.75))
            wrong++;
    }
    printf("%s 96^3: %d clear points (%d inside), %d wrong sign\n", name, clear, inside, wrong);
    free(g.data);
    mesh_free(&m);
    assert_true(inside > clear / 50);
    assert_true(wrong * 1000 <= clear);
}

static void test_sign_bunny(void **state)
{
    (void)state;
    check_sign("stanford-bunny", 1500);
}
static void test_sign_spot(void **state)
{
    (void)state;
    check_sign("spot", 3000);
}
static void test_sign_teapot(void **state)
{
    (void)state;
    check_sign("teapot", 3000);
}
static void test_sign_suzanne(void **state)
{
    (void)state;
    check_sign("suzanne", 3000);
}
static void test_sign_fandisk(void **state)
{
    (void)state;
    check_sign("fandisk", 3000);
}

/* The brute-force distance from voxel (i, j, k) of `g` to the nearest
 * triangle of `m`, and how far (in voxels) the grid's |value| is from it. */
static double dense_distance_error(const mesh *m, const dense *g, const int *ijk, double *exact)
{
    double p[3];
    dense_point(g, ijk[0], ijk[1], ijk[2], p);
    *exact = mesh_distance(m, p);
    return fabs(fabs(dense_at(g, ijk[0], ijk[1], ijk[2])) - *exact) / g->h;
}

/* |value| of a --full grid must equal the brute-force distance to the
 * nearest triangle within 1e-4 voxel at `samples` random voxels of the box
 * (most off the band), and at `samples` random voxels within BAND + 4
 * voxels of the surface (in the band, and just beyond it, where a search
 * shares its packet with band voxels). */
static void check_dense_distances(const char *name, const mesh *m, const dense *g, int samples)
{
    tu_rng rng = tu_rng_seed(11);
    double worst = 0, exact;
    int off_band = 0, near = 0, in_band = 0;
    for (int s = 0; s < samples; s++) {
        int ijk[3];
        for (int k = 0; k < 3; k++) {
            ijk[k] = (int)tu_uniform(&rng, 0, (float)g->n[k]);
            if (ijk[k] >= g->n[k])
                ijk[k] = g->n[k] - 1;
        }
        worst = fmax(worst, dense_distance_error(m, g, ijk, &exact));
        off_band += exact > BAND * g->h;
    }
    for (int tries = 0; near < samples && tries < 10000 * samples; tries++) {
        int ijk[3];
        for (int k = 0; k < 3; k++) {
            ijk[k] = (int)tu_uniform(&rng, 0, (float)g->n[k]);
            if (ijk[k] >= g->n[k])
                ijk[k] = g->n[k] - 1;
        }
        if (fabs(dense_at(g, ijk[0], ijk[1], ijk[2])) > (BAND + 4) * g->h)
            continue;
        near++;
        worst = fmax(worst, dense_distance_error(m, g, ijk, &exact));
        in_band += exact < BAND * g->h;
    }
    printf("%s --full %dx%dx%d: %d random voxels (%d off the band) and %d near the surface (%d in the band), largest "
           "distance error %.2e voxel\n",
           name, g->n[0], g->n[1], g->n[2], samples, off_band, near, in_band, worst);
    assert_true(off_band > samples / 4);
    assert_int_equal(near, samples);
    assert_true(in_band > samples / 4 && in_band < near);
    assert_true(worst <= 1e-4);
}

/* Converts `m` at `res`, narrow band and --full, and holds every stride-th
 * lattice point (in each axis) that the brute-force winding number calls
 * clearly inside (> 0.75) or outside (< 0.25) to the grid's sign, in the
 * band and off it. */
static void check_every_clear_point(const char *name, const mesh *m, int res, int stride)
{
    char off[512], full_name[256], flags[64];
    snprintf(full_name, sizeof full_name, "%s.off", name);
    tu_tmp(off, sizeof off, full_name);
    write_off(off, m);
    dense band = {0}, full = {0};
    snprintf(flags, sizeof flags, "--res %d", res);
    convert(off, name, flags, &band);
    snprintf(full_name, sizeof full_name, "%s_full", name);
    snprintf(flags, sizeof flags, "--res %d --full", res);
    convert(off, full_name, flags, &full);
    assert_memory_equal(band.n, full.n, sizeof band.n);
    long clear = 0, inside = 0, off_band = 0, wrong_band = 0, wrong_full = 0;
    for (int i = 0; i < band.n[0]; i += stride)
        for (int j = 0; j < band.n[1]; j += stride)
            for (int k = 0; k < band.n[2]; k += stride) {
                double p[3];
                dense_point(&band, i, j, k, p);
                const double w = winding(m, p);
                if (w > 0.25 && w < 0.75)
                    continue;
                const int in = w > 0.75;
                const float b = dense_at(&band, i, j, k);
                clear++;
                inside += in;
                off_band += fabs(b) >= BAND * band.h * (1 - 1e-6);
                wrong_band += !!signbit(b) != in;
                wrong_full += !!signbit(dense_at(&full, i, j, k)) != in;
            }
    printf("%s %d^3: %ld clear lattice points (%ld inside, %ld off the band), wrong sign: %ld narrow band, %ld "
           "--full\n",
           name, res, clear, inside, off_band, wrong_band, wrong_full);
    check_dense_distances(name, m, &full, 300);
    free(band.data);
    free(full.data);
    assert_true(inside > clear / 100 && off_band > clear / 4);
    assert_int_equal(wrong_band, 0);
    assert_int_equal(wrong_full, 0);
}

static void check_built_mesh(void (*make)(mesh *), const char *name, int res, int stride)
{
    mesh m = {0};
    make(&m);
    check_every_clear_point(name, &m, res, stride);
    mesh_free(&m);
}

static void test_sign_double_wall(void **state)
{
    (void)state;
    check_built_mesh(make_double_wall, "double_wall", 128, 3);
}

static void test_sign_nested_cups(void **state)
{
    (void)state;
    check_built_mesh(make_nested_cups, "nested_cups", 64, 2);
}

static void test_sign_slit_sphere(void **state)
{
    (void)state;
    check_built_mesh(make_slit_sphere, "slit_sphere", 96, 2);
}

static void test_sign_sheet_stack(void **state)
{
    (void)state;
    check_built_mesh(make_sheet_stack, "sheet_stack", 96, 1);
}

/* The bunny's base has holes; at 256^3, lattice points of a 48^3 lattice
 * over the padded box that lie within 10 voxels of a boundary edge (where
 * the winding number is between its interior's 1 and the outside's 0) and
 * off the band must have the sign of their brute-force winding number
 * wherever it is clear. */
static int edge_order(const void *a, const void *b)
{
    const int *x = a, *y = b;
    return x[0] != y[0] ? (x[0] > y[0]) - (x[0] < y[0]) : (x[1] > y[1]) - (x[1] < y[1]);
}

static void test_sign_bunny_base(void **state)
{
    (void)state;
    char in[1024];
    snprintf(in, sizeof in, "%s/stanford-bunny.obj", SDFT_MESH_DIR);
    mesh m = {0};
    assert_int_equal(read_obj(in, &m), 0);
    /* Boundary edges: used by one triangle (the file's vertices are shared). */
    int *edges = malloc(sizeof(int) * 6 * (size_t)m.nt), n = 0;
    for (int t = 0; t < m.nt; t++)
        for (int e = 0; e < 3; e++) {
            int a = m.t[3 * t + e], b = m.t[3 * t + (e + 1) % 3];
            edges[2 * n] = a < b ? a : b;
            edges[2 * n + 1] = a < b ? b : a;
            n++;
        }
    qsort(edges, (size_t)n, 2 * sizeof(int), edge_order);
    int boundary = 0;
    for (int i = 0; i < n;) {
        int j = i;
        while (j < n && !edge_order(&edges[2 * i], &edges[2 * j]))
            j++;
        if (j - i == 1) {
            edges[2 * boundary] = edges[2 * i];
            edges[2 * boundary + 1] = edges[2 * i + 1];
            boundary++;
        }
        i = j;
    }
    dense g = {0};
    convert(in, "bunny_base", "--res 256", &g);
    const double reach = 10 * g.h;
    long near = 0, clear = 0, wrong = 0;
    for (int a = 0; a < 48; a++)
        for (int b = 0; b < 48; b++)
            for (int c = 0; c < 48; c++) {
                const int ijk[3] = {(int)((a + 0.5) * g.n[0] / 48), (int)((b + 0.5) * g.n[1] / 48),
                                    (int)((c + 0.5) * g.n[2] / 48)};
                double p[3];
                dense_point(&g, ijk[0], ijk[1], ijk[2], p);
                const float value = dense_at(&g, ijk[0], ijk[1], ijk[2]);
                if (fabs(value) < BAND * g.h * (1 - 1e-6))
                    continue; /* in the band */
                int close = 0;
                for (int e = 0; e < boundary && !close; e++)
                    close = seg_dist2(p, &m.v[3 * edges[2 * e]], &m.v[3 * edges[2 * e + 1]]) < reach * reach;
                if (!close)
                    continue;
                near++;
                const double w = winding(&m, p);
                if (w > 0.25 && w < 0.75)
                    continue;
                clear++;
                wrong += (value < 0) != (w > 0.75);
            }
    printf("stanford-bunny 256^3: %d boundary edges, %ld lattice points off the band near them, %ld clear, %ld "
           "wrong sign\n",
           boundary, near, clear, wrong);
    free(edges);
    free(g.data);
    mesh_free(&m);
    assert_true(clear > 50);
    assert_int_equal(wrong, 0);
}

/* --full on the five shared meshes: exact distances at random voxels. */
/* The bounds on the winding number's gradient that the sign rests on
 * (convert/winding_sign.cpp: the exact field of the open edges, the bound
 * over a box edge by edge and by groups, the trapezoid rule along a step),
 * held to finite differences and changes of the brute-force winding number at
 * random points near and far from the open edges of the teapot and suzanne
 * (tests/mesh2sdf_bound_probe.cpp). */
static void test_gradient_bounds(void **state)
{
    (void)state;
    /* A sphere with one small round hole (radius 0.1): far away its open
     * edges' field is a dipole's, which the group bound must stay above. */
    char holed[512];
    tu_tmp(holed, sizeof holed, "holed_sphere.off");
    mesh m = {0};
    add_sphere_band(&m, 1.0, 0.1, 3.14159265358979323846, 24, 32, 0, NULL);
    write_off(holed, &m);
    mesh_free(&m);
    char paths[3][1024];
    snprintf(paths[0], sizeof paths[0], "%s/teapot.obj", SDFT_MESH_DIR);
    snprintf(paths[1], sizeof paths[1], "%s/suzanne.obj", SDFT_MESH_DIR);
    snprintf(paths[2], sizeof paths[2], "%s", holed);
    for (int i = 0; i < 3; i++) {
        char out[4096];
        int rc = tu_run(out, sizeof out, "%s '%s' 300", SDFT_BOUND_PROBE, paths[i]);
        printf("%s:\n%s", paths[i], out);
        assert_int_equal(rc, 0);
    }
}

static void test_full_distances(void **state)
{
    (void)state;
    const char *names[] = {"stanford-bunny", "spot", "teapot", "suzanne", "fandisk"};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        char in[1024], name[256];
        snprintf(in, sizeof in, "%s/%s.obj", SDFT_MESH_DIR, names[i]);
        snprintf(name, sizeof name, "%s_full", names[i]);
        mesh m = {0};
        assert_int_equal(read_obj(in, &m), 0);
        dense g = {0};
        convert(in, name, "--res 64 --full", &g);
        check_dense_distances(names[i], &m, &g, 300);
        free(g.data);
        mesh_free(&m);
    }
}

/* --full around thin triangles: a cube with four slivers beside it, two
 * thinner than mesh2sdf's threshold for a reliable normal (kThin, 1e-8 of
 * the longest edge: they count as their edges) and two just above it (their
 * normal from an ill-conditioned cross product), flat and tilted. Every
 * voxel of the box, with each level of vector instructions (--simd), must
 * equal the brute-force distance within 1e-4 voxel. The corners are exact
 * in float, so mesh2sdf and the brute force see the same triangles. */
static void test_full_thin_triangles(void **state)
{
    (void)state;
    mesh m = {0};
    make_cube(&m);
    mesh_add_slivers(&m);
    char off[512];
    tu_tmp(off, sizeof off, "thin.off");
    write_off(off, &m);
    /* The widest vector instructions the processor has (AVX-512 or AVX2),
     * AVX2 alone, and none. */
    const char *flags[3] = {"--res 40 --full", "--res 40 --full --simd avx2", "--res 40 --full --no-simd"};
    const char *names[3] = {"thin", "thin_avx2", "thin_scalar"};
    for (int f = 0; f < 3; f++) {
        dense g = {0};
        convert(off, names[f], flags[f], &g);
        double worst = 0;
        long near_sliver = 0, voxels = 0;
        for (int i = 0; i < g.n[0]; i++)
            for (int j = 0; j < g.n[1]; j++)
                for (int k = 0; k < g.n[2]; k++) {
                    double p[3], cube = INFINITY, sliver = INFINITY;
                    dense_point(&g, i, j, k, p);
                    for (int t = 0; t < m.nt; t++) {
                        const double d2 =
                            tri_dist2(p, &m.v[3 * m.t[3 * t]], &m.v[3 * m.t[3 * t + 1]], &m.v[3 * m.t[3 * t + 2]]);
                        if (t < 12)
                            cube = fmin(cube, d2);
                        else
                            sliver = fmin(sliver, d2);
                    }
                    near_sliver += sliver < cube;
                    voxels++;
                    worst = fmax(worst, fabs(fabs(dense_at(&g, i, j, k)) - sqrt(fmin(cube, sliver))) / g.h);
                }
        printf("thin triangles %s: %ld voxels (%ld nearest a sliver), largest distance error %.2e voxel\n", flags[f],
               voxels, near_sliver, worst);
        free(g.data);
        assert_true(near_sliver > voxels / 10);
        assert_true(worst <= 1e-4);
    }
    mesh_free(&m);
}

/* The progress bar on a terminal (script(1), from util-linux, gives
 * mesh2sdf one): its frames never go back, the stages come in order (the
 * library's names for them, told through sdft_mesh_stage_fn), and
 * 100% shows once, in the last frame, labelled "writing", after every
 * stage's work (once the sign pass of a big conversion ran at 100%). */
static void test_progress_bar(void **state)
{
    (void)state;
    static char out[65536];
    if (!tu_file_exists("/usr/bin/script") || tu_run(out, sizeof out, "script -qec true /dev/null") != 0) {
        print_message("skipped: no script(1) or no pseudo-terminal to give mesh2sdf a terminal\n");
        skip();
    }
    char in[1024], vdb[512], npy[512];
    snprintf(in, sizeof in, "%s/spot.obj", SDFT_MESH_DIR);
    tu_tmp(vdb, sizeof vdb, "progress.vdb");
    tu_tmp(npy, sizeof npy, "progress.npy");
    const char *stages[2][6] = {
        {"reading", "orienting", "exact distance, sign", "sign off the band", "writing", NULL},
        {"reading", "orienting", "exact distance, sign", "sign off the band", "dense distances", "writing"}};
    for (int full = 0; full < 2; full++) {
        const int rc = tu_run(out, sizeof out, "script -qec \"%s '%s' -o '%s' --npy '%s' --res 48%s\" /dev/null",
                              SDFT_MESH2SDF, in, vdb, npy, full ? " --full" : "");
        if (rc != 0)
            fail_msg("mesh2sdf under script failed: %s", out);
        int frames = 0, last = -1, stage = 0, hundreds = 0;
        char label[32] = "";
        for (const char *f = strstr(out, "\r["); f; f = strstr(f + 2, "\r[")) {
            const char *close = strchr(f, ']');
            int percent;
            char name[32] = "";
            if (!close || sscanf(close + 1, " %d%% %31[^\r]", &percent, name) < 1)
                fail_msg("a frame without a percent: %.60s", f + 1);
            for (size_t n = strlen(name); n > 0 && name[n - 1] == ' '; n--)
                name[n - 1] = '\0';
            if (strcmp(name, stages[full][stage]) != 0) {
                stage++;
                while (stage < 6 && stages[full][stage] && strcmp(name, stages[full][stage]) != 0 && stage < 2)
                    stage++; /* reading and orienting may pass too fast to be drawn */
                if (stage >= 6 || !stages[full][stage] || strcmp(name, stages[full][stage]) != 0)
                    fail_msg("stage '%s' out of order (after '%s')", name, label);
            }
            if (percent < last)
                fail_msg("the bar went back from %d%% to %d%% (%s)", last, percent, name);
            if (hundreds > 0)
                fail_msg("a frame after 100%%: %d%% %s", percent, name);
            if (percent == 100) {
                hundreds++;
                if (strcmp(name, "writing") != 0)
                    fail_msg("100%% during '%s'", name);
            }
            last = percent;
            snprintf(label, sizeof label, "%s", name);
            frames++;
        }
        printf("progress bar%s: %d frames, last %d%% %s\n", full ? " --full" : "", frames, last, label);
        assert_true(frames >= 10);
        assert_int_equal(hundreds, 1);
        assert_string_equal(label, "writing");
        assert_non_null(stages[full][stage]);
        assert_string_equal(stages[full][stage], "writing");
    }
}

static void test_render_round_trip(void **state)
{
    (void)state;
    char out[16384];
    tu_run(out, sizeof out, "%s render --help", SDFT_CLI);
    if (!strstr(out, "--grid")) {
        print_message("skipped: `sdftrace render --help` has no --grid option yet\n");
        skip();
    }
    char in[1024], nvdb[512], vdb[512], exr[512];
    snprintf(in, sizeof in, "%s/spot.obj", SDFT_MESH_DIR);
    tu_tmp(vdb, sizeof vdb, "spot_rt.vdb");
    tu_tmp(nvdb, sizeof nvdb, "spot_rt.nvdb");
    tu_tmp(exr, sizeof exr, "spot_rt.exr");
    int rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --nvdb '%s' --res 64 --quiet", SDFT_MESH2SDF, in, vdb, nvdb);
    if (rc != 0)
        fail_msg("mesh2sdf failed: %s", out);
    rc = tu_run(out, sizeof out, "%s render --grid '%s' -o '%s' --width 64 --height 64 --json", SDFT_CLI, nvdb, exr);
    if (rc != 0)
        fail_msg("sdftrace render --grid failed: %s", out);
    const char *hf = strstr(out, "\"hit_fraction\":");
    assert_non_null(hf);
    double hit = strtod(hf + strlen("\"hit_fraction\":"), NULL);
    printf("spot round trip: hit fraction %.3f\n", hit);
    assert_true(hit > 0.05 && hit < 0.95);
}

/* ----------------------------------------------------- health, help */

static void test_health_line(void **state)
{
    (void)state;
    char obj[512], vdb[512], out[8192];
    tu_tmp(obj, sizeof obj, "open_cube.obj");
    tu_tmp(vdb, sizeof vdb, "open_cube.vdb");
    write_cube_obj(obj, 1, 2); /* one quad missing, two degenerate faces */
    int rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --res 32 --sign flood", SDFT_MESH2SDF, obj, vdb);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(out, "11 vertices, 7 faces (10 triangles), 4 boundary edges, 0 non-manifold edges, "
                                "2 degenerate faces skipped"));
    assert_non_null(strstr(out, "warning: the mesh is not closed"));
    assert_non_null(strstr(out, "sign flood"));
    /* --quiet: nothing but the warning. */
    rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --res 32 --quiet", SDFT_MESH2SDF, obj, vdb);
    assert_int_equal(rc, 0);
    assert_string_equal(out, "");
}

static void test_help(void **state)
{
    (void)state;
    char out[16384];
    assert_int_equal(tu_run(out, sizeof out, "%s --help", SDFT_MESH2SDF), 0);
    const char *flags[] = {"-o",      "--nvdb",       "--npy",     "--res",     "--voxel-size", "--band",
                           "--full",  "--padding",    "--sign",    "--fp16",    "--name",       "--threads",
                           "--quiet", "--check-sign", "--samples", "--no-simd", "--simd"};
    for (size_t i = 0; i < sizeof flags / sizeof *flags; i++)
        if (!strstr(out, flags[i]))
            fail_msg("--help does not list %s", flags[i]);
    assert_non_null(strstr(out, "default: 256"));
    assert_non_null(strstr(out, "4096"));
    char want[64];
    snprintf(want, sizeof want, "mesh2sdf %s\n", SDFT_VERSION_STRING);
    assert_int_equal(tu_run(out, sizeof out, "%s --version", SDFT_MESH2SDF), 0);
    assert_string_equal(out, want);
}

/* ---------------------------------------------------------- bad input */

/* No file at `path`, nor a temporary file left beside it. */
static void assert_no_output(const char *path)
{
    assert_false(tu_file_exists(path));
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    tu_assert_no_temporaries(SDFT_TEST_TMP, base);
}

/* mesh2sdf ARGS must fail with exactly one line starting "mesh2sdf: ". */
static void expect_failure(const char *args, const char *expect)
{
    char out[8192];
    int rc = tu_run(out, sizeof out, "%s %s", SDFT_MESH2SDF, args);
    if (rc == 0)
        fail_msg("mesh2sdf %s succeeded", args);
    size_t len = strlen(out);
    int lines = 0;
    for (size_t i = 0; i < len; i++)
        lines += out[i] == '\n';
    if (lines != 1 || strncmp(out, "mesh2sdf: ", 10) != 0)
        fail_msg("mesh2sdf %s: want one 'mesh2sdf: ' line, got: %s", args, out);
    if (expect && !strstr(out, expect))
        fail_msg("mesh2sdf %s: message lacks '%s': %s", args, expect, out);
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* A mesh file NAME in the test folder holding `text`: mesh2sdf on it must
 * fail as expect_failure says and leave nothing at out_vdb. */
static void expect_text_failure(const char *name, const char *text, const char *expect, const char *out_vdb)
{
    char path[512], args[2048];
    tu_tmp(path, sizeof path, name);
    write_text(path, text);
    snprintf(args, sizeof args, "'%s' -o '%s'", path, out_vdb);
    expect_failure(args, expect);
    assert_no_output(out_vdb);
}

/* SIGTERM and SIGINT in the middle of a conversion: the run stops at the
 * library's next progress report, says so in one line, exits with 128 +
 * the signal, and leaves its folder as it found it (no output, no
 * temporary file). The signal is sent once the outputs are reserved (their
 * temporary files are there), so the handler is in place. */
static void test_interrupted(void **state)
{
    (void)state;
    static char out[16384];
    char dir[512], in[1024];
    snprintf(in, sizeof in, "%s/stanford-bunny.obj", SDFT_MESH_DIR);
    const char *signals[2] = {"TERM", "INT"};
    const int status[2] = {143, 130};
    for (int s = 0; s < 2; s++) {
        tu_tmp(dir, sizeof dir, s ? "interrupted-int" : "interrupted-term");
        tu_run(out, sizeof out, "rm -rf '%s' && mkdir -p '%s'", dir, dir);
        const int rc = tu_run(out, sizeof out,
                              "cd '%s' && { %s '%s' -o b.vdb --npy b.npy --res 700 --full --quiet & pid=$!; "
                              "n=0; until ls -A | grep -q tmp || [ $n -ge 1500 ]; do sleep 0.02; n=$((n+1)); done; "
                              "sleep 0.3; kill -%s $pid; wait $pid; "
                              "echo \"exit $?\"; ls -A; }",
                              dir, SDFT_MESH2SDF, in, signals[s]);
        assert_int_equal(rc, 0);
        char want[64];
        snprintf(want, sizeof want, "exit %d", status[s]);
        if (!strstr(out, want))
            fail_msg("SIG%s: want '%s', got: %s", signals[s], want, out);
        snprintf(want, sizeof want, "interrupted by SIG%s", signals[s]);
        assert_non_null(strstr(out, want));
        /* The exit line is the last: ls -A printed nothing after it. */
        const char *tail = strstr(out, "exit ");
        assert_int_equal(tu_lines(tail), 1);
    }
}

static void test_bad_input(void **state)
{
    (void)state;
    char cube[512], out_vdb[512], args[4096], path[512], npy[512];
    tu_tmp(cube, sizeof cube, "bad_cube.obj");
    write_cube_obj(cube, 0, 0);
    tu_tmp(out_vdb, sizeof out_vdb, "bad_out.vdb");
    tu_tmp(npy, sizeof npy, "bad_out.npy");
    remove(out_vdb);

    /* missing file */
    snprintf(args, sizeof args, "'%s/no_such_mesh.obj' -o '%s'", SDFT_TEST_TMP, out_vdb);
    expect_failure(args, "cannot open");
    assert_no_output(out_vdb);

    /* unknown extension */
    expect_text_failure("mesh.xyz", "v 0 0 0\n", "unknown mesh extension", out_vdb);

    /* unreadable mesh: a PLY that is not one */
    expect_text_failure("garbage.ply", "this is not a ply file\n\x01\x02\x03", NULL, out_vdb);

    /* empty mesh: vertices, no faces; and an empty file */
    expect_text_failure("nofaces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces", out_vdb);
    expect_text_failure("empty.off", "", NULL, out_vdb);

    /* NaN and Inf coordinates: as text in an OBJ, as floats in a binary PLY */
    const char *bad_obj[] = {"nan 0 0", "0 inf 0", "0 0 1e999"};
    for (size_t i = 0; i < 3; i++) {
        char text[256];
        snprintf(text, sizeof text, "v %s\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 2 3 4\nf 1 4 2\n",
                 bad_obj[i]);
        tu_tmp(path, sizeof path, "nonfinite.obj");
        write_text(path, text);
        snprintf(args, sizeof args, "'%s' -o '%s'", path, out_vdb);
        expect_failure(args, "non-finite");
        assert_no_output(out_vdb);
    }
    /* ... while numbers written other ways still read: a leading '+', a
     * signed zero, exponents, CRLF line ends; a number with trailing
     * characters is malformed */
    tu_tmp(path, sizeof path, "spelled.obj");
    write_text(path, "v +0 -0.0 0e0\r\nv 1 0 0\r\nv 0 +1.0 0\r\nv 0 0 1E+0\r\n"
                     "f 1 3 2\r\nf 1 2 4\r\nf 2 3 4\r\nf 1 4 3\r\n");
    {
        char out[8192];
        const int rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --res 16 --quiet", SDFT_MESH2SDF, path, out_vdb);
        if (rc != 0)
            fail_msg("mesh2sdf on %s: %s", path, out);
        remove(out_vdb);
    }
    expect_text_failure("malformed.obj", "v 0 0 0\nv 1.0x 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n",
                        "malformed coordinate (line 2)", out_vdb);
    mesh m = {0};
    make_cube(&m);
    const float poison[2] = {NAN, INFINITY};
    for (int i = 0; i < 2; i++) {
        tu_tmp(path, sizeof path, "nonfinite.ply");
        write_binary_ply(path, &m, poison[i]);
        snprintf(args, sizeof args, "'%s' -o '%s'", path, out_vdb);
        expect_failure(args, "non-finite");
        assert_no_output(out_vdb);
    }
    /* ... and as text in OFF, ASCII PLY and ASCII STL, where OpenMesh's
     * readers would report no faces or go on with a wrong vertex */
    const double saved = m.v[0];
    for (int i = 0; i < 2; i++) {
        m.v[0] = poison[i];
        tu_tmp(path, sizeof path, "nonfinite.off");
        write_off(path, &m);
        snprintf(args, sizeof args, "'%s' -o '%s'", path, out_vdb);
        expect_failure(args, "non-finite");
        assert_no_output(out_vdb);
        tu_tmp(path, sizeof path, "nonfinite_ascii.ply");
        write_ply(path, &m);
        snprintf(args, sizeof args, "'%s' -o '%s'", path, out_vdb);
        expect_failure(args, "non-finite");
        assert_no_output(out_vdb);
        char text[512];
        snprintf(text, sizeof text,
                 "solid t\nfacet normal 0 0 1\nouter loop\nvertex %s 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
                 "endfacet\nendsolid t\n",
                 i == 0 ? "nan" : "inf");
        tu_tmp(path, sizeof path, "nonfinite_ascii.stl");
        write_text(path, text);
        snprintf(args, sizeof args, "'%s' -o '%s'", path, out_vdb);
        expect_failure(args, "non-finite");
        assert_no_output(out_vdb);
    }
    m.v[0] = saved;
    mesh_free(&m);

    /* every triangle degenerate / zero-size bounding box */
    expect_text_failure("point.obj", "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n", "no non-degenerate triangles", out_vdb);
    /* Headers claiming 2^40 vertices: refused before anything is allocated
     * (OpenMesh's readers reserve what a header says). */
    expect_text_failure("huge.ply",
                        "ply\nformat ascii 1.0\nelement vertex 1099511627776\nproperty float x\nproperty float y\n"
                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                        "mesh header claims 1099511627777 elements", out_vdb);
    expect_text_failure("huge.off", "OFF\n1099511627776 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                        "mesh header claims 1099511627777 elements", out_vdb);

    /* --res out of range, too small for the padding; --voxel-size <= 0, NaN */
    const char *bad_flags[][2] = {{"--res 0", "--res must be"},
                                  {"--res 4097", "--res must be"},
                                  {"--res abc", "--res must be"},
                                  {"--res 6", "leaves no room"},
                                  {"--voxel-size 0", "--voxel-size must be"},
                                  {"--voxel-size -1", "--voxel-size must be"},
                                  {"--voxel-size nan", "--voxel-size must be"},
                                  {"--voxel-size 0.0001", "above the limit"},
                                  {"--res 64 --voxel-size 0.1", "not both"},
                                  {"--band 0", "--band must be"},
                                  {"--band ' 2'", "--band must be"}, /* strict: no blanks, as sdftrace */
                                  {"--res '32 '", "--res must be"},
                                  {"--sign maybe", "--sign must be"},
                                  {"--simd sse", "--simd must be"},
                                  {"--threads -2", "--threads must be"},
                                  {"--bogus", "unknown option"},
                                  {"--res", "needs a value"}};
    for (size_t i = 0; i < sizeof bad_flags / sizeof *bad_flags; i++) {
        snprintf(args, sizeof args, "'%s' -o '%s' %s", cube, out_vdb, bad_flags[i][0]);
        expect_failure(args, bad_flags[i][1]);
        assert_no_output(out_vdb);
    }
    snprintf(args, sizeof args, "'%s'", cube);
    expect_failure(args, "no output");

    /* unwritable outputs: a missing folder, a folder as the file; a bad
     * --npy destination must not leave the .vdb either */
    snprintf(args, sizeof args, "'%s' -o '%s/no/such/dir/out.vdb'", cube, SDFT_TEST_TMP);
    expect_failure(args, "cannot write");
    snprintf(args, sizeof args, "'%s' -o '%s'", cube, SDFT_TEST_TMP);
    expect_failure(args, "is a folder");
    snprintf(args, sizeof args, "'%s' -o '%s' --npy '%s/no/such/dir/out.npy'", cube, out_vdb, SDFT_TEST_TMP);
    expect_failure(args, "cannot write");
    assert_no_output(out_vdb);

    /* and the same command with good paths works and writes all four, with
     * the mode the umask gives (027 here: 0640, not mkstemp's 0600) */
    char json[512], nvdb[512];
    tu_tmp(json, sizeof json, "bad_out.json");
    tu_tmp(nvdb, sizeof nvdb, "bad_out.nvdb");
    snprintf(args, sizeof args, "umask 027 && %s '%s' -o '%s' --nvdb '%s' --npy '%s' --res 32 --quiet", SDFT_MESH2SDF,
             cube, out_vdb, nvdb, npy);
    assert_int_equal(tu_run(NULL, 0, "%s", args), 0);
    const char *written[] = {out_vdb, nvdb, npy, json};
    for (int i = 0; i < 4; i++) {
        assert_true(tu_file_exists(written[i]));
        assert_int_equal(tu_file_mode(written[i]), 0640);
    }
}

/* The .vdb is a level set OpenVDB's own tools read; the .nvdb validates. */
static void test_formats(void **state)
{
    (void)state;
    char in[1024], vdb[512], nvdb[512], out[16384];
    snprintf(in, sizeof in, "%s/suzanne.obj", SDFT_MESH_DIR);
    tu_tmp(vdb, sizeof vdb, "suzanne_fmt.vdb");
    tu_tmp(nvdb, sizeof nvdb, "suzanne_fmt.nvdb");
    int rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --nvdb '%s' --fp16 --name monkey --res 64 --quiet", SDFT_MESH2SDF,
                    in, vdb, nvdb);
    if (rc != 0)
        fail_msg("mesh2sdf failed: %s", out);
    if (tu_run(out, sizeof out, "vdb_print -l -m '%s'", vdb) == 0) {
        assert_non_null(strstr(out, "monkey"));
        assert_non_null(strstr(out, "level set"));
        assert_non_null(strstr(out, "mesh2sdf_sign: winding"));
        assert_non_null(strstr(out, "suzanne.obj"));
    }
    if (tu_run(out, sizeof out, "command -v nanovdb_validate") == 0) {
        rc = tu_run(out, sizeof out, "nanovdb_validate '%s'", nvdb);
        if (rc != 0)
            fail_msg("nanovdb_validate: %s", out);
    }
    if (tu_run(out, sizeof out, "command -v nanovdb_print") == 0) {
        assert_int_equal(tu_run(out, sizeof out, "nanovdb_print '%s'", nvdb), 0);
        assert_non_null(strstr(out, "monkey"));
        assert_non_null(strstr(out, "Float16")); /* nanovdb_print's name for Fp16 */
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_help),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_health_line),
        cmocka_unit_test(test_cube_distances),
        cmocka_unit_test(test_icosphere_distances),
        cmocka_unit_test(test_band_never_overstates_distance),
        cmocka_unit_test(test_formats),
        cmocka_unit_test(test_sign_spot),
        cmocka_unit_test(test_sign_suzanne),
        cmocka_unit_test(test_sign_teapot),
        cmocka_unit_test(test_sign_fandisk),
        cmocka_unit_test(test_sign_bunny),
        cmocka_unit_test(test_sign_double_wall),
        cmocka_unit_test(test_sign_nested_cups),
        cmocka_unit_test(test_sign_slit_sphere),
        cmocka_unit_test(test_sign_sheet_stack),
        cmocka_unit_test(test_sign_bunny_base),
        cmocka_unit_test(test_gradient_bounds),
        cmocka_unit_test(test_full_distances),
        cmocka_unit_test(test_full_thin_triangles),
        cmocka_unit_test(test_render_round_trip),
        cmocka_unit_test(test_progress_bar),
        cmocka_unit_test(test_interrupted),
    };
    return cmocka_run_group_tests_name("mesh2sdf", tests, NULL, NULL);
}
