/* sdftrace tests — the SDF toolkit (include/sdftrace/sdf.h) against
 * independent truth: closest points found by clamping, distances to dense
 * samplings of each surface, the dodecahedron as a polytope built from its
 * vertices, and brute-force minima over every copy of a repeated shape. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "sdftrace/sdf.h"
#include "testutil.h"

#define N_POINTS 2000
#define PI 3.14159265358979323846

/* Fails with the numbers when |got - want| > tol. */
#define assert_close(got, want, tol)                                                                                   \
    do {                                                                                                               \
        double g_ = (got), w_ = (want);                                                                                \
        if (!(fabs(g_ - w_) <= (tol))) {                                                                               \
            print_error("%s = %.7g, want %.7g (tol %.2g) at line %d\n", #got, g_, w_, (double)(tol), __LINE__);        \
            fail();                                                                                                    \
        }                                                                                                              \
    } while (0)

static sdft_vec3 rand_point(tu_rng *r, float extent)
{
    return sdft_v3(tu_uniform(r, -extent, extent), tu_uniform(r, -extent, extent), tu_uniform(r, -extent, extent));
}

static sdft_vec3 rand_unit(tu_rng *r)
{
    for (;;) {
        sdft_vec3 v = rand_point(r, 1.0f);
        float l = sdft_length(v);
        if (l > 0.1f && l <= 1.0f)
            return sdft_scale(v, 1.0f / l);
    }
}

static double dist3(sdft_vec3 a, sdft_vec3 b)
{
    double x = (double)a.x - b.x, y = (double)a.y - b.y, z = (double)a.z - b.z;
    return sqrt(x * x + y * y + z * z);
}

/* ---- surface samplings: brute-force distance ------------------------- */

typedef struct samples {
    sdft_vec3 *p;
    size_t n, cap;
} samples;

static void push(samples *s, float x, float y, float z)
{
    if (s->n == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 4096;
        s->p = realloc(s->p, s->cap * sizeof *s->p);
        assert_non_null(s->p);
    }
    s->p[s->n++] = sdft_v3(x, y, z);
}

static double nearest_sample(const samples *s, sdft_vec3 p)
{
    double best = INFINITY;
    for (size_t i = 0; i < s->n; i++) {
        double d = dist3(s->p[i], p);
        best = d < best ? d : best;
    }
    return best;
}

/* Checks f against +-(distance to the samples) at random points: the sampled
 * distance overestimates the true one by at most `spacing`. */
static void check_against_samples(const samples *s, float (*f)(sdft_vec3), int (*inside)(sdft_vec3), float extent,
                                  double spacing, int points)
{
    tu_rng rng = tu_rng_seed(11);
    for (int i = 0; i < points; i++) {
        sdft_vec3 p = rand_point(&rng, extent);
        double truth = nearest_sample(s, p) * (inside(p) ? -1.0 : 1.0);
        assert_close(f(p), truth, spacing);
    }
}

/* ---- primitives -------------------------------------------------------- */

static void test_sphere(void **state)
{
    (void)state;
    tu_rng rng = tu_rng_seed(1);
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 p = rand_point(&rng, 3.0f);
        sdft_vec3 nearest = sdft_scale(sdft_normalize(p), 1.25f); /* radial projection onto the sphere */
        double truth = dist3(p, nearest) * (sdft_length(p) < 1.25f ? -1.0 : 1.0);
        assert_close(sdft_sd_sphere(p, 1.25f), truth, 1e-5);
    }
}

/* Distance to a box by clamping: outside, the nearest point is p clamped to
 * the box; inside, the nearest face is the one with the least slack. */
static double box_truth(sdft_vec3 p, sdft_vec3 b)
{
    sdft_vec3 c = sdft_v3(fminf(fmaxf(p.x, -b.x), b.x), fminf(fmaxf(p.y, -b.y), b.y), fminf(fmaxf(p.z, -b.z), b.z));
    if (fabsf(p.x) > b.x || fabsf(p.y) > b.y || fabsf(p.z) > b.z)
        return dist3(p, c);
    double slack = fmin(b.x - fabsf(p.x), fmin(b.y - fabsf(p.y), b.z - fabsf(p.z)));
    return -slack;
}

