/* mesh2sdf's input formats: scenes in glTF (.glb, .gltf with its buffer in
 * a data URI or a file beside it), Collada, 3MF and FBX, written here with
 * meshes placed by node transforms and one mesh instanced twice, must convert
 * to the grid of the same triangles placed in world space by this test and
 * written as OBJ; PLY files with triangle strips, extra properties and
 * elements, in ascii and both binary byte orders, to the grid of the same
 * faces in OBJ; the shared meshes as PLY to the grid of their OBJ; and
 * malformed PLY and glTF files fail with one line and write nothing.
 *
 * Where every transform is exact in binary floating point (dyadic
 * translations and scales, rotations by multiples of 90 degrees given as
 * matrices or quaternions with entries 0 and 1) the grids are compared byte
 * for byte. Where a rotation is not (a quaternion of 30 degrees, FBX's
 * rotations in degrees), assimp composes it in float while this test places
 * the vertices in double, so the vertices differ by float rounding and the
 * grids are compared within 1e-5 world units. */
#define _GNU_SOURCE /* memmem */
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

#define RES "--res 40 --orient none" /* the faces as read: a reversed face shows */

/* ---------------------------------------------------------------- parts */

/* A part: vertices and faces of 3 or 4 corners, outward counter-clockwise. */
typedef struct part {
    const double (*v)[3];
    int nv;
    const int (*f)[4];
    int nf, arity;
} part;

/* An asymmetric box [0,1] x [0,0.5] x [0,0.25], as quads, and a
 * tetrahedron: turned or mirrored, either shows. */
static const double box_v[8][3] = {{0, 0, 0},   {1, 0, 0},   {1, .5, 0},   {0, .5, 0},
                                   {0, 0, .25}, {1, 0, .25}, {1, .5, .25}, {0, .5, .25}};
static const int box_f[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
static const double tet_v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
static const int tet_f[4][4] = {{0, 2, 1, -1}, {0, 1, 3, -1}, {0, 3, 2, -1}, {1, 2, 3, -1}};
static const part box = {box_v, 8, box_f, 6, 4};
static const part tet = {tet_v, 4, tet_f, 4, 3};

/* A part placed in the world by a 3x4 affine matrix (column vectors). */
typedef struct placed {
    const part *p;
    double m[3][4];
} placed;

static void affine_mul(const double a[3][4], const double b[3][4], double out[3][4])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            out[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j] + (j == 3 ? a[i][3] : 0);
}

/* Translation t, rotation by the unit quaternion q = (x, y, z, w), scale s:
 * T R S, as glTF composes a node. */
static void trs(const double t[3], const double q[4], const double s[3], double m[3][4])
{
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            m[i][j] = r[i][j] * s[j];
        m[i][3] = t[i];
    }
}

/* A file in the test folder, opened with `mode`. */
static FILE *open_tmp(const char *name, const char *mode)
{
    char path[512];
    FILE *f = fopen(tu_tmp(path, sizeof path, name), mode);
    assert_non_null(f);
    return f;
}

/* The placed parts' triangles in world space as OBJ: vertices rounded to
 * float (as every reader stores them), faces as the parts give them. */
static void write_world_obj(const char *path, const placed *parts, int n)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    int base = 1;
    for (int i = 0; i < n; i++) {
        const part *p = parts[i].p;
        for (int v = 0; v < p->nv; v++) {
            fprintf(f, "v");
            for (int k = 0; k < 3; k++) {
                const double *m = parts[i].m[k];
                fprintf(f, " %.9g", (float)(m[0] * p->v[v][0] + m[1] * p->v[v][1] + m[2] * p->v[v][2] + m[3]));
            }
            fprintf(f, "\n");
        }
        for (int t = 0; t < p->nf; t++) {
            fprintf(f, "f");
            for (int k = 0; k < p->arity; k++)
                fprintf(f, " %d", base + p->f[t][k]);
            fprintf(f, "\n");
        }
        base += p->nv;
    }
    fclose(f);
}

/* ------------------------------------------------------- comparing grids */

static unsigned char *read_bytes(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        fail_msg("cannot open %s", path);
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *b = malloc(*size + 1);
    assert_int_equal(fread(b, 1, *size, f), *size);
    fclose(f);
    return b;
}

/* Converts test-folder file `name` to NAME.out.npy, read back into `g`;
 * the .npy's path in `npy`. */
static void convert_tmp(const char *name, dense *g, char *npy, size_t len)
{
    char in[512], out[512];
    snprintf(out, sizeof out, "%s.out", name);
    convert(tu_tmp(in, sizeof in, name), out, RES, g);
    snprintf(npy, len, "%s/%s.npy", SDFT_TEST_TMP, out);
}

/* Converts `in` and `reference` (test-folder names) and holds their .npy
 * grids equal byte for byte. */
static void assert_same_grid(const char *in, const char *reference)
{
    char pa[600], pb[600];
    dense ga, gb;
    convert_tmp(in, &ga, pa, sizeof pa);
    convert_tmp(reference, &gb, pb, sizeof pb);
    free(ga.data);
    free(gb.data);
    size_t sa, sb;
    unsigned char *da = read_bytes(pa, &sa), *db = read_bytes(pb, &sb);
    if (sa != sb || memcmp(da, db, sa) != 0)
        fail_msg("%s and %s convert to different grids", in, reference);
    free(da);
    free(db);
}

/* The same, within `tolerance` world units: same shape, origins and values
 * that close. */
static void assert_close_grid(const char *in, const char *reference, double tolerance)
{
    char pa[600], pb[600];
    dense ga, gb;
    convert_tmp(in, &ga, pa, sizeof pa);
    convert_tmp(reference, &gb, pb, sizeof pb);
    for (int k = 0; k < 3; k++) {
        assert_int_equal(ga.n[k], gb.n[k]);
        assert_true(fabs(ga.origin[k] - gb.origin[k]) < tolerance);
    }
    double worst = 0;
    const size_t count = (size_t)ga.n[0] * ga.n[1] * ga.n[2];
    for (size_t i = 0; i < count; i++)
        worst = fmax(worst, fabs((double)ga.data[i] - gb.data[i]));
    if (!(worst < tolerance))
        fail_msg("%s and %s differ by %g", in, reference, worst);
    free(ga.data);
    free(gb.data);
}

