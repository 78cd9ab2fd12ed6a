/* Tests of refraction (src/core/secondary.h, render_whitted.c's path
 * through glass): a glass sphere and a glass slab traced in, through and
 * out as the renderer traces them, against Snell's law and the exit
 * points worked out here from the geometry; total internal reflection
 * exactly where Snell's law leaves no refracted ray. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>

#include "sdftrace/trace.h"
#include "secondary.h"

static const float IOR = 1.5f;

static float sphere_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)s;
    return sdft_length(p) - *(const float *)ctx;
}

/* A slab |z - h/2| <= h/2, wide in x and y (the box 40 x 40 x h). */
static float slab_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)s;
    const float h = *(const float *)ctx;
    const sdft_vec3 q = sdft_sub(sdft_abs3(sdft_sub(p, sdft_v3(0, 0, 0.5f * h))), sdft_v3(20, 20, 0.5f * h));
    return sdft_length(sdft_max3(q, 0.0f)) + fminf(sdft_maxcomp(q), 0.0f);
}

static sdft_field make_field(float (*distance)(const void *, sdft_scratch *, sdft_vec3), const float *size)
{
    sdft_field f = sdft_field_defaults();
    f.distance = distance;
    f.ctx = size;
    f.bounds = (sdft_aabb){{-30, -30, -30}, {30, 30, 30}};
    f.feature_size = 1e-4f;
    return f;
}

/* Snell's law by angles, independent of the vector form under test: the
 * refracted direction of unit d at unit normal n (facing d's origin) from
 * index n1 into n2, in the plane of d and n. */
static sdft_vec3 snell_by_angles(sdft_vec3 d, sdft_vec3 n, float n1, float n2)
{
    const double cos_i = -sdft_dot(d, n), theta_i = acos(cos_i);
    const double theta_t = asin(n1 / n2 * sin(theta_i));
    const sdft_vec3 tangent = sdft_normalize(sdft_madd(d, n, (float)cos_i)); /* d's part along the surface */
    return sdft_add(sdft_scale(n, (float)-cos(theta_t)), sdft_scale(tangent, (float)sin(theta_t)));
}

static void assert_close3(sdft_vec3 a, sdft_vec3 b, float tol)
{
    const float e = sdft_length(sdft_sub(a, b));
    if (!(e <= tol))
        fail_msg("(%g %g %g) vs (%g %g %g): %g apart, tolerance %g", a.x, a.y, a.z, b.x, b.y, b.z, e, tol);
}

/* The ray traced into the surface, refracted, traced through the inside
 * with f flipped from eps_dynamic inside, and refracted out, as
 * render_whitted does: the entry, the inside direction, the exit and the
 * direction out. */
typedef struct passage {
    sdft_vec3 entry, inside, exit, out;
} passage;

static passage pass_through(const sdft_field *f, sdft_vec3 org, sdft_vec3 dir)
{
    sdft_scratch s;
    sdft_scratch_init(f, &s);
    sdft_trace_params tp = sdft_trace_defaults();
    tp.method = SDFT_SPHERE, tp.eps = 1e-5f;
    const sdft_ray ray = {org, 0.0f, dir, INFINITY};
    const sdft_hit h = sdft_trace(f, &s, &ray, &tp);
    assert_int_equal(h.status, SDFT_HIT);
    passage ps;
    ps.entry = sdft_madd(org, dir, h.t);
    const sdft_vec3 n = sdft_field_normal(f, &s, ps.entry);
    assert_true(secondary_refract(dir, n, 1.0f / IOR, &ps.inside));
    const sdft_field in = secondary_inside(f);
    const float eps = secondary_eps(1e-4f, h.distance);
    const sdft_ray through = {sdft_madd(ps.entry, n, -eps), 0.0f, ps.inside, INFINITY};
    const sdft_hit e = sdft_trace(&in, &s, &through, &tp);
    assert_int_equal(e.status, SDFT_HIT);
    ps.exit = sdft_madd(through.org, through.dir, e.t);
    const sdft_vec3 n_exit = sdft_field_normal(f, &s, ps.exit);
    assert_true(secondary_refract(ps.inside, sdft_scale(n_exit, -1.0f), IOR, &ps.out));
    return ps;
}