static void test_box_and_round_box(void **state)
{
    (void)state;
    tu_rng rng = tu_rng_seed(2);
    const sdft_vec3 half = {0.7f, 0.4f, 1.1f};
    const float radius = 0.15f;
    const sdft_vec3 inner = sdft_sub(half, sdft_v3(radius, radius, radius));
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 p = rand_point(&rng, 2.0f);
        assert_close(sdft_sd_box(p, half), box_truth(p, half), 1e-5);
        /* A rounded box is the inner box grown by a ball of `radius`. */
        assert_close(sdft_sd_round_box(p, half, radius), box_truth(p, inner) - radius, 1e-5);
    }
}

static float torus_f(sdft_vec3 p) { return sdft_sd_torus(p, 0.8f, 0.25f); }
static int torus_in(sdft_vec3 p)
{
    double ring = hypot(p.x, p.z) - 0.8;
    return ring * ring + (double)p.y * p.y < 0.25 * 0.25;
}

static void test_torus(void **state)
{
    (void)state;
    samples s = {0};
    const int nu = 2400, nv = 240;
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            double u = 2 * PI * i / nu, v = 2 * PI * j / nv, rho = 0.8 + 0.25 * cos(v);
            push(&s, (float)(rho * cos(u)), (float)(0.25 * sin(v)), (float)(rho * sin(u)));
        }
    check_against_samples(&s, torus_f, torus_in, 1.5f, 4e-3, 300);
    free(s.p);
}

static float cylinder_f(sdft_vec3 p) { return sdft_sd_cylinder(p, 0.5f, 0.8f); }
static int cylinder_in(sdft_vec3 p) { return hypot(p.x, p.z) < 0.5 && fabsf(p.y) < 0.8f; }

static void test_cylinder(void **state)
{
    (void)state;
    samples s = {0};
    const int nt = 1200;
    for (int i = 0; i < nt; i++) {
        double t = 2 * PI * i / nt, c = cos(t), sn = sin(t);
        for (int j = 0; j <= 400; j++) /* side */
            push(&s, (float)(0.5 * c), -0.8f + 1.6f * (float)j / 400.0f, (float)(0.5 * sn));
        for (int j = 0; j <= 200; j++) { /* caps */
            double rho = 0.5 * j / 200.0;
            push(&s, (float)(rho * c), 0.8f, (float)(rho * sn));
            push(&s, (float)(rho * c), -0.8f, (float)(rho * sn));
        }
    }
    check_against_samples(&s, cylinder_f, cylinder_in, 1.5f, 3e-3, 300);
    free(s.p);

    /* And in closed form: the nearest point of a solid cylinder clamps the
     * radius to r and the height to +-h; inside, the nearer of side and cap. */
    tu_rng rng = tu_rng_seed(3);
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 p = rand_point(&rng, 1.5f);
        double rho = hypot(p.x, p.z), truth;
        if (rho < 0.5 && fabsf(p.y) < 0.8f)
            truth = -fmin(0.5 - rho, 0.8 - fabsf(p.y));
        else
            truth = hypot(fmax(rho - 0.5, 0.0), fmax(fabsf(p.y) - 0.8, 0.0));
        assert_close(sdft_sd_cylinder(p, 0.5f, 0.8f), truth, 1e-5);
    }
}

static void test_capsule(void **state)
{
    (void)state;
    const sdft_vec3 a = {-0.3f, 0.2f, 0.5f}, b = {0.6f, -0.4f, -0.2f};
    tu_rng rng = tu_rng_seed(4);
    for (int i = 0; i < 500; i++) {
        sdft_vec3 p = rand_point(&rng, 1.5f);
        double best = INFINITY; /* nearest of 20001 points along the segment */
        for (int k = 0; k <= 20000; k++)
            best = fmin(best, dist3(p, sdft_madd(a, sdft_sub(b, a), (float)k / 20000.0f)));
        assert_close(sdft_sd_capsule(p, a, b, 0.3f), best - 0.3, 1e-4);
    }
}

/* The plane dot(p, n) + d = 0 built from a point on it, q0 = -d n, and two
 * unit vectors u, v spanning it: the nearest point of the plane to p is q0
 * plus p's components along u and v, so the distance is |p - foot| (in
 * double), negative on the side opposite n. (Checking sdft_sd_plane against
 * itself, at the foot it computes, would pass for a function returning 0.) */