/* mesh2sdf's health line for test-folder file `name` must hold `counts`. */
static void assert_health(const char *name, const char *counts)
{
    char in[512], vdb[512], out[4096];
    const int rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --res 16 2>&1", SDFT_MESH2SDF, tu_tmp(in, sizeof in, name),
                          tu_tmp(vdb, sizeof vdb, "health.vdb"));
    if (rc != 0 || !strstr(out, counts))
        fail_msg("%s: want '%s' in the health line, got: %s", name, counts, out);
}

/* ------------------------------------------------------------------ glTF */

/* The glTF scene: mesh 0 the box (uint16 indices), mesh 1 the tetrahedron
 * (uint32 indices); node 0 the box moved along x; node 1 the box again,
 * translated, turned 180 degrees about z and scaled by 2 (TRS); node 2 a
 * matrix (90 degrees about x, then up z) over node 3, the tetrahedron
 * translated and halved, with the tetrahedron's corners also as points and
 * as lines (left out). With `turn30`, node 1 turns 30 degrees about the
 * axis (1,1,0)/sqrt(2) instead. */
#define GLTF_BYTES 264
static const double g_t0[3] = {2, 0, 0}, g_t1[3] = {-1, .5, 0}, g_s1[3] = {2, 2, 2}, g_t3[3] = {.5, 0, 0},
                    g_s3[3] = {.5, .5, .5}, g_one[3] = {1, 1, 1}, g_q0[4] = {0, 0, 0, 1}, g_q180[4] = {0, 0, 1, 0};
static const double g_m2[3][4] = {{1, 0, 0, 0}, {0, 0, -1, 0}, {0, 1, 0, 3}};

static void gltf_q30(double q[4])
{
    const double h = 15.0 * 3.14159265358979323846 / 180.0, a = sin(h) / sqrt(2.0);
    q[0] = a;
    q[1] = a;
    q[2] = 0;
    q[3] = cos(h);
}

/* The scene in world space, in assimp's order (the nodes depth first). */
static int gltf_world(int turn30, placed out[3])
{
    double q30[4], local[3][4], node3[3][4];
    gltf_q30(q30);
    out[0].p = &box;
    trs(g_t0, g_q0, g_one, out[0].m);
    out[1].p = &box;
    trs(g_t1, turn30 ? q30 : g_q180, g_s1, out[1].m);
    out[2].p = &tet;
    trs(g_t3, g_q0, g_s3, local);
    affine_mul(g_m2, local, node3);
    memcpy(out[2].m, node3, sizeof node3);
    return 3;
}

/* The binary buffer: box positions, box indices (uint16), tetrahedron
 * positions, tetrahedron indices (uint32), little-endian. */
static void gltf_buffer(unsigned char *b)
{
    size_t at = 0;
    for (int v = 0; v < 8; v++)
        for (int k = 0; k < 3; k++) {
            const float x = (float)box_v[v][k];
            memcpy(b + at, &x, 4);
            at += 4;
        }
    for (int q = 0; q < 6; q++) {
        const int tri[6] = {box_f[q][0], box_f[q][1], box_f[q][2], box_f[q][0], box_f[q][2], box_f[q][3]};
        for (int k = 0; k < 6; k++) {
            const uint16_t i = (uint16_t)tri[k];
            memcpy(b + at, &i, 2);
            at += 2;
        }
    }
    for (int v = 0; v < 4; v++)
        for (int k = 0; k < 3; k++) {
            const float x = (float)tet_v[v][k];
            memcpy(b + at, &x, 4);
            at += 4;
        }
    for (int t = 0; t < 4; t++)
        for (int k = 0; k < 3; k++) {
            const uint32_t i = (uint32_t)tet_f[t][k];
            memcpy(b + at, &i, 4);
            at += 4;
        }
    assert_int_equal(at, GLTF_BYTES);
}

/* The glTF JSON; `uri` NULL for a GLB's own buffer. */
static void gltf_json(char *json, size_t len, int turn30, const char *uri)
{
    double q30[4];
    gltf_q30(q30);
    const double *q1 = turn30 ? q30 : g_q180;
    char buffer[512];
    if (uri)
        snprintf(buffer, sizeof buffer, "{\"byteLength\":%d,\"uri\":\"%s\"}", GLTF_BYTES, uri);
    else
        snprintf(buffer, sizeof buffer, "{\"byteLength\":%d}", GLTF_BYTES);
    snprintf(json, len,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1,2]}],"
             "\"nodes\":[{\"mesh\":0,\"translation\":[2,0,0]},"
             "{\"mesh\":0,\"translation\":[-1,0.5,0],\"rotation\":[%.17g,%.17g,%.17g,%.17g],\"scale\":[2,2,2]},"
             "{\"matrix\":[1,0,0,0, 0,0,1,0, 0,-1,0,0, 0,0,3,1],\"children\":[3]},"
             "{\"mesh\":1,\"translation\":[0.5,0,0],\"scale\":[0.5,0.5,0.5]}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]},"
             "{\"primitives\":[{\"attributes\":{\"POSITION\":2},\"indices\":3,\"mode\":4},"
             "{\"attributes\":{\"POSITION\":2},\"mode\":0},{\"attributes\":{\"POSITION\":2},\"mode\":1}]}],"
             "\"buffers\":[%s],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":96},"
             "{\"buffer\":0,\"byteOffset\":96,\"byteLength\":72},"
             "{\"buffer\":0,\"byteOffset\":168,\"byteLength\":48},"
             "{\"buffer\":0,\"byteOffset\":216,\"byteLength\":48}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":8,\"type\":\"VEC3\","
             "\"min\":[0,0,0],\"max\":[1,0.5,0.25]},"
             "{\"bufferView\":1,\"componentType\":5123,\"count\":36,\"type\":\"SCALAR\"},"
             "{\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
             "\"min\":[0,0,0],\"max\":[1,1,1]},"
             "{\"bufferView\":3,\"componentType\":5125,\"count\":12,\"type\":\"SCALAR\"}]}",
             q1[0], q1[1], q1[2], q1[3], buffer);
}

static void put32(FILE *f, uint32_t v)
{
    const unsigned char b[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16),
                                (unsigned char)(v >> 24)};
    fwrite(b, 1, 4, f);
}

