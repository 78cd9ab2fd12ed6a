/* mesh2sdf on the faults real files have (the corpus tests/data/real/,
 * README.md there, and files made here): faces a reader cannot take are
 * counted, a warning without --strict and an error with it; a PLY header's
 * free text is read as a comment; a scene whose importer reads past its
 * data is refused; a mirrored node keeps its outside out without orienting;
 * --check-sign judges by the orientation it names; two copies of a model
 * whose open patch is oriented differently give one grid; a batch rerun
 * with other options converts again; a killed run's temporary file is
 * removed by the next run and a running one's is not; and the messages:
 * a folder as a mesh, --json on failure, --help's usage, the ambiguous
 * voxels among the active ones. Grids are held to the exact distance to
 * boxes, signs to brute-force winding numbers, counts to the files' own. */
#define _GNU_SOURCE /* kill, fork, utimes, strdup */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "mesh_support.h"
#include "testutil.h"

#define BAND 3.0

/* ---------------------------------------------------------------- helpers */

/* Writes `text` to `path`. */
static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    assert_int_equal(fclose(f), 0);
}

/* A unit cube and a tetrahedron, faces outward. */
#define CUBE_OBJ                                                                                                       \
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"                                         \
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"
#define TET_OBJ "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"

/* An empty test folder `name` into dir, and tet.obj in it (TET_OBJ) into
 * tet. */
static void fresh_folder(const char *name, char *dir, size_t dir_len, char *tet, size_t tet_len)
{
    tu_tmp(dir, dir_len, name);
    assert_int_equal(tu_run(NULL, 0, "rm -rf '%s' && mkdir -p '%s'", dir, dir), 0);
    snprintf(tet, tet_len, "%s/tet.obj", dir);
    write_text(tet, TET_OBJ);
}

/* A file of the corpus. */
static const char *real(char *buf, size_t len, const char *name)
{
    snprintf(buf, len, "%s/tests/data/real/%s", SDFT_SOURCE_DIR, name);
    return buf;
}

static int count_of(const char *text, const char *what)
{
    int n = 0;
    for (const char *at = text; (at = strstr(at, what)) != NULL; at += strlen(what))
        n++;
    return n;
}

/* The exact signed distance to the box [lo, hi]. */
static double box_sdf(const double lo[3], const double hi[3], const double *p)
{
    double out = 0, in = -INFINITY;
    for (int k = 0; k < 3; k++) {
        const double d = fmax(lo[k] - p[k], p[k] - hi[k]);
        out += d > 0 ? d * d : 0;
        in = fmax(in, d);
    }
    return out > 0 ? sqrt(out) : in;
}

/* Converts `in` with `flags` into NAME.npy and holds every voxel to the
 * exact distance to the union of `n` disjoint boxes: within 1e-5 in the
 * band, and the sign of every voxel a voxel or more from their surfaces. */
static void assert_boxes(const char *in, const char *name, const char *flags, const double (*lo)[3],
                         const double (*hi)[3], int n)
{
    dense g;
    convert(in, name, flags, &g);
    long band = 0;
    for (int i = 0; i < g.n[0]; i++)
        for (int j = 0; j < g.n[1]; j++)
            for (int k = 0; k < g.n[2]; k++) {
                double p[3], d = INFINITY;
                dense_point(&g, i, j, k, p);
                for (int b = 0; b < n; b++)
                    d = fmin(d, box_sdf(lo[b], hi[b], p));
                const float v = dense_at(&g, i, j, k);
                if (fabs(v) < BAND * g.h * (1 - 1e-6)) {
                    band++;
                    if (fabs(v - d) > 1e-5)
                        fail_msg("%s: voxel (%d,%d,%d) is %g, the boxes' distance %g", in, i, j, k, v, d);
                } else if (fabs(d) > g.h && (v < 0) != (d < 0)) {
                    fail_msg("%s: voxel (%d,%d,%d) is %g off the band, the boxes' distance %g", in, i, j, k, v, d);
                }
            }
    assert_true(band > 0);
    free(g.data);
}