static void test_plane(void **state)
{
    (void)state;
    tu_rng rng = tu_rng_seed(5);
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 n = rand_unit(&rng), p = rand_point(&rng, 3.0f);
        float d = tu_uniform(&rng, -1.0f, 1.0f);
        sdft_vec3 u = sdft_normalize(sdft_cross(n, rand_unit(&rng))), v = sdft_cross(n, u);
        sdft_vec3 q0 = sdft_scale(n, -d), r = sdft_sub(p, q0);
        sdft_vec3 foot = sdft_add(q0, sdft_add(sdft_scale(u, sdft_dot(r, u)), sdft_scale(v, sdft_dot(r, v))));
        double truth = dist3(p, foot) * (sdft_dot(sdft_sub(p, foot), n) < 0.0f ? -1.0 : 1.0);
        assert_close(sdft_sd_plane(p, n, d), truth, 1e-5);
        /* and any other point of the plane is farther away */
        sdft_vec3 other = sdft_add(foot, sdft_scale(u, tu_uniform(&rng, -1.0f, 1.0f)));
        assert_true(dist3(p, other) >= fabs(truth) - 1e-5);
    }
}

static float ellipsoid_f(sdft_vec3 p) { return sdft_sd_ellipsoid(p, sdft_v3(0.3f, 0.6f, 0.45f)); }
static int ellipsoid_in(sdft_vec3 p)
{
    return (p.x / 0.3) * (p.x / 0.3) + (p.y / 0.6) * (p.y / 0.6) + (p.z / 0.45) * (p.z / 0.45) < 1.0;
}

static void test_ellipsoid_is_a_bound(void **state)
{
    (void)state;
    samples s = {0};
    const int nu = 1600, nv = 800;
    for (int i = 0; i < nu; i++)
        for (int j = 0; j <= nv; j++) {
            double u = 2 * PI * i / nu, v = PI * j / nv;
            push(&s, (float)(0.3 * sin(v) * cos(u)), (float)(0.6 * cos(v)), (float)(0.45 * sin(v) * sin(u)));
        }
    tu_rng rng = tu_rng_seed(6);
    for (int i = 0; i < 400; i++) {
        sdft_vec3 p = rand_point(&rng, 1.2f);
        double truth = nearest_sample(&s, p);
        float f = ellipsoid_f(p);
        assert_int_equal(f < 0.0f, ellipsoid_in(p));
        assert_true(fabs(f) <= truth + 1e-5);
    }
    free(s.p);
    /* Exact along the shortest semi-axis. */
    assert_close(ellipsoid_f(sdft_v3(0.8f, 0, 0)), 0.5, 1e-6);
}

/* ---- the dodecahedron, built independently from its 20 vertices -------- */

typedef struct face {
    sdft_vec3 n;    /* unit outward normal */
    double offset;  /* plane: dot(p, n) = offset */
    sdft_vec3 v[5]; /* corners in order around n */
} face;