static void write_glb(const char *name, int turn30)
{
    char json[4096];
    unsigned char buf[GLTF_BYTES];
    gltf_buffer(buf);
    gltf_json(json, sizeof json, turn30, NULL);
    size_t jlen = strlen(json);
    while (jlen % 4)
        json[jlen++] = ' '; /* chunks are 4-byte aligned, JSON padded with spaces */
    FILE *f = open_tmp(name, "wb");
    put32(f, 0x46546C67); /* "glTF" */
    put32(f, 2);
    put32(f, (uint32_t)(12 + 8 + jlen + 8 + GLTF_BYTES));
    put32(f, (uint32_t)jlen);
    put32(f, 0x4E4F534A); /* "JSON" */
    fwrite(json, 1, jlen, f);
    put32(f, GLTF_BYTES);
    put32(f, 0x004E4942); /* "BIN" */
    fwrite(buf, 1, GLTF_BYTES, f);
    fclose(f);
}

static void base64(const unsigned char *in, size_t n, char *out)
{
    static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        const uint32_t v =
            (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0) | (i + 2 < n ? in[i + 2] : 0);
        out[o++] = digits[v >> 18 & 63];
        out[o++] = digits[v >> 12 & 63];
        out[o++] = i + 1 < n ? digits[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? digits[v & 63] : '=';
    }
    out[o] = '\0';
}

/* A .gltf whose buffer is a data URI, or (`bin` set) the file `bin` beside it. */
static void write_gltf(const char *name, const char *bin)
{
    char json[4096], uri[512];
    unsigned char buf[GLTF_BYTES];
    gltf_buffer(buf);
    if (bin) {
        FILE *b = open_tmp(bin, "wb");
        fwrite(buf, 1, GLTF_BYTES, b);
        fclose(b);
        snprintf(uri, sizeof uri, "%s", bin);
    } else {
        strcpy(uri, "data:application/octet-stream;base64,");
        base64(buf, GLTF_BYTES, uri + strlen(uri));
    }
    gltf_json(json, sizeof json, 0, uri);
    FILE *f = open_tmp(name, "w");
    fputs(json, f);
    fclose(f);
}

static void write_world(const char *name, const placed *parts, int n)
{
    char path[512];
    write_world_obj(tu_tmp(path, sizeof path, name), parts, n);
}

static void test_gltf(void **state)
{
    (void)state;
    placed world[3];
    write_world("gltf_world.obj", world, gltf_world(0, world));
    write_glb("scene.glb", 0);
    write_gltf("scene_data_uri.gltf", NULL);
    write_gltf("scene_file.gltf", "scene_file.bin");
    assert_same_grid("scene.glb", "gltf_world.obj");
    /* the points and lines add no vertex */
    assert_health("scene.glb", "20 vertices, 28 faces (28 triangles)");
    assert_same_grid("scene_data_uri.gltf", "gltf_world.obj");
    assert_same_grid("scene_file.gltf", "gltf_world.obj");
    /* A rotation assimp composes in float: within rounding. */
    write_world("gltf_world30.obj", world, gltf_world(1, world));
    write_glb("scene30.glb", 1);
    assert_close_grid("scene30.glb", "gltf_world30.obj", 1e-5);
}

/* --------------------------------------------------------------- Collada */

/* The box (quads, a polylist) at x = 2; under a matrix node (90 degrees
 * about x, up z) the box again and a child node with the tetrahedron
 * translated and halved. Z_UP is declared and must not turn anything.
 * `count` names the float arrays' count attribute ("count"; anything else
 * makes assimp 5.2 crash). */
static void write_dae(const char *name, const char *count)
{
    FILE *f = open_tmp(name, "w");
    fprintf(f, "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
               "<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n"
               "<asset><up_axis>Z_UP</up_axis></asset>\n<library_geometries>\n");
    const part *parts[2] = {&box, &tet};
    const char *names[2] = {"box", "tet"};
    for (int g = 0; g < 2; g++) {
        const part *p = parts[g];
        fprintf(f, "<geometry id=\"%s\"><mesh><source id=\"%s-pos\"><float_array id=\"%s-arr\" %s=\"%d\">", names[g],
                names[g], names[g], count, 3 * p->nv);
        for (int v = 0; v < p->nv; v++)
            fprintf(f, " %g %g %g", p->v[v][0], p->v[v][1], p->v[v][2]);
        fprintf(f,
                "</float_array><technique_common><accessor source=\"#%s-arr\" count=\"%d\" stride=\"3\">"
                "<param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/>"
                "<param name=\"Z\" type=\"float\"/></accessor></technique_common></source>\n"
                "<vertices id=\"%s-v\"><input semantic=\"POSITION\" source=\"#%s-pos\"/></vertices>\n"
                "<polylist count=\"%d\"><input semantic=\"VERTEX\" source=\"#%s-v\" offset=\"0\"/><vcount>",
                names[g], p->nv, names[g], names[g], p->nf, names[g]);
        for (int t = 0; t < p->nf; t++)
            fprintf(f, " %d", p->arity);
        fprintf(f, "</vcount><p>");
        for (int t = 0; t < p->nf; t++)
            for (int k = 0; k < p->arity; k++)
                fprintf(f, " %d", p->f[t][k]);
        fprintf(f, "</p></polylist></mesh></geometry>\n");
    }
    fprintf(f, "</library_geometries>\n<library_visual_scenes><visual_scene id=\"s\">\n"
               "<node id=\"a\"><translate>2 0 0</translate><instance_geometry url=\"#box\"/></node>\n"
               "<node id=\"b\"><matrix>1 0 0 0 0 0 -1 0 0 1 0 3 0 0 0 1</matrix>"
               "<instance_geometry url=\"#box\"/>\n"
               "<node id=\"c\"><translate>0.5 0 0</translate><scale>0.5 0.5 0.5</scale>"
               "<instance_geometry url=\"#tet\"/></node></node>\n"
               "</visual_scene></library_visual_scenes>\n"
               "<scene><instance_visual_scene url=\"#s\"/></scene>\n</COLLADA>\n");
    fclose(f);
}

