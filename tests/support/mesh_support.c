/* Meshes, brute-force geometry and mesh2sdf's dense output for the
 * converter's tests (mesh_support.h). */
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

void mesh_vertex(mesh *m, double x, double y, double z)
{
    if (m->nv == m->cap_v) {
        m->cap_v = m->cap_v ? 2 * m->cap_v : 256;
        m->v = realloc(m->v, sizeof(double) * 3 * (size_t)m->cap_v);
    }
    m->v[3 * m->nv] = x;
    m->v[3 * m->nv + 1] = y;
    m->v[3 * m->nv + 2] = z;
    m->nv++;
}

void mesh_triangle(mesh *m, int a, int b, int c)
{
    if (m->nt == m->cap_t) {
        m->cap_t = m->cap_t ? 2 * m->cap_t : 256;
        m->t = realloc(m->t, sizeof(int) * 3 * (size_t)m->cap_t);
    }
    m->t[3 * m->nt] = a;
    m->t[3 * m->nt + 1] = b;
    m->t[3 * m->nt + 2] = c;
    m->nt++;
}

void mesh_free(mesh *m)
{
    free(m->v);
    free(m->t);
    memset(m, 0, sizeof *m);
}

void mesh_add_slivers(mesh *m)
{
    const double tiny[2] = {0x1p-30, 0x1p-23}; /* below and above kThin */
    for (int i = 0; i < 2; i++) {
        const double z = i ? -0.75 : 0.75;
        mesh_vertex(m, -0.5, 0, z);
        mesh_vertex(m, 0.5, 0, z);
        mesh_vertex(m, 0, tiny[i], z);
        mesh_triangle(m, m->nv - 3, m->nv - 2, m->nv - 1);
    }
    const double tilt[2] = {0x1p-28, 0x1p-24};
    for (int i = 0; i < 2; i++) {
        const double x = i ? 0.875 : -0.875;
        mesh_vertex(m, x, -0.5, -0.375);
        mesh_vertex(m, x + 0.25, 0.5, 0.375);
        mesh_vertex(m, x + 0.125 + tilt[i], tilt[i], 0);
        mesh_triangle(m, m->nv - 3, m->nv - 2, m->nv - 1);
    }
}

/* Reads the v and f lines of an OBJ (v, v/t, v/t/n, v//n, negative
 * indices); polygons become fans. */
int read_obj(const char *path, mesh *m)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[4096];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == 'v' && line[1] == ' ') {
            double x, y, z;
            if (sscanf(line + 2, "%lf %lf %lf", &x, &y, &z) == 3)
                mesh_vertex(m, x, y, z);
        } else if (line[0] == 'f' && line[1] == ' ') {
            int idx[64], n = 0;
            char *s = line + 2;
            while (n < 64) {
                char *end;
                long i = strtol(s, &end, 10);
                if (end == s)
                    break;
                idx[n++] = (int)(i < 0 ? m->nv + i : i - 1);
                s = end;
                while (*s && *s != ' ' && *s != '\t' && *s != '\n' && *s != '\r')
                    s++;
            }
            for (int k = 1; k + 1 < n; k++)
                mesh_triangle(m, idx[0], idx[k], idx[k + 1]);
        }
    }
    fclose(f);
    return 0;
}

void write_off(const char *path, const mesh *m)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "OFF\n%d %d 0\n", m->nv, m->nt);
    for (int i = 0; i < m->nv; i++)
        fprintf(f, "%.17g %.17g %.17g\n", m->v[3 * i], m->v[3 * i + 1], m->v[3 * i + 2]);
    for (int i = 0; i < m->nt; i++)
        fprintf(f, "3 %d %d %d\n", m->t[3 * i], m->t[3 * i + 1], m->t[3 * i + 2]);
    fclose(f);
}

double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Squared distance from p to segment ab. */
double seg_dist2(const double *p, const double *a, const double *b)
{
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double s = dot3(ap, ab) / dot3(ab, ab);
    s = s < 0 ? 0 : s > 1 ? 1 : s;
    double d[3] = {ap[0] - s * ab[0], ap[1] - s * ab[1], ap[2] - s * ab[2]};
    return dot3(d, d);
}

/* Squared distance from p to triangle abc: the plane if p projects inside,
 * else the nearest edge. */