static const double kUnitLo[1][3] = {{0, 0, 0}}, kUnitHi[1][3] = {{1, 1, 1}};

/* Converts `in` with `flags` into NAME.npy and holds every voxel to the
 * brute-force signed distance of `truth` (mesh_sdf: the distance to its
 * triangles, negative where their winding number exceeds 1/2): within
 * 1e-5 in the band, and the sign everywhere, where the winding number is
 * clearly in or out (|w - 1/2| > 1/4). */
static void assert_mesh_truth(const char *in, const char *name, const char *flags, const mesh *truth)
{
    dense g;
    convert(in, name, flags, &g);
    long band = 0;
    for (int i = 0; i < g.n[0]; i++)
        for (int j = 0; j < g.n[1]; j++)
            for (int k = 0; k < g.n[2]; k++) {
                double p[3];
                dense_point(&g, i, j, k, p);
                const double w = winding(truth, p);
                if (!(fabs(w - 0.5) > 0.25))
                    continue;
                const double d = mesh_distance(truth, p) * (w > 0.5 ? -1 : 1);
                const float v = dense_at(&g, i, j, k);
                if (fabs(v) < BAND * g.h * (1 - 1e-6)) {
                    band++;
                    if (fabs(v - d) > 1e-5)
                        fail_msg("%s: voxel (%d,%d,%d) is %g, the truth %g", in, i, j, k, v, d);
                } else if ((v < 0) != (d < 0)) {
                    fail_msg("%s: voxel (%d,%d,%d) is %g off the band, the truth %g", in, i, j, k, v, d);
                }
            }
    assert_true(band > 0);
    free(g.data);
}

/* mesh2sdf on `in` with `flags` must fail: one line naming `in` and
 * saying `expect`, and no output. */
static void expect_refused(const char *in, const char *flags, const char *expect)
{
    char vdb[512], out[8192];
    tu_tmp(vdb, sizeof vdb, "refused.vdb");
    remove(vdb);
    const int rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --res 16 %s", SDFT_MESH2SDF, in, vdb, flags);
    if (rc != 1 || tu_lines(out) != 1 || strncmp(out, "mesh2sdf: ", 10) != 0 || !strstr(out, in) ||
        !strstr(out, expect))
        fail_msg("%s %s: want one line naming it and saying '%s', got (%d): %s", in, flags, expect, rc, out);
    assert_false(tu_file_exists(vdb));
    tu_assert_no_temporaries(SDFT_TEST_TMP, "refused.vdb");
}

/* mesh2sdf on `in` must convert and warn, on stderr, `warning`. */
static void expect_warning(const char *in, const char *warning)
{
    char vdb[512], out[8192];
    const int rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --res 16 --quiet", SDFT_MESH2SDF, in,
                          tu_tmp(vdb, sizeof vdb, "warned.vdb"));
    if (rc != 0 || !strstr(out, "mesh2sdf: warning: ") || !strstr(out, warning))
        fail_msg("%s: want a warning saying '%s', got (%d): %s", in, warning, rc, out);
}

/* ------------------------------------------------------ faces left out */

/* Corpus file `name`, of the unit cube and `left` faces its reader cannot
 * take: they are counted (`faces` taken), warned of, refused with --strict,
 * and the good faces give the cube's exact grid. */
static void expect_faces_left_out(const char *name, int left, int faces)
{
    char in[1024], vdb[512], out[8192], said[64];
    real(in, sizeof in, name);
    snprintf(said, sizeof said, "%d faces of the file were left out", left);
    expect_warning(in, said);
    expect_refused(in, "--strict", said);
    assert_int_equal(tu_run(out, sizeof out, "%s '%s' -o '%s' --res 16 --json 2>/dev/null", SDFT_MESH2SDF, in,
                            tu_tmp(vdb, sizeof vdb, "left_out.vdb")),
                     0);
    assert_int_equal((int)json_number(out, "\"skipped_faces\"", 0), left);
    assert_int_equal((int)json_number(out, "\"faces\"", 0), faces);
    assert_boxes(in, "left_out", "--res 24", kUnitLo, kUnitHi, 1);
}