static void test_collada(void **state)
{
    (void)state;
    write_dae("scene.dae", "count");
    placed world[3] = {{&box, {{1, 0, 0, 2}, {0, 1, 0, 0}, {0, 0, 1, 0}}}, {&box, {{0}}}, {&tet, {{0}}}};
    double local[3][4];
    memcpy(world[1].m, g_m2, sizeof g_m2);
    trs(g_t3, g_q0, g_s3, local);
    affine_mul(g_m2, local, world[2].m);
    write_world("dae_world.obj", world, 3);
    assert_same_grid("scene.dae", "dae_world.obj");
}

/* ------------------------------------------------------------------- 3MF */

static uint32_t crc32(const unsigned char *b, size_t n)
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        c ^= b[i];
        for (int k = 0; k < 8; k++)
            c = c >> 1 ^ (0xEDB88320u & (0u - (c & 1)));
    }
    return ~c;
}

static void put16(FILE *f, uint16_t v)
{
    const unsigned char b[2] = {(unsigned char)v, (unsigned char)(v >> 8)};
    fwrite(b, 1, 2, f);
}

/* A zip archive of `n` files stored uncompressed: the OPC package 3MF is. */
static void write_zip(const char *path, const char *const *names, const char *const *texts, int n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    uint32_t offsets[8];
    for (int i = 0; i < n; i++) {
        offsets[i] = (uint32_t)ftell(f);
        const uint32_t size = (uint32_t)strlen(texts[i]);
        put32(f, 0x04034b50);
        put16(f, 20), put16(f, 0), put16(f, 0), put16(f, 0), put16(f, 0x21);
        put32(f, crc32((const unsigned char *)texts[i], size)), put32(f, size), put32(f, size);
        put16(f, (uint16_t)strlen(names[i])), put16(f, 0);
        fputs(names[i], f);
        fputs(texts[i], f);
    }
    const uint32_t directory = (uint32_t)ftell(f);
    for (int i = 0; i < n; i++) {
        const uint32_t size = (uint32_t)strlen(texts[i]);
        put32(f, 0x02014b50);
        put16(f, 20), put16(f, 20), put16(f, 0), put16(f, 0), put16(f, 0), put16(f, 0x21);
        put32(f, crc32((const unsigned char *)texts[i], size)), put32(f, size), put32(f, size);
        put16(f, (uint16_t)strlen(names[i])), put16(f, 0), put16(f, 0), put16(f, 0), put16(f, 0);
        put32(f, 0), put32(f, offsets[i]);
        fputs(names[i], f);
    }
    const uint32_t end = (uint32_t)ftell(f);
    put32(f, 0x06054b50);
    put16(f, 0), put16(f, 0), put16(f, (uint16_t)n), put16(f, (uint16_t)n);
    put32(f, end - directory), put32(f, directory), put16(f, 0);
    fclose(f);
}

/* Objects box and tetrahedron (triangles); build items: the box at x = 2,
 * the tetrahedron turned 90 degrees about x and moved up z. 3MF's matrices
 * act on row vectors: the rows are the columns of ours. */
static void write_3mf(const char *name)
{
    char model[8192], path[512];
    size_t at = (size_t)snprintf(model, sizeof model,
                                 "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" "
                                 "xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\"><resources>\n");
    const part *parts[2] = {&box, &tet};
    for (int o = 0; o < 2; o++) {
        at +=
            (size_t)snprintf(model + at, sizeof model - at, "<object id=\"%d\" type=\"model\"><mesh><vertices>", o + 1);
        for (int v = 0; v < parts[o]->nv; v++)
            at += (size_t)snprintf(model + at, sizeof model - at, "<vertex x=\"%g\" y=\"%g\" z=\"%g\"/>",
                                   parts[o]->v[v][0], parts[o]->v[v][1], parts[o]->v[v][2]);
        at += (size_t)snprintf(model + at, sizeof model - at, "</vertices><triangles>");
        for (int t = 0; t < parts[o]->nf; t++)
            for (int k = 1; k + 1 < parts[o]->arity; k++)
                at += (size_t)snprintf(model + at, sizeof model - at, "<triangle v1=\"%d\" v2=\"%d\" v3=\"%d\"/>",
                                       parts[o]->f[t][0], parts[o]->f[t][k], parts[o]->f[t][k + 1]);
        at += (size_t)snprintf(model + at, sizeof model - at, "</triangles></mesh></object>\n");
    }
    snprintf(model + at, sizeof model - at,
             "</resources><build><item objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 2 0 0\"/>"
             "<item objectid=\"2\" transform=\"1 0 0 0 0 1 0 -1 0 0 0 3\"/></build></model>\n");
    const char *names[3] = {"[Content_Types].xml", "_rels/.rels", "3D/3dmodel.model"};
    const char *texts[3] = {
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types "
        "xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\"><Default Extension=\"rels\" "
        "ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/><Default Extension=\"model\" "
        "ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/></Types>\n",
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships "
        "xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\"><Relationship "
        "Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
        "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n",
        model};
    write_zip(tu_tmp(path, sizeof path, name), names, texts, 3);
}

static void test_3mf(void **state)
{
    (void)state;
    write_3mf("scene.3mf");
    placed world[2] = {{&box, {{1, 0, 0, 2}, {0, 1, 0, 0}, {0, 0, 1, 0}}}, {&tet, {{0}}}};
    memcpy(world[1].m, g_m2, sizeof g_m2);
    write_world("3mf_world.obj", world, 2);
    assert_same_grid("scene.3mf", "3mf_world.obj");
}

/* ------------------------------------------------------------------- FBX */

/* An ASCII FBX 7.4: the box under a model translated along x, and again
 * under a model turned 90 degrees about x (FBX's Euler angles, degrees),
 * scaled by (2, 1, 1) and translated up z, as FBX composes them: T R S. */
