/* Tests of the primer's soft shadows and ambient occlusion
 * (src/core/secondary_light.c) on a floor under a large slab held up in
 * the light: floor points in the open see all of the light, points under
 * the slab none, points by the shadow's edge a share that grows away from
 * it; occlusion is 1 in the open and less in the corner under the slab. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>

#include "secondary.h"

static const sdft_vec3 LIGHT = {0.0f, 10.0f, 0.0f};
static const float K = 8.0f; /* the primer's */

static float box(sdft_vec3 p, sdft_vec3 centre, sdft_vec3 half)
{
    const sdft_vec3 q = sdft_sub(sdft_abs3(sdft_sub(p, centre)), half);
    return sdft_length(sdft_max3(q, 0.0f)) + fminf(sdft_maxcomp(q), 0.0f);
}

/* A floor (top at y = 0) and a 4 x 4 slab from y = 1 to 1.2 over the origin. */
static float scene(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    const float floor = box(p, sdft_v3(0, -0.5f, 0), sdft_v3(20, 0.5f, 20));
    return fminf(floor, box(p, sdft_v3(0, 1.1f, 0), sdft_v3(2, 0.1f, 2)));
}

static float light_at(sdft_vec3 p, uint32_t *steps)
{
    sdft_field f = sdft_field_defaults();
    f.distance = scene;
    f.bounds = (sdft_aabb){{-20, -1, -20}, {20, 12, 20}};
    sdft_scratch s;
    sdft_scratch_init(&f, &s);
    const float lift = 2e-3f;
    const sdft_vec3 org = sdft_madd(p, sdft_v3(0, 1, 0), lift), to = sdft_sub(LIGHT, org);
    const float dist = sdft_length(to);
    return secondary_soft_shadow(&f, &s, org, sdft_scale(to, 1.0f / dist), dist, K, lift, 1e-4f, 1000, steps);
}

static void open_floor_is_fully_lit(void **state)
{
    (void)state;
    for (int k = 0; k < 5; k++) {
        uint32_t steps = 0;
        assert_float_equal(light_at(sdft_v3(5.0f + 2.0f * (float)k, 0, 1.0f), &steps), 1.0f, 0.0f);
        assert_true(steps > 0);
    }
}

static void floor_under_the_slab_is_dark(void **state)
{
    (void)state;
    for (int k = 0; k < 5; k++) {
        uint32_t steps = 0;
        assert_float_equal(light_at(sdft_v3(-1.5f + 0.7f * (float)k, 0, 0.3f), &steps), 0.0f, 0.0f);
    }
}

/* The hard shadow's edge on the floor: the slab's upper edge x = 2, y = 1.2
 * seen from the light falls at x = 2 * 10 / 8.8. Beyond, the light grows
 * from 0 to 1 over about t / k, the slab's distance over k: 0.15. */
static void penumbra_lies_between_and_grows_outwards(void **state)
{
    (void)state;
    const float edge = 2.0f * 10.0f / 8.8f;
    float last = 0.0f;
    int between = 0;
    for (int k = 1; k <= 40; k++) {
        uint32_t steps = 0;
        const float v = light_at(sdft_v3(edge + 0.01f * (float)k, 0, 0), &steps);
        assert_true(v >= 0.0f && v <= 1.0f);
        assert_true(v >= last - 1e-4f);
        between += v > 0.0f && v < 1.0f;
        last = v;
    }
    assert_true(between >= 5);
    assert_float_equal(last, 1.0f, 1e-6f);
}

static void occlusion_is_one_in_the_open_less_under_the_slab_edge(void **state)
{
    (void)state;
    sdft_field f = sdft_field_defaults();
    f.distance = scene;
    sdft_scratch s;
    sdft_scratch_init(&f, &s);
    uint32_t steps = 0;
    assert_float_equal(secondary_occlusion(&f, &s, sdft_v3(10, 0, 0), sdft_v3(0, 1, 0), 0.5f, &steps), 1.0f, 1e-6f);
    assert_int_equal(steps, 5);
    /* The slab's underside, 1 above the floor: a sample 0.5 up sees the floor 0.5 below it... and nothing else. */
    const float under = secondary_occlusion(&f, &s, sdft_v3(0, 0, 0), sdft_v3(0, 1, 0), 1.5f, &steps);
    assert_true(under < 0.9f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(open_floor_is_fully_lit),
        cmocka_unit_test(floor_under_the_slab_is_dark),
        cmocka_unit_test(penumbra_lies_between_and_grows_outwards),
        cmocka_unit_test(occlusion_is_one_in_the_open_less_under_the_slab_edge),
    };
    return cmocka_run_group_tests_name("shading", tests, NULL, NULL);
}