/* An OBJ with five faces OpenMesh's reader drops without a word (a corner
 * past the vertices, a corner 0, a negative corner before the first, a
 * repeated corner, two corners) beside the cube's twelve. */
static void test_obj_faces_left_out(void **state)
{
    (void)state;
    expect_faces_left_out("bad_indices.obj", 5, 12);
}

/* A glTF whose index buffer has two triangles past its eight vertices
 * beside the cube's twelve: assimp's importer drops them with a log line
 * that has no count. */
static void test_gltf_faces_left_out(void **state)
{
    (void)state;
    expect_faces_left_out("bad_indices.gltf", 2, 12);
}

/* PLY: a face with a corner out of range and a strip triangle on one are
 * left out and counted; the strip's zero-area stitches are no faces of the
 * file and are not. */
static void test_ply_faces_left_out(void **state)
{
    (void)state;
    char path[512], out[8192], vdb[512];
    tu_tmp(path, sizeof path, "ply_left_out.ply");
    write_text(path, "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                     "element face 7\nproperty list uchar int vertex_indices\nelement tristrips 1\n"
                     "property list int int vertex_indices\nend_header\n"
                     "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                     "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n3 0 1 8\n"
                     /* a strip: 0 1 2 (twice, a stitch), 9 (out of range: the two
                      * triangles on it), then a fresh strip 4 5 6 */
                     "9 0 1 2 2 9 -1 4 5 6\n");
    assert_int_equal(tu_run(out, sizeof out, "%s '%s' -o '%s' --res 16 --json --orient none 2>/dev/null", SDFT_MESH2SDF,
                            path, tu_tmp(vdb, sizeof vdb, "ply.vdb")),
                     0);
    /* the face 0 1 8, and the strip's triangle 2 2 9 (its 2 1 2 is a
     * stitch, no face) */
    assert_int_equal((int)json_number(out, "\"skipped_faces\"", 0), 2);
    /* six quads, the strip's 0 1 2 and 4 5 6 */
    assert_int_equal((int)json_number(out, "\"faces\"", 0), 8);
}

/* A PLY header with a line of free text (an old exporter's, without the
 * comment keyword): read as a comment, said, the file's cube converted;
 * refused with --strict. */
static void test_ply_free_text(void **state)
{
    (void)state;
    char in[1024];
    real(in, sizeof in, "free_text_header.ply");
    expect_warning(in, "line 3, 'Created by an old exporter");
    expect_refused(in, "--strict", "is no PLY keyword");
    assert_boxes(in, "free_text", "--res 24", kUnitLo, kUnitHi, 1);
}

/* A Collada file whose accessor claims more points than its array holds:
 * assimp 5.2 reads past the array, into whatever memory holds. Refused
 * with one line, never a grid of garbage: the bytes past the array read as
 * coordinates of absurd size, or (where the allocator fills fresh memory)
 * the two reads of the file differ. */
static void test_scene_past_its_data(void **state)
{
    (void)state;
    char in[1024], out[8192];
    real(in, sizeof in, "past_array_end.dae");
    expect_refused(in, "", "mesh");
    tu_run(out, sizeof out, "%s '%s' -o /dev/null --res 16", SDFT_MESH2SDF, in);
    if (!strstr(out, "of absurd size") && !strstr(out, "two different scenes"))
        fail_msg("want the garbage named: %s", out);
}

/* ------------------------------------------------------------ mirrored */

/* A glTF node mirrored by its scale reverses its faces' winding (the
 * format says so): converted with --orient none, both cubes are solid. */
static void test_mirrored_node(void **state)
{
    (void)state;
    char in[1024];
    real(in, sizeof in, "mirrored.gltf");
    const double lo[2][3] = {{0, 0, 0}, {-3, 0, 0}}, hi[2][3] = {{1, 1, 1}, {-2, 1, 1}};
    assert_boxes(in, "mirrored_none", "--res 40 --orient none", lo, hi, 2);
    assert_boxes(in, "mirrored_outward", "--res 40", lo, hi, 2);
}