static int build_dodecahedron(face faces[12], float inradius)
{
    const float phi = (1.0f + sqrtf(5.0f)) / 2.0f, iphi = 1.0f / phi;
    sdft_vec3 v[20];
    int nv = 0;
    for (int s = 0; s < 8; s++) /* (+-1, +-1, +-1) */
        v[nv++] = sdft_v3(s & 1 ? -1 : 1, s & 2 ? -1 : 1, s & 4 ? -1 : 1);
    for (int s = 0; s < 4; s++) { /* cyclic (0, +-phi, +-1/phi): faces normal to (0, 1, phi) and kin */
        float a = s & 1 ? -iphi : iphi, b = s & 2 ? -phi : phi;
        v[nv++] = sdft_v3(0, b, a), v[nv++] = sdft_v3(b, a, 0), v[nv++] = sdft_v3(a, 0, b);
    }
    /* Faces: any 3 vertices whose plane has all 20 on one side and exactly 5
     * on it. Collect each such plane once. */
    int nf = 0;
    for (int i = 0; i < 20; i++)
        for (int j = i + 1; j < 20; j++)
            for (int k = j + 1; k < 20; k++) {
                sdft_vec3 n = sdft_normalize(sdft_cross(sdft_sub(v[j], v[i]), sdft_sub(v[k], v[i])));
                double off = sdft_dot(n, v[i]);
                if (off < 0)
                    n = sdft_scale(n, -1.0f), off = -off;
                int on = 0, above = 0;
                for (int m = 0; m < 20; m++) {
                    double e = sdft_dot(n, v[m]) - off;
                    if (fabs(e) < 1e-4)
                        on++;
                    else if (e > 0)
                        above++;
                }
                if (above || on != 5)
                    continue;
                int seen = 0;
                for (int f = 0; f < nf; f++)
                    seen |= sdft_dot(faces[f].n, n) > 0.9999f;
                if (seen)
                    continue;
                face *f = &faces[nf++];
                f->n = n, f->offset = off;
                int c = 0;
                for (int m = 0; m < 20; m++)
                    if (fabs(sdft_dot(n, v[m]) - off) < 1e-4)
                        f->v[c++] = v[m];
                /* order the corners by angle around the face centre */
                sdft_vec3 ctr = sdft_scale(n, (float)off), e0 = sdft_normalize(sdft_sub(f->v[0], ctr));
                sdft_vec3 e1 = sdft_cross(n, e0);
                for (int a = 0; a < 5; a++)
                    for (int b = a + 1; b < 5; b++) {
                        sdft_vec3 da = sdft_sub(f->v[a], ctr), db = sdft_sub(f->v[b], ctr);
                        if (atan2(sdft_dot(db, e1), sdft_dot(db, e0)) < atan2(sdft_dot(da, e1), sdft_dot(da, e0))) {
                            sdft_vec3 t = f->v[a];
                            f->v[a] = f->v[b], f->v[b] = t;
                        }
                    }
            }
    /* scale to the wanted inradius */
    for (int f = 0; f < nf; f++) {
        float s = inradius / (float)faces[f].offset;
        faces[f].offset = inradius;
        for (int c = 0; c < 5; c++)
            faces[f].v[c] = sdft_scale(faces[f].v[c], s);
    }
    return nf;
}

static double segment_distance(sdft_vec3 p, sdft_vec3 a, sdft_vec3 b)
{
    sdft_vec3 ab = sdft_sub(b, a);
    double t = sdft_dot(sdft_sub(p, a), ab) / sdft_dot(ab, ab);
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return dist3(p, sdft_madd(a, ab, (float)t));
}

/* Distance from p to a convex pentagon: to its plane if p projects inside,
 * else to the nearest edge. */
static double face_distance(const face *f, sdft_vec3 p)
{
    double h = sdft_dot(p, f->n) - f->offset;
    sdft_vec3 proj = sdft_madd(p, f->n, (float)-h);
    int inside = 1;
    for (int c = 0; c < 5; c++) {
        sdft_vec3 e = sdft_sub(f->v[(c + 1) % 5], f->v[c]);
        inside &= sdft_dot(sdft_cross(e, sdft_sub(proj, f->v[c])), f->n) >= 0.0f;
    }
    if (inside)
        return fabs(h);
    double best = INFINITY;
    for (int c = 0; c < 5; c++)
        best = fmin(best, segment_distance(p, f->v[c], f->v[(c + 1) % 5]));
    return best;
}

static void test_dodecahedron_bound(void **state)
{
    (void)state;
    const float r = 0.9f;
    face faces[12];
    assert_int_equal(build_dodecahedron(faces, r), 12);
    tu_rng rng = tu_rng_seed(7);
    int outside = 0;
    for (int i = 0; i < 20000; i++) {
        sdft_vec3 p = rand_point(&rng, 2.5f);
        double truth = INFINITY;
        int in = 1;
        for (int f = 0; f < 12; f++) {
            truth = fmin(truth, face_distance(&faces[f], p));
            in &= sdft_dot(p, faces[f].n) < faces[f].offset;
        }
        float bound = sdft_sd_dodecahedron(p, r);
        if (in) { /* inside a convex body the nearest boundary point is on a face plane: exact */
            assert_close(bound, -truth, 1e-5);
        } else {
            outside++;
            assert_true(bound >= 0.0f);
            if (!(bound <= truth + 1e-5))
                print_error("bound %.7g exceeds true distance %.7g\n", (double)bound, truth);
            assert_true(bound <= truth + 1e-5);
        }
    }
    assert_true(outside > 10000);
    /* Exact along every face normal, in front of the face. */
    for (int f = 0; f < 12; f++)
        for (float s = 0.05f; s < 2.0f; s += 0.25f) {
            sdft_vec3 p = sdft_scale(faces[f].n, r + s);
            assert_close(sdft_sd_dodecahedron(p, r), s, 1e-5);
            assert_close(face_distance(&faces[f], p), s, 1e-5);
        }
}

