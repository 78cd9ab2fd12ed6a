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

#include "sdftrace/render.h"
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

/* The jewel rendered the Whitted way, relaxed 1.2, counted the papers'
 * way, rays inside the gem marching through it (no 3.5); *hits_far (if not NULL): primary hits with pixel_radius t
 * above the field's feature size, from the image's depth. */
static sdft_render_stats render_jewel(int screen_space, int smooth_iters, float eps_min, int *hits_far)
{
    const sdft_scene *sc = sdft_scene_find("jewel");
    sdft_render_params p = sdft_render_defaults();
    p.width = WIDTH, p.height = HEIGHT, p.camera = sc->camera, p.light = sc->light, p.threads = 2;
    p.materials = 1, p.convex = 0, p.screen_space = screen_space, p.smooth_iters = smooth_iters, p.eps_min = eps_min;
    p.trace.method = SDFT_RELAXED, p.trace.omega = 1.2f;
    sdft_render_papers(&p);
    sdft_image img;
    sdft_render_stats st;
    char msg[256];
    assert_int_equal(sdft_image_alloc(&img, p.width, p.height, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_render(&sc->field, &p, &img, &st, msg, sizeof msg), SDFT_OK);
    const float pixel_radius = sdft_camera_pixel_radius(&sc->camera, HEIGHT);
    if (hits_far) {
        *hits_far = 0;
        for (int i = 0; i < WIDTH * HEIGHT; i++)
            *hits_far += img.status[i] == SDFT_HIT && pixel_radius * img.depth[i] > sc->field.feature_size;
    }
    sdft_image_free(&img);
    return st;
}

/* With the default eps_min (the feature size) the |f(p)| term decides
 * where a hit lies off the surface, and only there. A converged hit is
 * refined onto the surface (|f| ~ 1e-7), so eps_min decides every one; a
 * hit settled by 3.4 under the screen-space criterion lies on f = eps(t) =
 * pixel_radius t, beyond the feature size wherever pixel_radius t is:
 * every such primary hit at least, counted from the depth plane. */
static void f_decides_where_hits_lie_off_the_surface(void **state)
{
    (void)state;
    const sdft_render_stats refined = render_jewel(0, 0, 0.0f, NULL);
    assert_true(refined.dynamic_eps_hits >= refined.hits);
    assert_int_equal(refined.dynamic_eps_from_f, 0);
    int far = 0;
    const sdft_render_stats settled = render_jewel(1, 3, 0.0f, &far);
    assert_true(far > WIDTH * HEIGHT / 4);
    if (!(settled.dynamic_eps_from_f >= (uint64_t)far))
        fail_msg("|f(p)| decided %llu of %llu hits; %d primary hits alone lie beyond eps_min",
                 (unsigned long long)settled.dynamic_eps_from_f, (unsigned long long)settled.dynamic_eps_hits, far);
    print_message("|f(p)| decided 0 of %llu refined hits, %llu of %llu settled ones\n",
                  (unsigned long long)refined.dynamic_eps_hits, (unsigned long long)settled.dynamic_eps_from_f,
                  (unsigned long long)settled.dynamic_eps_hits);
}

/* eps_min 1e-5, below the trace's eps of 1e-4: a secondary ray starts
 * within eps of the surface it leaves and converges there at once; the
 * renderer counts it. The default never does that. */
static void eps_min_below_eps_is_self_hits(void **state)
{
    (void)state;
    const sdft_render_stats tiny = render_jewel(0, 0, 1e-5f, NULL), fine = render_jewel(0, 0, 0.0f, NULL);
    assert_int_equal(fine.secondary_self_hits, 0);
    if (!(tiny.secondary_self_hits > tiny.secondary_rays / 2))
        fail_msg("eps_min 1e-5: %llu self-hits of %llu secondary rays", (unsigned long long)tiny.secondary_self_hits,
                 (unsigned long long)tiny.secondary_rays);
    assert_true(tiny.secondary_rays > 4 * fine.secondary_rays); /* each re-hit spends a bounce on the next ray */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(dynamic_eps_leaves_every_glass_hit),
        cmocka_unit_test(fixed_tiny_eps_re_hits_its_own_surface),
        cmocka_unit_test(f_decides_where_hits_lie_off_the_surface),
        cmocka_unit_test(eps_min_below_eps_is_self_hits),
    };
    return cmocka_run_group_tests_name("dynamic_eps", tests, NULL, NULL);
}