/* ---------------------------------------------------------- check-sign */

/* The --check-sign rows of `out` (--json): grid g's clear and wrong. */
static void check_row(const char *out, int g, double *clear, double *wrong)
{
    const char *at = out;
    for (int i = 0; i <= g; i++) {
        at = strstr(at, "{\"grid\": ");
        assert_non_null(at);
        at++;
    }
    *clear = json_number(at, "\"clear\"", 0);
    *wrong = json_number(at, "\"wrong\"", 0);
}

/* An inside-out cow (spot's faces reversed) converted both ways: outward
 * (the default) gets it right, --orient none gets no inside at all.
 * --check-sign judges by the orientation its --orient gives and names it:
 * by default the outward grid has no wrong point and the other is wrong at
 * every clear inside point (their share, against brute-force winding
 * numbers of spot as it was); with --orient none, the other way round. */
static void test_check_sign_orientation(void **state)
{
    (void)state;
    char in[1024], off[512], a[512], b[512], out[16384];
    snprintf(in, sizeof in, "%s/spot.obj", SDFT_MESH_DIR);
    mesh m = {0};
    assert_int_equal(read_obj(in, &m), 0);
    for (int t = 0; t < m.nt; t++) {
        const int swap = m.t[3 * t + 1];
        m.t[3 * t + 1] = m.t[3 * t + 2];
        m.t[3 * t + 2] = swap;
    }
    tu_tmp(off, sizeof off, "spot_inside_out.off");
    write_off(off, &m);
    tu_tmp(a, sizeof a, "spot_io_outward.vdb");
    tu_tmp(b, sizeof b, "spot_io_none.vdb");
    assert_int_equal(tu_run(out, sizeof out, "%s '%s' -o '%s' --res 48 --quiet", SDFT_MESH2SDF, off, a), 0);
    assert_int_equal(tu_run(out, sizeof out, "%s '%s' -o '%s' --res 48 --quiet --orient none", SDFT_MESH2SDF, off, b),
                     0);
    assert_int_equal(tu_run(out, sizeof out, "%s '%s' --check-sign '%s' --check-sign '%s' --check-points 2000",
                            SDFT_MESH2SDF, off, a, b),
                     0);
    assert_int_equal(count_of(out, "orient=outward"), 2);
    assert_int_equal(tu_run(out, sizeof out, "%s '%s' --check-sign '%s' --check-sign '%s' --check-points 2000 --json",
                            SDFT_MESH2SDF, off, a, b),
                     0);
    double clear_a, wrong_a, clear_b, wrong_b;
    check_row(out, 0, &clear_a, &wrong_a);
    check_row(out, 1, &clear_b, &wrong_b);
    assert_true(clear_a > 1000);
    if (wrong_a != 0)
        fail_msg("the outward grid of an inside-out mesh is judged wrong at %g of %g points", wrong_a, clear_a);
    /* The share of the grown box inside spot, by brute force. */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < m.nv; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m.v[3 * v + k]);
            hi[k] = fmax(hi[k], m.v[3 * v + k]);
        }
    mesh right = m;
    right.t = malloc(sizeof(int) * 3 * (size_t)m.nt);
    for (int t = 0; t < m.nt; t++) {
        right.t[3 * t] = m.t[3 * t];
        right.t[3 * t + 1] = m.t[3 * t + 2];
        right.t[3 * t + 2] = m.t[3 * t + 1];
    }
    tu_rng rng = tu_rng_seed(40);
    int inside = 0;
    const int samples = 1500;
    for (int s = 0; s < samples; s++) {
        double p[3];
        for (int k = 0; k < 3; k++) {
            const double grow = 0.05 * (hi[k] - lo[k]);
            p[k] = tu_uniform(&rng, (float)(lo[k] - grow), (float)(hi[k] + grow));
        }
        inside += winding(&right, p) > 0.5;
    }
    free(right.t);
    const double share = (double)inside / samples;
    if (!(fabs(wrong_b / clear_b - share) < 0.05))
        fail_msg("the --orient none grid of an inside-out mesh: wrong at %g of %g points, want the inside's share %g",
                 wrong_b, clear_b, share);
    /* Judged by the file's own faces, the other way round. */
    assert_int_equal(tu_run(out, sizeof out,
                            "%s '%s' --check-sign '%s' --check-sign '%s' --check-points 2000 --json --orient none",
                            SDFT_MESH2SDF, off, a, b),
                     0);
    assert_non_null(strstr(out, "\"orient\": \"none\""));
    check_row(out, 0, &clear_a, &wrong_a);
    check_row(out, 1, &clear_b, &wrong_b);
    assert_true(wrong_a / clear_a > share - 0.05);
    assert_true(wrong_b == 0);
    mesh_free(&m);
}