/* ---- operators ---------------------------------------------------------- */

static void test_boolean_operators_follow_sets(void **state)
{
    (void)state;
    tu_rng rng = tu_rng_seed(8);
    const sdft_vec3 half = {0.6f, 0.6f, 0.6f}, c = {0.5f, 0.3f, 0.0f};
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 p = rand_point(&rng, 1.5f);
        float box = sdft_sd_box(p, half), ball = sdft_sd_sphere(sdft_translate(p, c), 0.5f);
        int in_box = fabsf(p.x) < half.x && fabsf(p.y) < half.y && fabsf(p.z) < half.z;
        int in_ball = dist3(p, c) < 0.5;
        assert_int_equal(sdft_op_union(box, ball) < 0.0f, in_box || in_ball);
        assert_int_equal(sdft_op_intersect(box, ball) < 0.0f, in_box && in_ball);
        assert_int_equal(sdft_op_subtract(ball, box) < 0.0f, in_box && !in_ball);
    }
}

static void test_smooth_union(void **state)
{
    (void)state;
    tu_rng rng = tu_rng_seed(9);
    const float k = 0.3f;
    const sdft_vec3 c0 = {-0.4f, 0, 0}, c1 = {0.45f, 0.1f, 0};
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 p = rand_point(&rng, 1.5f), q = sdft_madd(p, rand_unit(&rng), tu_uniform(&rng, 1e-3f, 0.3f));
        float a = sdft_sd_sphere(sdft_translate(p, c0), 0.4f), b = sdft_sd_sphere(sdft_translate(p, c1), 0.35f);
        float s = sdft_op_smooth_union(a, b, k);
        assert_true(s <= fminf(a, b) + 1e-6f);
        assert_true(s >= fminf(a, b) - 0.25f * k - 1e-6f);
        if (fabsf(a - b) >= k)
            assert_close(s, fminf(a, b), 1e-6);
        float sq = sdft_op_smooth_union(sdft_sd_sphere(sdft_translate(q, c0), 0.4f),
                                        sdft_sd_sphere(sdft_translate(q, c1), 0.35f), k);
        assert_true(fabs(s - sq) <= dist3(p, q) * (1 + 1e-4) + 1e-6); /* still 1-Lipschitz */
    }
}

static void test_near_bound_is_continuous(void **state)
{
    (void)state;
    /* A sphere early-out around a box: both branches meet where bound == k. */
    const float k = 0.2f;
    tu_rng rng = tu_rng_seed(10);
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 p = rand_point(&rng, 2.0f), q = sdft_madd(p, rand_unit(&rng), tu_uniform(&rng, 1e-3f, 0.1f));
        float bp = sdft_sd_sphere(p, 0.9f), bq = sdft_sd_sphere(q, 0.9f);
        float fp = bp > k ? bp : sdft_op_near_bound(bp, sdft_sd_box(p, sdft_v3(0.5f, 0.5f, 0.5f)), k);
        float fq = bq > k ? bq : sdft_op_near_bound(bq, sdft_sd_box(q, sdft_v3(0.5f, 0.5f, 0.5f)), k);
        assert_true(fabs(fp - fq) <= dist3(p, q) * (1 + 1e-4) + 1e-6);
        assert_true(fp <= box_truth(p, sdft_v3(0.5f, 0.5f, 0.5f)) + 1e-5);
        assert_int_equal(fp < 0.0f, box_truth(p, sdft_v3(0.5f, 0.5f, 0.5f)) < 0.0);
    }
}

/* ---- transforms --------------------------------------------------------- */