double tri_dist2(const double *p, const double *a, const double *b, const double *c)
{
    double e0[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e1[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3] = {e0[1] * e1[2] - e0[2] * e1[1], e0[2] * e1[0] - e0[0] * e1[2], e0[0] * e1[1] - e0[1] * e1[0]};
    const double *v[3] = {a, b, c};
    int inside = 1;
    for (int k = 0; k < 3; k++) {
        const double *u = v[k], *w = v[(k + 1) % 3];
        double e[3] = {w[0] - u[0], w[1] - u[1], w[2] - u[2]}, up[3] = {p[0] - u[0], p[1] - u[1], p[2] - u[2]};
        double cr[3] = {e[1] * up[2] - e[2] * up[1], e[2] * up[0] - e[0] * up[2], e[0] * up[1] - e[1] * up[0]};
        if (dot3(cr, n) < 0)
            inside = 0;
    }
    if (inside) {
        double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        double h = dot3(ap, n);
        return h * h / dot3(n, n);
    }
    double d = seg_dist2(p, a, b), d2 = seg_dist2(p, b, c), d3 = seg_dist2(p, c, a);
    return fmin(d, fmin(d2, d3));
}

/* Generalized winding number by brute force: Van Oosterom–Strackee solid
 * angle of every triangle over 4π. */
double winding(const mesh *m, const double *q)
{
    double w = 0;
    for (int t = 0; t < m->nt; t++) {
        double a[3], b[3], c[3];
        for (int k = 0; k < 3; k++) {
            a[k] = m->v[3 * m->t[3 * t] + k] - q[k];
            b[k] = m->v[3 * m->t[3 * t + 1] + k] - q[k];
            c[k] = m->v[3 * m->t[3 * t + 2] + k] - q[k];
        }
        double la = sqrt(dot3(a, a)), lb = sqrt(dot3(b, b)), lc = sqrt(dot3(c, c));
        double bc[3] = {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]};
        double det = dot3(a, bc);
        double den = la * lb * lc + dot3(a, b) * lc + dot3(b, c) * la + dot3(c, a) * lb;
        w += 2.0 * atan2(det, den);
    }
    return w / (4.0 * 3.14159265358979323846);
}

/* Brute force: the distance from p to the nearest triangle of m. */
double mesh_distance(const mesh *m, const double *p)
{
    double best = INFINITY;
    for (int t = 0; t < m->nt; t++)
        best = fmin(best, tri_dist2(p, &m->v[3 * m->t[3 * t]], &m->v[3 * m->t[3 * t + 1]], &m->v[3 * m->t[3 * t + 2]]));
    return sqrt(best);
}

double mesh_sdf(const mesh *m, const double *p)
{
    const double d = mesh_distance(m, p);
    return winding(m, p) > 0.5 ? -d : d;
}

double json_number(const char *json, const char *key, int index)
{
    const char *s = strstr(json, key);
    assert_non_null(s);
    s = strchr(s, ':');
    assert_non_null(s);
    s++;
    while (*s == ' ' || *s == '[')
        s++;
    for (int i = 0; i < index; i++) {
        s = strchr(s, ',');
        assert_non_null(s);
        s++;
    }
    return strtod(s, NULL);
}

void read_dense(const char *npy, dense *g)
{
    FILE *f = fopen(npy, "rb");
    assert_non_null(f);
    unsigned char pre[10];
    assert_int_equal(fread(pre, 1, 10, f), 10);
    assert_memory_equal(pre, "\x93NUMPY\x01\x00", 8);
    size_t hlen = pre[8] | (size_t)pre[9] << 8;
    assert_int_equal((10 + hlen) % 64, 0);
    char *header = calloc(hlen + 1, 1);
    assert_int_equal(fread(header, 1, hlen, f), hlen);
    assert_non_null(strstr(header, "'descr': '<f4'"));
    assert_non_null(strstr(header, "'fortran_order': False"));
    const char *shape = strstr(header, "'shape': (");
    assert_non_null(shape);
    assert_int_equal(sscanf(shape, "'shape': (%d, %d, %d)", &g->n[0], &g->n[1], &g->n[2]), 3);
    free(header);
    size_t count = (size_t)g->n[0] * g->n[1] * g->n[2];
    g->data = malloc(count * sizeof(float));
    assert_int_equal(fread(g->data, sizeof(float), count, f), count);
    fclose(f);

    char json_path[1024];
    snprintf(json_path, sizeof json_path, "%.*s.json", (int)(strlen(npy) - 4), npy);
    f = fopen(json_path, "r");
    assert_non_null(f);
    char json[4096];
    size_t got = fread(json, 1, sizeof json - 1, f);
    json[got] = '\0';
    fclose(f);
    for (int k = 0; k < 3; k++) {
        g->origin[k] = json_number(json, "\"origin\"", k);
        assert_int_equal((int)json_number(json, "\"shape\"", k), g->n[k]);
    }
    g->h = json_number(json, "\"voxel_size\"", 0);
    assert_true(g->h > 0);
}

float dense_at(const dense *g, int i, int j, int k) { return g->data[((size_t)i * g->n[1] + j) * g->n[2] + k]; }

void dense_point(const dense *g, int i, int j, int k, double *p)
{
    p[0] = g->origin[0] + i * g->h;
    p[1] = g->origin[1] + j * g->h;
    p[2] = g->origin[2] + k * g->h;
}

/* Runs mesh2sdf on `in` with extra flags, writing NAME.vdb and NAME.npy in
 * the test folder, and reads the dense grid back. */
void convert(const char *in, const char *name, const char *flags, dense *g)
{
    char vdb[512], npy[512], out[8192], file[256];
    snprintf(file, sizeof file, "%s.vdb", name);
    tu_tmp(vdb, sizeof vdb, file);
    snprintf(file, sizeof file, "%s.npy", name);
    tu_tmp(npy, sizeof npy, file);
    int rc = tu_run(out, sizeof out, "%s '%s' -o '%s' --npy '%s' --quiet %s", SDFT_MESH2SDF, in, vdb, npy, flags);
    if (rc != 0)
        fail_msg("mesh2sdf failed (%d): %s", rc, out);
    read_dense(npy, g);
}