/* No false alarm on a scene with a mirrored part, nor on an open model. */
static void test_check_sign_no_false_alarm(void **state)
{
    (void)state;
    const char *files[] = {"mirrored.gltf", "cup_lid.off", "cup_lid.stl"};
    for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
        char in[1024], vdb[512], out[8192];
        real(in, sizeof in, files[i]);
        tu_tmp(vdb, sizeof vdb, "no_alarm.vdb");
        assert_int_equal(tu_run(out, sizeof out, "%s '%s' -o '%s' --res 32 --quiet", SDFT_MESH2SDF, in, vdb), 0);
        assert_int_equal(
            tu_run(out, sizeof out, "%s '%s' --check-sign '%s' --check-points 3000 --json", SDFT_MESH2SDF, in, vdb), 0);
        double clear, wrong;
        check_row(out, 0, &clear, &wrong);
        if (!(clear > 1000 && wrong == 0))
            fail_msg("%s: judged wrong at %g of %g points: %s", files[i], wrong, clear, out);
    }
}

/* ------------------------------------------------------- open patches */

/* A cup and its lid, the lid a patch of its own (its edges meet none of
 * the cup's) and flat, so with no outside of its own: the OFF copy has it
 * outward, the STL copy inward. The cup's winding number says which side
 * of the lid is out: both copies give the cube's grid, byte for byte. */
static void test_two_copies_one_grid(void **state)
{
    (void)state;
    char off[1024], stl[1024], a[512], b[512];
    real(off, sizeof off, "cup_lid.off");
    real(stl, sizeof stl, "cup_lid.stl");
    /* The truth: the cup, and the lid facing up. */
    mesh m = {0};
    for (int v = 0; v < 8; v++)
        mesh_vertex(&m, v & 1 ? 1 : 0, v & 2 ? 1 : 0, v & 4 ? 1 : 0);
    const int q[5][4] = {{0, 2, 3, 1}, {0, 1, 5, 4}, {1, 3, 7, 5}, {3, 2, 6, 7}, {2, 0, 4, 6}};
    for (int f = 0; f < 5; f++)
        mesh_triangle(&m, q[f][0], q[f][1], q[f][2]), mesh_triangle(&m, q[f][0], q[f][2], q[f][3]);
    mesh_vertex(&m, -0.125, -0.125, 1), mesh_vertex(&m, 1.125, -0.125, 1), mesh_vertex(&m, 1.125, 1.125, 1),
        mesh_vertex(&m, -0.125, 1.125, 1);
    mesh_triangle(&m, 8, 9, 10), mesh_triangle(&m, 8, 10, 11);
    assert_mesh_truth(off, "cup_lid_off", "--res 32", &m);
    assert_mesh_truth(stl, "cup_lid_stl", "--res 32", &m);
    mesh_free(&m);
    char *da = tu_slurp(tu_tmp(a, sizeof a, "cup_lid_off.npy")), *db = tu_slurp(tu_tmp(b, sizeof b, "cup_lid_stl.npy"));
    struct stat sa, sb;
    assert_int_equal(stat(a, &sa), 0);
    assert_int_equal(stat(b, &sb), 0);
    assert_int_equal(sa.st_size, sb.st_size);
    assert_memory_equal(da, db, (size_t)sa.st_size);
    free(da);
    free(db);
}