static void test_fbx(void **state)
{
    (void)state;
    FILE *f = open_tmp("scene.fbx", "w");
    fprintf(f, "; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n\tFBXHeaderVersion: 1003\n\tFBXVersion: 7400\n}\n"
               "Objects:  {\n\tGeometry: 1000, \"Geometry::box\", \"Mesh\" {\n\t\tVertices: *24 {\n\t\t\ta: ");
    for (int v = 0; v < 8; v++)
        fprintf(f, "%s%g,%g,%g", v ? "," : "", box_v[v][0], box_v[v][1], box_v[v][2]);
    fprintf(f, "\n\t\t}\n\t\tPolygonVertexIndex: *24 {\n\t\t\ta: ");
    for (int q = 0; q < 6; q++) /* the last corner of each polygon as -(index + 1) */
        fprintf(f, "%s%d,%d,%d,%d", q ? "," : "", box_f[q][0], box_f[q][1], box_f[q][2], -box_f[q][3] - 1);
    fprintf(f, "\n\t\t}\n\t\tGeometryVersion: 124\n\t}\n"
               "\tModel: 2000, \"Model::a\", \"Mesh\" {\n\t\tVersion: 232\n\t\tProperties70:  {\n"
               "\t\t\tP: \"Lcl Translation\", \"Lcl Translation\", \"\", \"A\",2,0,0\n\t\t}\n\t}\n"
               "\tModel: 2001, \"Model::b\", \"Mesh\" {\n\t\tVersion: 232\n\t\tProperties70:  {\n"
               "\t\t\tP: \"Lcl Translation\", \"Lcl Translation\", \"\", \"A\",0,0,3\n"
               "\t\t\tP: \"Lcl Rotation\", \"Lcl Rotation\", \"\", \"A\",90,0,0\n"
               "\t\t\tP: \"Lcl Scaling\", \"Lcl Scaling\", \"\", \"A\",2,1,1\n\t\t}\n\t}\n}\n"
               "Connections:  {\n\tC: \"OO\",1000,2000\n\tC: \"OO\",1000,2001\n"
               "\tC: \"OO\",2000,0\n\tC: \"OO\",2001,0\n}\n");
    fclose(f);
    placed world[2] = {{&box, {{1, 0, 0, 2}, {0, 1, 0, 0}, {0, 0, 1, 0}}},
                       {&box, {{2, 0, 0, 0}, {0, 0, -1, 0}, {0, 1, 0, 3}}}};
    write_world("fbx_world.obj", world, 2);
    assert_close_grid("scene.fbx", "fbx_world.obj", 1e-5);
}

/* ------------------------------------------------------------------- PLY */

typedef enum { ASCII, LITTLE, BIG } ply_encoding;
static const char *const encoding_name[3] = {"ascii", "binary_little_endian", "binary_big_endian"};

/* Writes one value of a PLY scalar type ("float", "uchar" ...). */
static void ply_value(FILE *f, ply_encoding e, const char *type, double v)
{
    if (e == ASCII) {
        fprintf(f, "%.9g ", v);
        return;
    }
    unsigned char b[8];
    size_t n;
    if (!strcmp(type, "float")) {
        const float x = (float)v;
        memcpy(b, &x, n = 4);
    } else if (!strcmp(type, "double")) {
        memcpy(b, &v, n = 8);
    } else if (!strcmp(type, "uchar")) {
        b[0] = (unsigned char)v, n = 1;
    } else if (!strcmp(type, "short")) {
        const int16_t x = (int16_t)v;
        memcpy(b, &x, n = 2);
    } else if (!strcmp(type, "int")) {
        const int32_t x = (int32_t)v;
        memcpy(b, &x, n = 4);
    } else {
        assert_string_equal(type, "uint");
        const uint32_t x = (uint32_t)(int64_t)v;
        memcpy(b, &x, n = 4);
    }
    if (e == BIG)
        for (size_t i = 0; i < n / 2; i++) {
            const unsigned char t = b[i];
            b[i] = b[n - 1 - i];
            b[n - 1 - i] = t;
        }
    fwrite(b, 1, n, f);
}

static void ply_end(FILE *f, ply_encoding e)
{
    if (e == ASCII)
        fputc('\n', f);
}

static FILE *ply_open(const char *name, ply_encoding e, const char *elements)
{
    FILE *f = open_tmp(name, "wb");
    fprintf(f, "ply\nformat %s 1.0\ncomment written by test_mesh2sdf_formats\n%send_header\n", encoding_name[e],
            elements);
    return f;
}

/* The box's quads as strips: quad (a, b, c, d) is the strip a b d c, whose
 * triangles are (a, b, d) and (d, b, c). Quads 0 and 1 are stitched into one
 * strip through repeated vertices (zero-area triangles, dropped), the others
 * are separated by -1; quad 5 is a face of the `face` element, written
 * before the strips. The OBJ lists the same triangles in that order. */
static void write_strip_ply(const char *name, ply_encoding e, const char *index_type)
{
    int strip[64], n = 0;
    for (int q = 0; q < 5; q++) {
        if (q == 2 || q == 3 || q == 4)
            strip[n++] = -1;
        if (q == 1) { /* stitch: repeat the last vertex and the next first */
            strip[n] = strip[n - 1];
            n++;
            strip[n++] = box_f[1][0];
        }
        strip[n++] = box_f[q][0], strip[n++] = box_f[q][1], strip[n++] = box_f[q][3], strip[n++] = box_f[q][2];
    }
    char header[512];
    snprintf(header, sizeof header,
             "element vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
             "element face 1\nproperty list uchar int vertex_indices\n"
             "element tristrips 1\nproperty list int %s vertex_indices\n",
             index_type);
    FILE *f = ply_open(name, e, header);
    for (int v = 0; v < 8; v++) {
        for (int k = 0; k < 3; k++)
            ply_value(f, e, "float", box_v[v][k]);
        ply_end(f, e);
    }
    ply_value(f, e, "uchar", 4);
    for (int k = 0; k < 4; k++)
        ply_value(f, e, "int", box_f[5][k]);
    ply_end(f, e);
    ply_value(f, e, "int", n);
    for (int i = 0; i < n; i++)
        ply_value(f, e, index_type, strip[i]);
    ply_end(f, e);
    fclose(f);
}

