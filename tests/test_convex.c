/* Tests of Keinert et al.'s optimization for convex objects (3.5,
 * src/core/secondary_convex.c): a dodecahedron in its bounding sphere, rays
 * from outside the sphere, from inside it but outside the dodecahedron,
 * and from inside the dodecahedron. Each finds the hit plain tracing finds
 * (from inside, plain tracing marches through with f's sign flipped), and
 * the rays of each case together take fewer evaluations. From outside,
 * plain tracing clips its rays to the sphere's box, so that what is
 * measured is the sphere's own part; from inside, to a scene's box
 * around it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>

#include "sdftrace/sdf.h"
#include "secondary.h"
#include "testutil.h"

static const float INRADIUS = 1.0f, SPHERE = 1.27f; /* circumradius 1.2584 */
static const float EPS = 1e-4f;

static float dodecahedron(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    return sdft_sd_dodecahedron(p, INRADIUS);
}

/* The part as a field of its own, its rays clipped to a box of half-side `half`. */
static sdft_field plain_field(float half)
{
    sdft_field f = sdft_field_defaults();
    f.distance = dodecahedron;
    f.bounds = (sdft_aabb){{-half, -half, -half}, {half, half, half}};
    return f;
}

static sdft_trace_params params(void)
{
    sdft_trace_params tp = sdft_trace_defaults();
    tp.method = SDFT_SPHERE, tp.eps = EPS;
    return tp;
}

/* A point at distance between lo and hi from the centre, in a random direction. */
static sdft_vec3 point_between(tu_rng *r, float lo, float hi)
{
    const sdft_vec3 d = sdft_normalize(sdft_v3(tu_uniform(r, -1, 1), tu_uniform(r, -1, 1), tu_uniform(r, -1, 1)));
    return sdft_scale(d, tu_uniform(r, lo, hi));
}

/* Rays from origins drawn by `origin`: the convex trace against plain
 * tracing (inside: of -f), hit for hit, and their evaluations in total. */
static void compare(const char *name, sdft_vec3 (*origin)(tu_rng *), int inside, int aim_at_centre, float box)
{
    const sdft_field f = plain_field(box), flipped = secondary_inside(&f);
    const sdft_convex_part part = {.distance = dodecahedron, .centre = {0, 0, 0}, .radius = SPHERE};
    sdft_scratch s;
    sdft_scratch_init(&f, &s);
    const sdft_trace_params tp = params();
    tu_rng r = tu_rng_seed(31);
    uint64_t plain_steps = 0, convex_steps = 0;
    int hits = 0;
    for (int k = 0; k < 400; k++) {
        const sdft_vec3 o = origin(&r);
        const sdft_vec3 aim = aim_at_centre ? point_between(&r, 0.0f, 0.9f) : point_between(&r, 0.0f, 3.0f);
        const sdft_ray ray = {o, 0.0f, sdft_normalize(sdft_sub(aim, o)), INFINITY};
        const sdft_hit plain = sdft_trace(inside ? &flipped : &f, &s, &ray, &tp);
        const sdft_hit convex = secondary_trace_convex(&part, &s, &ray, &tp);
        plain_steps += plain.steps, convex_steps += convex.steps;
        assert_int_equal(convex.status == SDFT_HIT, plain.status == SDFT_HIT);
        if (plain.status != SDFT_HIT)
            continue;
        hits++;
        /* Both within eps of the surface, at the same place: one crossing of a convex surface. */
        const sdft_vec3 a = sdft_madd(o, ray.dir, plain.t), b = sdft_madd(o, ray.dir, convex.t);
        assert_true(fabsf(dodecahedron(NULL, NULL, b)) <= 2.0f * EPS);
        if (!(sdft_length(sdft_sub(a, b)) <= 4.0f * EPS))
            fail_msg("ray %d: plain t %g, convex t %g", k, plain.t, convex.t);
    }
    assert_true(hits > 100);
    if (!(convex_steps < plain_steps))
        fail_msg("convex %llu evaluations, plain %llu", (unsigned long long)convex_steps,
                 (unsigned long long)plain_steps);
    print_message("%s: %d hits, %llu evaluations plain, %llu convex\n", name, hits, (unsigned long long)plain_steps,
                  (unsigned long long)convex_steps);
}

static sdft_vec3 outside_sphere(tu_rng *r) { return point_between(r, 2.0f, 6.0f); }

/* Inside the sphere, outside the dodecahedron: between a face's plane and the sphere, along the
 * directions of the vertices (where the gap is widest, 1.2584 .. 1.27). */
static sdft_vec3 between(tu_rng *r)
{
    for (;;) {
        const sdft_vec3 p = point_between(r, 1.15f, 1.265f);
        if (dodecahedron(NULL, NULL, p) > 1e-3f)
            return p;
    }
}

static sdft_vec3 in_object(tu_rng *r) { return point_between(r, 0.0f, 0.95f); }

static void same_hits_fewer_steps_from_outside_the_sphere(void **state)
{
    (void)state;
    compare("outside the sphere", outside_sphere, 0, 1, SPHERE);
}

static void same_hits_fewer_steps_from_inside_the_sphere(void **state)
{
    (void)state;
    compare("inside the sphere", between, 0, 0, 20.0f);
}

static void same_hits_fewer_steps_from_inside_the_object(void **state)
{
    (void)state;
    compare("inside the object", in_object, 1, 0, 20.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(same_hits_fewer_steps_from_outside_the_sphere),
        cmocka_unit_test(same_hits_fewer_steps_from_inside_the_sphere),
        cmocka_unit_test(same_hits_fewer_steps_from_inside_the_object),
    };
    return cmocka_run_group_tests_name("convex", tests, NULL, NULL);
}