/* A patch nothing decides (a square sheet alone: the only patch) keeps
 * the file's orientation, and the run says which patch, where and how much
 * of the surface it is. */
static void test_undecided_patch_named(void **state)
{
    (void)state;
    char path[512], vdb[512], out[8192];
    tu_tmp(path, sizeof path, "sheet_and_cube.obj");
    /* the unit cube, and a sheet of area 1 at z = 3 */
    write_text(path, CUBE_OBJ "v 0 0 3\nv 1 0 3\nv 1 1 3\nv 0 1 3\nf 9 10 11 12\n");
    const int rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --res 24 --quiet", SDFT_MESH2SDF, path,
                          tu_tmp(vdb, sizeof vdb, "sheet.vdb"));
    if (rc != 0 || !strstr(out, "warning: 1 open patches have no clear outside") ||
        !strstr(out, "(14.3% of the surface area") ||
        !strstr(out, "an open patch of 2 triangles (14.3% of the surface area, from (0, 0, 3) to (1, 1, 3))"))
        fail_msg("want the sheet named, with its share 1/7 of the area: (%d) %s", rc, out);
}

/* ---------------------------------------------------------------- batch */

/* A batch rerun with the same options skips every mesh; with another
 * --res it converts every one again (the report records the options); and
 * a rerun of that skips them again. */
static void test_batch_rerun_options(void **state)
{
    (void)state;
    char dir[512], list[600], out[16384], report[600], cube[600], tet[600];
    fresh_folder("rerun_batch", dir, sizeof dir, tet, sizeof tet);
    snprintf(cube, sizeof cube, "%s/cube.obj", dir);
    write_text(cube, CUBE_OBJ);
    snprintf(list, sizeof list, "%s/list.txt", dir);
    write_text(list, "cube.obj\ntet.obj\n");
    snprintf(report, sizeof report, "%s/out/report.jsonl", dir);
    const char *runs[][2] = {{"12", "2 converted, 0 skipped"},
                             {"12", "0 converted, 2 skipped"},
                             {"14", "2 converted, 0 skipped"},
                             {"14", "0 converted, 2 skipped"}};
    for (size_t r = 0; r < sizeof runs / sizeof *runs; r++) {
        const int rc = tu_run(out, sizeof out, "%s --batch '%s' --out-dir '%s/out' --res %s", SDFT_MESH2SDF, list, dir,
                              runs[r][0]);
        if (rc != 0 || !strstr(out, runs[r][1]))
            fail_msg("run %zu (--res %s): want '%s', got (%d) %s", r, runs[r][0], runs[r][1], rc, out);
        /* the cube's grid is as --res says: its longest side */
        char *rows = tu_slurp(report);
        assert_non_null(rows);
        assert_int_equal((int)json_number(rows, "\"dims\"", 0), atoi(runs[r][0]));
        assert_int_equal(count_of(rows, "\"options\": \""), 2);
        free(rows);
    }
}

/* -------------------------------------------------------- temporaries */

/* Starts mesh2sdf with `args` (a shell word list) in the background;
 * returns its pid. */
static pid_t start(const char *args)
{
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "exec %s %s >/dev/null 2>&1", SDFT_MESH2SDF, args);
    const pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
        _exit(127);
    }
    return pid;
}

/* Waits up to 60 s for a temporary file of `name` in `dir`. */
static void wait_for_temporary(const char *dir, const char *name)
{
    for (int i = 0; i < 6000 && tu_temporaries(dir, name) == 0; i++)
        usleep(10000);
    assert_int_equal(tu_temporaries(dir, name), 1);
}

/* Sets the times of every temporary file of `name` in `dir` a minute back:
 * older than the moment between a temporary file's creation and its lock. */
static void age_temporaries(const char *dir, const char *name)
{
    assert_int_equal(tu_run(NULL, 0, "touch -d '1 minute ago' '%s'/.'%s'.tmp-*", dir, name), 0);
}