static void test_rotation(void **state)
{
    (void)state;
    tu_rng rng = tu_rng_seed(12);
    for (int i = 0; i < 200; i++) {
        sdft_vec3 axis = rand_unit(&rng);
        float angle = tu_uniform(&rng, -3.0f, 3.0f);
        sdft_mat3 m = sdft_mat3_rotation(axis, angle);
        /* orthonormal rows, axis fixed, angle between a perpendicular and its image */
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                double dot = 0;
                for (int k = 0; k < 3; k++)
                    dot += (double)m.m[r][k] * m.m[c][k];
                assert_close(dot, r == c ? 1.0 : 0.0, 1e-5);
            }
        sdft_vec3 fixed = sdft_mat3_apply(&m, axis);
        assert_close(dist3(fixed, axis), 0.0, 1e-5);
        sdft_vec3 perp = sdft_normalize(sdft_cross(axis, rand_unit(&rng)));
        sdft_vec3 turned = sdft_mat3_apply(&m, perp);
        assert_close(atan2(sdft_dot(sdft_cross(perp, turned), axis), sdft_dot(perp, turned)), angle, 1e-4);
        /* a sphere centred at c, rotated by m, is centred at m c */
        sdft_vec3 c = rand_point(&rng, 1.0f), p = rand_point(&rng, 2.0f);
        float f = sdft_sd_sphere(sdft_translate(sdft_rotate(p, &m), c), 0.3f);
        assert_close(f, dist3(p, sdft_mat3_apply(&m, c)) - 0.3, 1e-5);
        /* rotate_y is the rotation about +y */
        sdft_mat3 y = sdft_mat3_rotation(sdft_v3(0, 1, 0), angle);
        assert_close(dist3(sdft_rotate_y(p, angle), sdft_rotate(p, &y)), 0.0, 1e-5);
    }
    /* right-handed: a quarter turn about +y takes +x to -z */
    sdft_mat3 q = sdft_mat3_rotation(sdft_v3(0, 1, 0), (float)(PI / 2));
    assert_close(dist3(sdft_mat3_apply(&q, sdft_v3(1, 0, 0)), sdft_v3(0, 0, -1)), 0.0, 1e-6);
}

static void test_uniform_scale(void **state)
{
    (void)state;
    tu_rng rng = tu_rng_seed(13);
    const sdft_vec3 half = {0.3f, 0.5f, 0.2f};
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 p = rand_point(&rng, 3.0f);
        float s = tu_uniform(&rng, 0.2f, 4.0f);
        float scaled = sdft_scaled_distance(sdft_sd_box(sdft_scaled_point(p, s), half), s);
        assert_close(scaled, box_truth(p, sdft_scale(half, s)), 1e-5 * (1 + s));
    }
}

/* Brute force: the nearest of every copy of a sphere of radius r centred at
 * the given cell centres. */
static double nearest_copy(sdft_vec3 p, const sdft_vec3 *centres, int n, float r)
{
    double best = INFINITY;
    for (int i = 0; i < n; i++)
        best = fmin(best, dist3(p, centres[i]) - r);
    return best;
}

static void test_repetition(void **state)
{
    (void)state;
    tu_rng rng = tu_rng_seed(14);
    sdft_vec3 centres[2000];
    /* infinite: period 1 in x, 1.5 in y, none in z; copies within +-8 cells suffice */
    int n = 0;
    for (int i = -8; i <= 8; i++)
        for (int j = -8; j <= 8; j++)
            centres[n++] = sdft_v3((float)i, 1.5f * (float)j, 0.2f);
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 p = rand_point(&rng, 4.0f);
        sdft_vec3 q = sdft_translate(sdft_op_repeat(p, sdft_v3(1.0f, 1.5f, 0.0f)), sdft_v3(0, 0, 0.2f));
        assert_close(sdft_sd_sphere(q, 0.35f), nearest_copy(p, centres, n, 0.35f), 1e-5);
    }
    /* limited: cells -2..2 in x and -3..3 in z, period 1.2 */
    n = 0;
    for (int i = -2; i <= 2; i++)
        for (int k = -3; k <= 3; k++)
            centres[n++] = sdft_v3(1.2f * (float)i, 0, 1.2f * (float)k);
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 p = rand_point(&rng, 7.0f);
        sdft_vec3 q = sdft_op_repeat_limited(p, sdft_v3(1.2f, 0, 1.2f), sdft_v3(2, 0, 3));
        assert_close(sdft_sd_sphere(q, 0.4f), nearest_copy(p, centres, n, 0.4f), 1e-5);
    }
    /* angular: 7 spheres around y at radius 1 */
    n = 0;
    for (int i = 0; i < 7; i++)
        centres[n++] = sdft_rotate_y(sdft_v3(1, 0.1f, 0), (float)(2 * PI * i / 7));
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 p = rand_point(&rng, 2.0f);
        sdft_vec3 q = sdft_translate(sdft_op_repeat_angular_y(p, 7), sdft_v3(1, 0.1f, 0));
        assert_close(sdft_sd_sphere(q, 0.3f), nearest_copy(p, centres, n, 0.3f), 1e-5);
    }
}