static void test_strip_ply(void **state)
{
    (void)state;
    FILE *f = open_tmp("strips.obj", "w");
    for (int v = 0; v < 8; v++)
        fprintf(f, "v %g %g %g\n", box_v[v][0], box_v[v][1], box_v[v][2]);
    fprintf(f, "f %d %d %d %d\n", box_f[5][0] + 1, box_f[5][1] + 1, box_f[5][2] + 1, box_f[5][3] + 1);
    for (int q = 0; q < 5; q++)
        fprintf(f, "f %d %d %d\nf %d %d %d\n", box_f[q][0] + 1, box_f[q][1] + 1, box_f[q][3] + 1, box_f[q][3] + 1,
                box_f[q][1] + 1, box_f[q][2] + 1);
    fclose(f);
    write_strip_ply("strips_ascii.ply", ASCII, "int");
    write_strip_ply("strips_le.ply", LITTLE, "uint"); /* -1 as 0xffffffff */
    write_strip_ply("strips_be.ply", BIG, "int");
    assert_same_grid("strips_ascii.ply", "strips.obj");
    assert_same_grid("strips_le.ply", "strips.obj");
    assert_same_grid("strips_be.ply", "strips.obj");
    /* The health line counts the strips' triangles as faces, not the
     * stitching ones. */
    assert_health("strips_ascii.ply", "8 vertices, 11 faces (12 triangles)");
}

/* A box scaled to integers, coordinates as `coord` ("short", "double" ...)
 * among other properties: a colour before x, normals and a list after z; a
 * list before the faces' vertex_indices and a float after; an element of
 * lists after the faces. */
static void write_busy_ply(const char *name, ply_encoding e, const char *coord)
{
    char header[1024];
    snprintf(header, sizeof header,
             "element vertex 8\nproperty uchar red\nproperty %s x\nproperty %s y\nproperty %s z\n"
             "property float nx\nproperty list uchar int neighbours\n"
             "element face 6\nproperty list uchar float uv\nproperty list uchar int vertex_indices\n"
             "property float quality\n"
             "element edge 2\nproperty list int int ends\nproperty short crease\n",
             coord, coord, coord);
    FILE *f = ply_open(name, e, header);
    for (int v = 0; v < 8; v++) {
        ply_value(f, e, "uchar", 200);
        for (int k = 0; k < 3; k++)
            ply_value(f, e, coord, 4 * box_v[v][k]);
        ply_value(f, e, "float", 0.5);
        ply_value(f, e, "uchar", 2);
        ply_value(f, e, "int", 7);
        ply_value(f, e, "int", 1);
        ply_end(f, e);
    }
    for (int q = 0; q < 6; q++) {
        ply_value(f, e, "uchar", 3);
        for (int k = 0; k < 3; k++)
            ply_value(f, e, "float", 0.25 * k);
        ply_value(f, e, "uchar", 4);
        for (int k = 0; k < 4; k++)
            ply_value(f, e, "int", box_f[q][k]);
        ply_value(f, e, "float", 1.5);
        ply_end(f, e);
    }
    for (int i = 0; i < 2; i++) {
        ply_value(f, e, "int", 2);
        ply_value(f, e, "int", i);
        ply_value(f, e, "int", i + 1);
        ply_value(f, e, "short", -3);
        ply_end(f, e);
    }
    fclose(f);
}

static void test_ply_other_properties(void **state)
{
    (void)state;
    const placed scaled = {&box, {{4, 0, 0, 0}, {0, 4, 0, 0}, {0, 0, 4, 0}}};
    write_world("busy.obj", &scaled, 1);
    const char *coords[3] = {"float", "double", "short"};
    for (int e = ASCII; e <= BIG; e++)
        for (int c = 0; c < 3; c++) {
            char name[64];
            snprintf(name, sizeof name, "busy_%d_%s.ply", e, coords[c]);
            write_busy_ply(name, (ply_encoding)e, coords[c]);
            assert_same_grid(name, "busy.obj");
        }
}

/* Indices of one byte: 252 unused vertices, then the tetrahedron's at
 * 252..255, so that its faces use 255, the largest uchar (a vertex, not a
 * restart: only strips restart). */
static void test_ply_byte_indices(void **state)
{
    (void)state;
    FILE *obj = open_tmp("bytes.obj", "w");
    for (int v = 0; v < 256; v++) {
        const double *p = v < 252 ? tet_v[0] : tet_v[v - 252];
        fprintf(obj, "v %g %g %g\n", p[0], p[1], p[2]);
    }
    for (int t = 0; t < 4; t++)
        fprintf(obj, "f %d %d %d\n", 253 + tet_f[t][0], 253 + tet_f[t][1], 253 + tet_f[t][2]);
    fclose(obj);
    for (int e = ASCII; e <= BIG; e++) {
        char name[64];
        snprintf(name, sizeof name, "bytes_%d.ply", e);
        FILE *f = ply_open(name, (ply_encoding)e,
                           "element vertex 256\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 4\nproperty list uchar uchar vertex_indices\n");
        for (int v = 0; v < 256; v++) {
            const double *p = v < 252 ? tet_v[0] : tet_v[v - 252];
            for (int k = 0; k < 3; k++)
                ply_value(f, (ply_encoding)e, "float", p[k]);
            ply_end(f, (ply_encoding)e);
        }
        for (int t = 0; t < 4; t++) {
            ply_value(f, (ply_encoding)e, "uchar", 3);
            for (int k = 0; k < 3; k++)
                ply_value(f, (ply_encoding)e, "uchar", 252 + tet_f[t][k]);
            ply_end(f, (ply_encoding)e);
        }
        fclose(f);
        assert_same_grid(name, "bytes.obj");
    }
}

/* One of the shared meshes as its OBJ gives it: the coordinates' words and
 * the polygons' vertex numbers (before any '/'), from 0. */
typedef struct obj_text {
    char (*coord)[3][32];
    int nv, cap_v;
    int *corners, nc, cap_c; /* every polygon's corners */
    int *count, nf, cap_f;   /* corners per polygon */
} obj_text;

static void read_obj_text(const char *path, obj_text *o)
{
    memset(o, 0, sizeof *o);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char line[1024];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == 'v' && line[1] == ' ') {
            if (o->nv == o->cap_v)
                o->coord = realloc(o->coord, (size_t)(o->cap_v = 2 * o->cap_v + 64) * sizeof *o->coord);
            char(*c)[32] = o->coord[o->nv++];
            assert_int_equal(sscanf(line + 2, "%31s %31s %31s", c[0], c[1], c[2]), 3);
        } else if (line[0] == 'f' && line[1] == ' ') {
            if (o->nf == o->cap_f)
                o->count = realloc(o->count, (size_t)(o->cap_f = 2 * o->cap_f + 64) * sizeof *o->count);
            o->count[o->nf] = 0;
            for (char *w = strtok(line + 2, " \t\r\n"); w; w = strtok(NULL, " \t\r\n")) {
                if (o->nc == o->cap_c)
                    o->corners = realloc(o->corners, (size_t)(o->cap_c = 2 * o->cap_c + 64) * sizeof *o->corners);
                o->corners[o->nc++] = atoi(w) - 1;
                o->count[o->nf]++;
            }
            o->nf++;
        }
    }
    fclose(f);
}