/* A run killed with SIGKILL leaves its temporary file; the next run into
 * that folder removes it. A run still writing keeps its own, whatever runs
 * beside it; and a batch sweeps its folder of what killed runs left there,
 * and of nothing else. */
static void test_killed_run_leftover(void **state)
{
    (void)state;
    char dir[512], spot[1024], small[600], args[4096], out[8192], path[700];
    fresh_folder("killed", dir, sizeof dir, small, sizeof small);
    snprintf(spot, sizeof spot, "%s/spot.obj", SDFT_MESH_DIR);
    /* A run beside a live one into the same destination keeps the live
     * run's temporary file, however old it looks. */
    snprintf(args, sizeof args, "'%s' -o '%s/grid.vdb' --res 256 --full --threads 1", spot, dir);
    const pid_t pid = start(args);
    wait_for_temporary(dir, "grid.vdb");
    age_temporaries(dir, "grid.vdb");
    char live[700];
    assert_int_equal(tu_run(live, sizeof live, "ls -i '%s'/.grid.vdb.tmp-*", dir), 0);
    assert_int_equal(tu_run(out, sizeof out, "%s '%s' -o '%s/grid.vdb' --res 16 --quiet", SDFT_MESH2SDF, small, dir),
                     0);
    assert_int_equal(tu_run(out, sizeof out, "ls -i '%s'/.grid.vdb.tmp-*", dir), 0);
    if (strcmp(live, out) != 0)
        fail_msg("a live run's temporary file was removed: it was %s, now %s", live, out);
    /* Killed, it leaves it; the next run into that destination removes it. */
    assert_int_equal(kill(pid, SIGKILL), 0);
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFSIGNALED(status));
    assert_int_equal(tu_temporaries(dir, "grid.vdb"), 1);
    age_temporaries(dir, "grid.vdb");
    assert_int_equal(tu_run(out, sizeof out, "%s '%s' -o '%s/grid.vdb' --res 16 --quiet", SDFT_MESH2SDF, small, dir),
                     0);
    tu_assert_no_temporaries(dir, "grid.vdb");
    /* A batch's folder: a killed run's temporary files (a grid's, the
     * report's) go, another program's stay. */
    const char *planted[] = {"tet.vdb", "report.jsonl", "notes.txt"};
    for (int i = 0; i < 3; i++) {
        snprintf(path, sizeof path, "%s/out/.%s.tmp-Ab12Cd", dir, planted[i]);
        assert_int_equal(
            tu_run(NULL, 0, "mkdir -p '%s/out' && : > '%s' && touch -d '1 minute ago' '%s'", dir, path, path), 0);
    }
    snprintf(path, sizeof path, "%s/list.txt", dir);
    write_text(path, "tet.obj\n");
    assert_int_equal(
        tu_run(out, sizeof out, "%s --batch '%s' --out-dir '%s/out' --res 16 --quiet", SDFT_MESH2SDF, path, dir), 0);
    snprintf(path, sizeof path, "%s/out", dir);
    tu_assert_no_temporaries(path, "tet.vdb");
    tu_assert_no_temporaries(path, "report.jsonl");
    assert_int_equal(tu_temporaries(path, "notes.txt"), 1);
}

/* ------------------------------------------------------------- messages */