/* Boxes that differ per cell (sizes by cell index), each >= 0.25 inside its
 * 2-wide cell: the cell-wall bound never exceeds the distance to the nearest
 * box of any cell, has the right sign, and is 1-Lipschitz. */
static sdft_vec3 cell_box(int ix, int iz)
{
    return sdft_v3(0.3f + 0.1f * (float)((ix * 7 + iz * 3) & 3), 0.2f + 0.3f * (float)((ix + 5 * iz) & 3),
                   0.75f - 0.1f * (float)((ix * 5 + iz) & 3));
}

static float cell_field(sdft_vec3 p)
{
    sdft_cell c = sdft_cell_locate(p, sdft_v3(2, 0, 2), sdft_v3(3, 0, 2));
    return sdft_cell_bound(&c, sdft_sd_box(c.q, cell_box(c.ix, c.iz)), 0.25f);
}

static void test_cell_wall_bound(void **state)
{
    (void)state;
    tu_rng rng = tu_rng_seed(15);
    for (int i = 0; i < N_POINTS; i++) {
        sdft_vec3 p = rand_point(&rng, 9.0f);
        double truth = INFINITY;
        for (int ix = -3; ix <= 3; ix++)
            for (int iz = -2; iz <= 2; iz++)
                truth = fmin(truth, box_truth(sdft_translate(p, sdft_v3(2.0f * ix, 0, 2.0f * iz)), cell_box(ix, iz)));
        float f = cell_field(p);
        assert_int_equal(f < 0.0f, truth < 0.0);
        assert_true(f <= truth + 1e-5);
        if (truth < 0.0)
            assert_close(f, truth, 1e-5); /* inside, the own box is the only one */
        sdft_vec3 q = sdft_madd(p, rand_unit(&rng), tu_uniform(&rng, 1e-3f, 0.5f));
        assert_true(fabsf(f - cell_field(q)) <= dist3(p, q) * (1 + 1e-4) + 1e-5);
    }
    /* The located cell and its walls. */
    sdft_cell c = sdft_cell_locate(sdft_v3(2.7f, 5.0f, -9.0f), sdft_v3(2, 0, 2), sdft_v3(3, 0, 2));
    assert_int_equal(c.ix, 1);
    assert_int_equal(c.iz, -2);
    assert_close(c.q.x, 0.7, 1e-6);
    assert_close(c.q.z, -5.0, 1e-6);
    assert_close(c.wall, 0.3, 1e-6); /* the x wall towards cell 2; nothing lies beyond z = -5 */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_box_and_round_box),
        cmocka_unit_test(test_torus),
        cmocka_unit_test(test_cylinder),
        cmocka_unit_test(test_capsule),
        cmocka_unit_test(test_plane),
        cmocka_unit_test(test_ellipsoid_is_a_bound),
        cmocka_unit_test(test_dodecahedron_bound),
        cmocka_unit_test(test_boolean_operators_follow_sets),
        cmocka_unit_test(test_smooth_union),
        cmocka_unit_test(test_near_bound_is_continuous),
        cmocka_unit_test(test_rotation),
        cmocka_unit_test(test_uniform_scale),
        cmocka_unit_test(test_repetition),
        cmocka_unit_test(test_cell_wall_bound),
    };
    return cmocka_run_group_tests_name("sdf", tests, NULL, NULL);
}