static void glass_sphere_matches_snell_and_its_chord(void **state)
{
    (void)state;
    const float radius = 1.0f;
    const sdft_field f = make_field(sphere_distance, &radius);
    for (int k = 0; k < 9; k++) {
        const float b = 0.1f * (float)k; /* impact parameter */
        const sdft_vec3 org = sdft_v3(b, 0.0f, -5.0f), dir = sdft_v3(0, 0, 1);
        const passage ps = pass_through(&f, org, dir);
        /* Entry where the line meets the sphere; inside along Snell's angle; the chord from a
         * point of the sphere at angle theta_t to the inward normal is 2 R cos(theta_t). */
        const sdft_vec3 entry = sdft_v3(b, 0.0f, -sqrtf(radius * radius - b * b));
        const sdft_vec3 n = sdft_scale(entry, 1.0f / radius);
        const sdft_vec3 inside = snell_by_angles(dir, n, 1.0f, IOR);
        const float chord = 2.0f * radius * -sdft_dot(inside, n); /* 2 R cos(theta_t) */
        const sdft_vec3 exit = sdft_madd(entry, inside, chord);
        assert_close3(ps.entry, entry, 1e-4f);
        assert_close3(ps.inside, inside, 5e-4f); /* float differences for the normal */
        assert_close3(ps.exit, exit, 1e-3f);
        /* Out at the incidence angle, symmetric about the exit normal. */
        const sdft_vec3 n_exit = sdft_scale(exit, 1.0f / radius);
        assert_close3(ps.out, snell_by_angles(inside, sdft_scale(n_exit, -1.0f), IOR, 1.0f), 1e-3f);
        assert_float_equal(sdft_dot(ps.out, n_exit), -sdft_dot(dir, n), 1e-3f); /* cos(theta_i) */
    }
}

static void glass_slab_shifts_the_ray_and_keeps_its_direction(void **state)
{
    (void)state;
    const float h = 0.5f;
    const sdft_field f = make_field(slab_distance, &h);
    for (int k = 0; k < 6; k++) {
        const float theta = 0.15f * (float)k; /* incidence angle */
        const sdft_vec3 dir = sdft_v3(sinf(theta), 0.0f, cosf(theta));
        const sdft_vec3 org = sdft_madd(sdft_v3(0, 0, 0), dir, -3.0f); /* enters at the origin */
        const passage ps = pass_through(&f, org, dir);
        const float theta_t = asinf(sinf(theta) / IOR);
        assert_close3(ps.entry, sdft_v3(0, 0, 0), 1e-4f);
        assert_close3(ps.inside, sdft_v3(sinf(theta_t), 0.0f, cosf(theta_t)), 1e-4f);
        assert_close3(ps.exit, sdft_v3(h * tanf(theta_t), 0.0f, h), 2e-4f);
        assert_close3(ps.out, dir, 1e-3f);
    }
}

static void total_internal_reflection_where_snell_says(void **state)
{
    (void)state;
    const float critical = asinf(1.0f / IOR); /* 41.8 degrees */
    const sdft_vec3 n = sdft_v3(0, 0, -1);    /* the glass's face, seen from inside (+z outside is -n) */
    for (int k = -20; k <= 20; k++) {
        const float theta = critical + 0.01f * (float)k;
        const sdft_vec3 d = sdft_v3(sinf(theta), 0.0f, cosf(theta)); /* inside, towards the face */
        sdft_vec3 t = sdft_v3(7, 7, 7);
        const int passes = secondary_refract(d, n, IOR, &t);
        if (k < 0) {
            assert_true(passes);
            assert_float_equal(t.x, IOR * sinf(theta), 1e-4f); /* n1 sin(i) = n2 sin(t) */
        } else if (k > 0) {
            assert_false(passes);
            assert_float_equal(t.x, 7.0f, 0.0f);
        }
    }
    /* From outside into glass, never. */
    for (int k = 0; k < 16; k++) {
        const float theta = 0.1f * (float)k;
        sdft_vec3 t;
        assert_true(secondary_refract(sdft_v3(sinf(theta), 0.0f, cosf(theta)), sdft_v3(0, 0, -1), 1.0f / IOR, &t));
    }
}

/* Fresnel: at normal incidence ((n1 - n2) / (n1 + n2))^2, rising to 1 at grazing. */
static void schlick_matches_fresnel_at_its_ends(void **state)
{
    (void)state;
    const float r0 = (1.0f - IOR) / (1.0f + IOR);
    assert_float_equal(secondary_schlick(1.0f, IOR, 1.0f), r0 * r0, 1e-6f);
    assert_float_equal(secondary_schlick(1.0f, IOR, 0.0f), 1.0f, 1e-6f);
    float last = 0.0f;
    for (int k = 10; k >= 0; k--) {
        const float f = secondary_schlick(1.0f, IOR, 0.1f * (float)k);
        assert_true(f >= last);
        last = f;
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(glass_sphere_matches_snell_and_its_chord),
        cmocka_unit_test(glass_slab_shifts_the_ray_and_keeps_its_direction),
        cmocka_unit_test(total_internal_reflection_where_snell_says),
        cmocka_unit_test(schlick_matches_fresnel_at_its_ends),
    };
    return cmocka_run_group_tests_name("refraction", tests, NULL, NULL);
}
