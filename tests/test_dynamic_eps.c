/* Tests of Keinert et al.'s dynamic epsilon (3.3, src/core/secondary.h):
 * every hit of the jewel scene's glass, traced with the screen-space
 * criterion (hits up to half a pixel's footprint off the surface), sends a
 * refraction ray in and a reflection ray out, and where the refraction ray
 * leaves the glass, a ray out and one reflected back in; offset by eps_dynamic = 2
 * max(eps_min, |f(p)|), none of them meets its own surface again before
 * it has travelled 2 eps_min, where a fixed, tiny offset lets many do so
 * at once. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>

#include "sdftrace/scene.h"
#include "secondary.h"

enum { WIDTH = 64, HEIGHT = 40 };
static const float EPS_MIN = 1e-3f;

typedef struct tally {
    int glass_hits; /* hits on the glass, each sending two rays */
    int self_hits;  /* secondary rays that met a surface before travelling 2 eps_min */
    float most_f;   /* the largest |f(p)| at a glass hit */
} tally;

/* Where the refraction ray r leaves the glass (its hit e inside), the two
 * rays from there: out through the surface, and reflected back in. How
 * many meet their own surface before travelling 2 eps_min. */
static int leave_exit(const sdft_field *f, const sdft_field *in, sdft_scratch *s, const sdft_trace_params *tp,
                      const sdft_ray *r, sdft_hit e, int dynamic)
{
    const sdft_vec3 q = sdft_madd(r->org, r->dir, e.t), n = sdft_field_normal(f, s, q); /* outward */
    const float eps = dynamic ? secondary_eps(EPS_MIN, e.distance) : 1e-6f;
    const sdft_ray out = {sdft_madd(q, n, eps), 0.0f, r->dir, INFINITY};
    const sdft_ray back = {sdft_madd(q, n, -eps), 0.0f, secondary_reflect(r->dir, sdft_scale(n, -1.0f)), INFINITY};
    const sdft_hit ho = sdft_trace(f, s, &out, tp), hb = sdft_trace(in, s, &back, tp);
    return (ho.status == SDFT_HIT && ho.t < 2.0f * EPS_MIN) + (hb.status == SDFT_HIT && hb.t < 2.0f * EPS_MIN);
}

/* Sends each glass hit's two rays from `offset(|f(p)|)` off the surface. */
static tally count_self_hits(int dynamic)
{
    const sdft_scene *sc = sdft_scene_find("jewel");
    assert_non_null(sc);
    const sdft_field *f = &sc->field;
    const sdft_field in = secondary_inside(f);
    sdft_scratch s;
    sdft_scratch_init(f, &s);
    sdft_trace_params tp = sdft_trace_defaults();
    tp.method = SDFT_RELAXED, tp.omega = 1.2f, tp.eps = 0.0f;
    tp.pixel_radius = sdft_camera_pixel_radius(&sc->camera, HEIGHT);
    const sdft_view v = sdft_camera_view(&sc->camera, WIDTH, HEIGHT);
    tally t = {0};
    for (int y = 0; y < HEIGHT; y++)
        for (int x = 0; x < WIDTH; x++) {
            const sdft_ray ray = sdft_view_ray(&v, (float)x + 0.5f, (float)y + 0.5f);
            const sdft_hit h = sdft_trace(f, &s, &ray, &tp);
            const sdft_vec3 p = sdft_madd(ray.org, ray.dir, h.t);
            if (h.status != SDFT_HIT || !(f->material(f->ctx, p).ior > 0.0f))
                continue;
            t.glass_hits++;
            t.most_f = fmaxf(t.most_f, fabsf(h.distance));
            const sdft_vec3 n = sdft_field_normal(f, &s, p);
            const float eps = dynamic ? secondary_eps(EPS_MIN, h.distance) : 1e-6f;
            sdft_vec3 refracted;
            if (secondary_refract(ray.dir, n, 1.0f / 1.7f, &refracted)) {
                const sdft_ray r = {sdft_madd(p, n, -eps), 0.0f, refracted, INFINITY};
                const sdft_hit e = sdft_trace(&in, &s, &r, &tp);
                t.self_hits += e.status == SDFT_HIT && e.t < 2.0f * EPS_MIN;
                if (e.status == SDFT_HIT)
                    t.self_hits += leave_exit(f, &in, &s, &tp, &r, e, dynamic);
            }
            const sdft_ray r = {sdft_madd(p, n, eps), 0.0f, secondary_reflect(ray.dir, n), INFINITY};
            const sdft_hit e = sdft_trace(f, &s, &r, &tp);
            t.self_hits += e.status == SDFT_HIT && e.t < 2.0f * EPS_MIN;
        }
    return t;
}

static void dynamic_eps_leaves_every_glass_hit(void **state)
{
    (void)state;
    const tally t = count_self_hits(1);
    assert_true(t.glass_hits > 100);
    assert_true(t.most_f > 2.0f * EPS_MIN); /* the screen-space hits lie well off the surface */
    assert_int_equal(t.self_hits, 0);
}

static void fixed_tiny_eps_re_hits_its_own_surface(void **state)
{
    (void)state;
    const tally t = count_self_hits(0);
    if (!(t.self_hits > t.glass_hits / 10))
        fail_msg("a fixed eps of 1e-6: %d self-intersections in %d glass hits", t.self_hits, t.glass_hits);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(dynamic_eps_leaves_every_glass_hit),
        cmocka_unit_test(fixed_tiny_eps_re_hits_its_own_surface),
    };
    return cmocka_run_group_tests_name("dynamic_eps", tests, NULL, NULL);
}