static void test_messages(void **state)
{
    (void)state;
    char dir[1024], out[16384], err[512], vdb[512];
    /* A folder given as a mesh. */
    real(dir, sizeof dir, "");
    expect_refused(dir, "", "mesh is a folder, not a file");
    /* --json: a failed run answers with an object on stdout, and its one
     * line on stderr. */
    tu_tmp(err, sizeof err, "json_error.txt");
    tu_tmp(vdb, sizeof vdb, "json_error.vdb");
    int rc = tu_run(out, sizeof out, "( %s /nonexistent/mesh.obj -o '%s' --json 2>'%s' )", SDFT_MESH2SDF, vdb, err);
    assert_int_equal(rc, 1);
    if (strncmp(out, "{\"mesh\": \"/nonexistent/mesh.obj\", \"status\": \"failed\", \"error\": ", 63) != 0 ||
        !strstr(out, "\"cannot open mesh: /nonexistent/mesh.obj\"}") || tu_lines(out) != 1)
        fail_msg("want the error as a JSON object, got: %s", out);
    char *line = tu_slurp(err);
    assert_non_null(line);
    assert_int_equal(tu_lines(line), 1);
    assert_non_null(strstr(line, "mesh2sdf: cannot open mesh"));
    free(line);
    /* --help: each usage once, one list of what a batch writes. */
    assert_int_equal(tu_run(out, sizeof out, "%s --help", SDFT_MESH2SDF), 0);
    assert_int_equal(count_of(out, "mpirun -np N mesh2sdf"), 1);
    assert_int_equal(count_of(out, "\n       mesh2sdf --batch LIST"), 1);
    assert_int_equal(count_of(out, "[--formats "), 1);
    assert_non_null(strstr(out, "[--formats vdb,nvdb,npy,samples]"));
    assert_non_null(strstr(out, "--strict"));
    assert_non_null(strstr(out, "A rerun resumes"));
}

/* The ambiguous voxels are counted among the active ones, as the summary
 * says: a sheet's band, held to brute-force winding numbers at its band's
 * voxels. */
static void test_ambiguous_among_active(void **state)
{
    (void)state;
    char path[512], vdb[512], npy[512], out[8192];
    tu_tmp(path, sizeof path, "big_sheet.obj");
    write_text(path, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    assert_int_equal(tu_run(out, sizeof out, "%s '%s' -o '%s' --npy '%s' --res 48 --json 2>/dev/null", SDFT_MESH2SDF,
                            path, tu_tmp(vdb, sizeof vdb, "big_sheet.vdb"), tu_tmp(npy, sizeof npy, "big_sheet.npy")),
                     0);
    const double active = json_number(out, "\"active_voxels\"", 0),
                 ambiguous = json_number(out, "\"ambiguous_voxels\"", 0);
    mesh m = {0};
    mesh_vertex(&m, 0, 0, 0), mesh_vertex(&m, 1, 0, 0), mesh_vertex(&m, 1, 1, 0), mesh_vertex(&m, 0, 1, 0);
    mesh_triangle(&m, 0, 1, 2), mesh_triangle(&m, 0, 2, 3);
    dense g;
    read_dense(npy, &g);
    long band = 0, unclear = 0;
    for (int i = 0; i < g.n[0]; i++)
        for (int j = 0; j < g.n[1]; j++)
            for (int k = 0; k < g.n[2]; k++) {
                if (!(fabs(dense_at(&g, i, j, k)) < BAND * g.h * (1 - 1e-6)))
                    continue;
                double p[3];
                dense_point(&g, i, j, k, p);
                band++;
                unclear += fabs(winding(&m, p) - 0.5) < 0.25;
            }
    free(g.data);
    mesh_free(&m);
    assert_int_equal((long)active, band);
    if (!(ambiguous <= active && fabs(ambiguous - (double)unclear) <= 0.02 * (double)band))
        fail_msg("%g ambiguous voxels of %g active; brute force finds %ld of the band's %ld", ambiguous, active,
                 unclear, band);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_obj_faces_left_out),
        cmocka_unit_test(test_gltf_faces_left_out),
        cmocka_unit_test(test_ply_faces_left_out),
        cmocka_unit_test(test_ply_free_text),
        cmocka_unit_test(test_scene_past_its_data),
        cmocka_unit_test(test_mirrored_node),
        cmocka_unit_test(test_check_sign_orientation),
        cmocka_unit_test(test_check_sign_no_false_alarm),
        cmocka_unit_test(test_two_copies_one_grid),
        cmocka_unit_test(test_undecided_patch_named),
        cmocka_unit_test(test_batch_rerun_options),
        cmocka_unit_test(test_killed_run_leftover),
        cmocka_unit_test(test_messages),
        cmocka_unit_test(test_ambiguous_among_active),
    };
    return cmocka_run_group_tests_name("mesh2sdf_real", tests, NULL, NULL);
}
