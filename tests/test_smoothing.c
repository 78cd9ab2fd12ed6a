/* Tests of Keinert et al.'s discontinuity reduction (3.4,
 * src/core/secondary_smooth.c): the dodecahedron scene traced as the paper
 * traces it for Fig. 9, by Listing 1 with the screen-space threshold
 * err(t) (a hit: f < err(t) within a small step cap), unrefined; f(p) at
 * the hits then jumps anywhere in (0, err(t)) from pixel to pixel, and
 * three fixed-point iterations make the jumps between neighbouring hit
 * pixels much smaller. (sdft_trace itself refines its hits onto the
 * surface; there the iteration matters for the rays the cap stops.) */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>
#include <math.h>

#include "sdftrace/scene.h"
#include "secondary.h"

enum { WIDTH = 96, HEIGHT = 54 };

/* The mean |f(p) - f(q)| over horizontally and vertically neighbouring
 * pixels that both hit, f evaluated here at each pixel's point. */
static double neighbour_variation(const sdft_field *f, const sdft_vec3 *p, const int *hit)
{
    sdft_scratch s;
    sdft_scratch_init(f, &s);
    double sum = 0.0;
    int pairs = 0;
    for (int y = 0; y < HEIGHT; y++)
        for (int x = 0; x < WIDTH; x++) {
            const int i = y * WIDTH + x;
            const int next[2] = {x + 1 < WIDTH ? i + 1 : -1, y + 1 < HEIGHT ? i + WIDTH : -1};
            for (int k = 0; k < 2; k++)
                if (hit[i] && next[k] >= 0 && hit[next[k]]) {
                    sum += fabs(sdft_field_distance(f, &s, p[i]) - sdft_field_distance(f, &s, p[next[k]]));
                    pairs++;
                }
        }
    assert_true(pairs > 1000);
    return sum / pairs;
}

/* Keinert's Listing 1 with tau = err(t): t where f < err(t), or INFINITY. */
static float listing1(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *tp,
                      float *f_at_t)
{
    float t = 0.0f;
    for (uint32_t i = 0; i < tp->max_steps && t < 30.0f; i++) {
        const float radius = sdft_field_distance(f, s, sdft_madd(ray->org, ray->dir, t));
        *f_at_t = radius;
        if (radius < tp->eps + tp->pixel_radius * t)
            return t;
        t += radius;
    }
    return INFINITY;
}

static void smoothing_lowers_the_variation_of_f_between_neighbours(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("dodecahedron");
    const sdft_field *f = &sc->field;
    sdft_scratch s;
    sdft_scratch_init(f, &s);
    sdft_trace_params tp = sdft_trace_defaults();
    tp.method = SDFT_SPHERE, tp.eps = 0.0f, tp.max_steps = 24;
    tp.pixel_radius = sdft_camera_pixel_radius(&sc->camera, HEIGHT);
    const sdft_view v = sdft_camera_view(&sc->camera, WIDTH, HEIGHT);
    sdft_vec3 *before = calloc(WIDTH * HEIGHT, sizeof *before), *after = calloc(WIDTH * HEIGHT, sizeof *after);
    int *hit = calloc(WIDTH * HEIGHT, sizeof *hit), capped = 0;
    assert_true(before && after && hit);
    for (int y = 0; y < HEIGHT; y++)
        for (int x = 0; x < WIDTH; x++) {
            const int i = y * WIDTH + x;
            const sdft_ray ray = sdft_view_ray(&v, (float)x + 0.5f, (float)y + 0.5f);
            float f0 = 0.0f;
            const float t0 = listing1(f, &s, &ray, &tp, &f0);
            hit[i] = t0 < INFINITY;
            capped += !hit[i];
            if (!hit[i])
                continue;
            uint32_t steps = 0;
            float fp;
            const float t = secondary_smooth(f, &s, &ray, t0, f0, &tp, 3, &fp, &steps);
            assert_int_equal(steps, 3);
            before[i] = sdft_madd(ray.org, ray.dir, t0);
            after[i] = sdft_madd(ray.org, ray.dir, t);
            assert_float_equal(fp, sdft_field_distance(f, &s, after[i]), 0.0f);
        }
    assert_true(capped > WIDTH * HEIGHT / 20); /* the sky, and where the cap bites */
    const double v0 = neighbour_variation(f, before, hit), v3 = neighbour_variation(f, after, hit);
    print_message("mean |f(p) - f(q)| between neighbours: %.3g before, %.3g after 3 iterations\n", v0, v3);
    assert_true(v3 < 0.5 * v0);
    free(before), free(after), free(hit);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(smoothing_lowers_the_variation_of_f_between_neighbours),
    };
    return cmocka_run_group_tests_name("smoothing", tests, NULL, NULL);
}