/* `o` as PLY: ascii with the OBJ's own words, binary with them read as
 * float (correctly rounded, as every reader reads them). */
static void write_obj_as_ply(const char *name, const obj_text *o, ply_encoding e)
{
    char header[256];
    snprintf(header, sizeof header,
             "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
             "element face %d\nproperty list uchar int vertex_indices\n",
             o->nv, o->nf);
    FILE *f = ply_open(name, e, header);
    for (int v = 0; v < o->nv; v++) {
        for (int k = 0; k < 3; k++)
            if (e == ASCII)
                fprintf(f, "%s ", o->coord[v][k]);
            else
                ply_value(f, e, "float", strtof(o->coord[v][k], NULL));
        ply_end(f, e);
    }
    for (int t = 0, at = 0; t < o->nf; at += o->count[t++]) {
        ply_value(f, e, "uchar", o->count[t]);
        for (int k = 0; k < o->count[t]; k++)
            ply_value(f, e, "int", o->corners[at + k]);
        ply_end(f, e);
    }
    fclose(f);
}

/* The shared meshes as PLY, in each encoding, convert to their OBJ's grid:
 * the same vertices and faces in the same order. */
static void test_ply_matches_obj(void **state)
{
    (void)state;
    const char *names[] = {"suzanne", "spot", "teapot", "fandisk", "stanford-bunny"};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        char obj[1024], copy[512], name[128];
        snprintf(obj, sizeof obj, "%s/%s.obj", SDFT_MESH_DIR, names[i]);
        snprintf(name, sizeof name, "%s.obj", names[i]);
        assert_int_equal(tu_run(NULL, 0, "cp '%s' '%s'", obj, tu_tmp(copy, sizeof copy, name)), 0);
        obj_text o;
        read_obj_text(obj, &o);
        for (int e = ASCII; e <= BIG; e++) {
            char ply[128];
            snprintf(ply, sizeof ply, "%s_%d.ply", names[i], e);
            write_obj_as_ply(ply, &o, (ply_encoding)e);
            assert_same_grid(ply, name);
        }
        free(o.coord);
        free(o.corners);
        free(o.count);
    }
}

/* ------------------------------------------------------------ bad input */

/* mesh2sdf on test-folder file `name` with `flags` must fail with one line
 * naming it, saying `expect`, and write nothing. */
static void expect_failure_with(const char *name, const char *flags, const char *expect)
{
    char in[512], vdb[512], out[8192];
    tu_tmp(in, sizeof in, name);
    tu_tmp(vdb, sizeof vdb, "bad_format.vdb");
    remove(vdb);
    const int rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --res 16 %s", SDFT_MESH2SDF, in, vdb, flags);
    if (rc == 0 || tu_lines(out) != 1 || strncmp(out, "mesh2sdf: ", 10) != 0 || !strstr(out, name))
        fail_msg("%s: want one 'mesh2sdf: ' line naming it, got (%d): %s", name, rc, out);
    if (expect && !strstr(out, expect))
        fail_msg("%s: message lacks '%s': %s", name, expect, out);
    assert_false(tu_file_exists(vdb));
    tu_assert_no_temporaries(SDFT_TEST_TMP, "bad_format.vdb");
}

static void expect_clean_failure(const char *name, const char *expect) { expect_failure_with(name, "", expect); }

/* mesh2sdf on test-folder file `name` must convert, warning `warning`. */
static void expect_warning(const char *name, const char *warning)
{
    char in[512], vdb[512], out[8192];
    const int rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --res 16 --quiet", SDFT_MESH2SDF,
                          tu_tmp(in, sizeof in, name), tu_tmp(vdb, sizeof vdb, "warned.vdb"));
    if (rc != 0 || !strstr(out, "mesh2sdf: warning: ") || !strstr(out, warning))
        fail_msg("%s: want it converted with a warning saying '%s', got (%d): %s", name, warning, rc, out);
}

static void write_file(const char *name, const void *bytes, size_t n)
{
    FILE *f = open_tmp(name, "wb");
    fwrite(bytes, 1, n, f);
    fclose(f);
}

static void write_text(const char *name, const char *text) { write_file(name, text, strlen(text)); }

#define TETRA_HEADER(nv, nf)                                                                                           \
    "ply\nformat ascii 1.0\nelement vertex " nv "\nproperty float x\nproperty float y\nproperty float z\n"             \
    "element face " nf "\nproperty list uchar int vertex_indices\nend_header\n"
#define TETRA_VERTICES "0 0 0\n1 0 0\n0 1 0\n0 0 1\n"

static void test_bad_ply(void **state)
{
    (void)state;
    write_text("empty.ply", "");
    expect_clean_failure("empty.ply", "not a PLY file");
    write_text("no_magic.ply", "format ascii 1.0\nend_header\n");
    expect_clean_failure("no_magic.ply", "not a PLY file");
    write_text("bad_format.ply", "ply\nformat binary_middle_endian 1.0\nelement vertex 0\nend_header\n");
    expect_clean_failure("bad_format.ply", "format line");
    write_text("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
    expect_clean_failure("no_end.ply", "end_header");
    write_text("bad_type.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float128 x\nend_header\n");
    expect_clean_failure("bad_type.ply", "property line");
    write_text("no_z.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                           "end_header\n0 0\n");
    expect_clean_failure("no_z.ply", "x, y or z");
    /* counts larger than the file: in total, and per element at its
     * fewest bytes (4 vertices of 3 floats in binary take 48) */
    write_text("huge.ply", TETRA_HEADER("1099511627776", "4") TETRA_VERTICES);
    expect_clean_failure("huge.ply", "mesh header claims 1099511627780 elements");
    const char binary[] = "ply\nformat binary_little_endian 1.0\nelement vertex 40\nproperty float x\n"
                          "property float y\nproperty float z\nend_header\n";
    unsigned char body[sizeof binary - 1 + 100] = {0};
    memcpy(body, binary, sizeof binary - 1);
    write_file("short_binary.ply", body, sizeof body);
    expect_clean_failure("short_binary.ply", "claims 40 vertex elements");
    /* a body that ends early: ascii, and binary cut inside a face */
    write_text("truncated.ply", TETRA_HEADER("4", "4") TETRA_VERTICES "3 0 2 1\n3 0 1 3\n3 0 3");
    expect_clean_failure("truncated.ply", "ends early");
    const char header[] = "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
    unsigned char cut[sizeof header - 1 + 48 + 4 * 13] = {0};
    memcpy(cut, header, sizeof header - 1);
    for (int t = 0; t < 4; t++)
        cut[sizeof header - 1 + 48 + 13 * t] = 3;
    write_file("cut.ply", cut, sizeof cut - 5);
    expect_clean_failure("cut.ply", "ends early (face 3 of 4)");
    /* indices out of range (a face, a negative face index, a strip's):
     * the face left out and counted, refused with --strict */
    write_text("index.ply", TETRA_HEADER("4", "4") TETRA_VERTICES "3 0 2 1\n3 0 1 4\n3 0 3 2\n3 1 2 3\n");
    expect_warning("index.ply", "1 face of the file was left out");
    expect_failure_with("index.ply", "--strict", "1 face of the file was left out");
    write_text("negative.ply", TETRA_HEADER("4", "4") TETRA_VERTICES "3 0 2 1\n3 0 1 -1\n3 0 3 2\n3 1 2 3\n");
    expect_warning("negative.ply", "1 face of the file was left out");
    write_text("strip_index.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                  "property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
                                  "end_header\n" TETRA_VERTICES "8 0 1 2 3 -1 3 1 99\n");
    expect_warning("strip_index.ply", "1 face of the file was left out");
    /* malformed numbers: a coordinate, a count */
    write_text("word.ply", TETRA_HEADER("4", "4") "0 0 0\n1 0x 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    expect_clean_failure("word.ply", "malformed number");
    write_text("count.ply", TETRA_HEADER("4", "4") TETRA_VERTICES "3 0 2 1\nthree 0 1 3\n3 0 3 2\n3 1 2 3\n");
    expect_clean_failure("count.ply", "malformed integer");
    write_text("nan.ply", TETRA_HEADER("4", "4") "0 0 0\nnan 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    expect_clean_failure("nan.ply", "non-finite");
    write_text("no_faces.ply", TETRA_HEADER("4", "0") TETRA_VERTICES);
    expect_clean_failure("no_faces.ply", "no faces");
}

static void test_bad_scene(void **state)
{
    (void)state;
    write_glb("whole.glb", 0);
    char path[512];
    size_t size;
    unsigned char *glb = read_bytes(tu_tmp(path, sizeof path, "whole.glb"), &size);
    const size_t cuts[] = {0, 11, 20, 100, size / 2, size - 1};
    for (size_t i = 0; i < sizeof cuts / sizeof *cuts; i++) {
        write_file("cut.glb", glb, cuts[i]);
        expect_clean_failure("cut.glb", "cannot read mesh");
    }
    free(glb);
    write_text("garbage.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [{\"primitives\": 7}]}");
    expect_clean_failure("garbage.gltf", "cannot read mesh");
    write_text("garbage.dae", "<COLLADA><library_geometries><geometry>");
    expect_clean_failure("garbage.dae", "cannot read mesh");
    write_text("garbage.fbx", "; FBX 7.4.0 project file\nObjects: {\n");
    expect_clean_failure("garbage.fbx", NULL);
    write_text("garbage.3mf", "PK\003\004 not really a zip");
    expect_clean_failure("garbage.3mf", "cannot read mesh");
    /* Files assimp 5.2 aborts or crashes on: a 3MF whose zip entry does not
     * match its CRC (an assertion), a Collada float array without its count
     * (a segmentation fault). The reader's process ends; mesh2sdf says so. */
    write_3mf("crc.3mf");
    unsigned char *zip = read_bytes(tu_tmp(path, sizeof path, "crc.3mf"), &size);
    unsigned char *x = memmem(zip, size, "<vertex x=\"0\"", 13);
    assert_non_null(x);
    x[11] = '7'; /* the CRC stays that of the 0 */
    write_file("crc.3mf", zip, size);
    free(zip);
    expect_clean_failure("crc.3mf", "the 3MF importer (assimp ");
    expect_clean_failure("crc.3mf", ") crashed on it: signal 6 (Aborted); the file may be valid)");
    write_dae("nocount.dae", "coun9");
    expect_clean_failure("nocount.dae", "the Collada importer (assimp ");
    expect_clean_failure("nocount.dae", ") crashed on it: signal 11");
}

static void test_help_lists_formats(void **state)
{
    (void)state;
    char out[16384];
    assert_int_equal(tu_run(out, sizeof out, "%s --help", SDFT_MESH2SDF), 0);
    const char *formats[] = {"obj", "ply", "off", "stl", "gltf", "glb", "fbx", "dae", "3mf", "tristrips"};
    for (size_t i = 0; i < sizeof formats / sizeof *formats; i++)
        if (!strstr(out, formats[i]))
            fail_msg("--help does not name %s", formats[i]);
    write_text("mesh.xyz", "v 0 0 0\n");
    expect_clean_failure("mesh.xyz", ".glb");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gltf),
        cmocka_unit_test(test_collada),
        cmocka_unit_test(test_3mf),
        cmocka_unit_test(test_fbx),
        cmocka_unit_test(test_strip_ply),
        cmocka_unit_test(test_ply_other_properties),
        cmocka_unit_test(test_ply_byte_indices),
        cmocka_unit_test(test_ply_matches_obj),
        cmocka_unit_test(test_bad_ply),
        cmocka_unit_test(test_bad_scene),
        cmocka_unit_test(test_help_lists_formats),
    };
    return cmocka_run_group_tests_name("mesh2sdf_formats", tests, NULL, NULL);
}
