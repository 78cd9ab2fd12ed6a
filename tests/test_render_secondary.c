/* Tests of the renderer's secondary rays end to end (render_whitted.c,
 * `sdftrace render`): each new flag's bad values are one line on stderr,
 * a non-zero exit and no output; the jewel's evaluations come apart into
 * primary, shadow and secondary rays that add up, the convex-object
 * optimization takes fewer of them for the same picture's rays; and a
 * grid renders with every technique on. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "testutil.h"

static char out[16384];

static void bad_flag_values_are_one_line_and_no_output(void **state)
{
    (void)state;
    static const char *const cases[][2] = {
        {"--eps-min -1e-3", "--eps-min"},
        {"--eps-min nan", "--eps-min"},
        {"--bounces 3", "--bounces"},
        {"--bounces 17,0", "--bounces"},
        {"--bounces 0,17", "--bounces"},
        {"--bounces 2,-1", "--bounces"},
        {"--bounces -1,2", "--bounces"},
        {"--bounces 2,8,1", "--bounces"},
        {"--bounces nan,1", "--bounces"},
        {"--smooth-iters -1", "--smooth-iters"},
        {"--smooth-iters 65", "--smooth-iters"},
        {"--smooth-iters nan", "--smooth-iters"},
        {"--soft-shadows -8", "--soft-shadows"},
        {"--soft-shadows 0", "--soft-shadows"},
        {"--soft-shadows nan", "--soft-shadows"},
        {"--material 1,1,1,0", "--material"},
        {"--material 1,1,nan,0,1.5", "--material"},
        {"--material 1,1,1,2,0", "reflectance"},
        {"--material 1,1,1,0,0.5", "index of refraction"},
        {"--material 1,1,3,0,1.5", "colour"},
    };
    char exr[512];
    tu_tmp(exr, sizeof exr, "secondary_bad.exr");
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        remove(exr);
        const int rc = tu_run(out, sizeof out, "%s render --scene jewel --width 16 --height 9 -o %s %s", SDFT_CLI, exr,
                              cases[i][0]);
        if (rc == 0 || tu_lines(out) != 1 || tu_file_exists(exr) || !strstr(out, cases[i][1]))
            fail_msg("case '%s': rc %d, output '%s' (want one line naming '%s')", cases[i][0], rc, out, cases[i][1]);
        tu_assert_no_temporaries(SDFT_TEST_TMP, "secondary_bad.exr");
    }
}

/* The library refuses the same values through sdft_render, whoever calls it. */
static void render_refuses_bad_shading_parameters(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("jewel");
    sdft_image img;
    char msg[256];
    assert_int_equal(sdft_image_alloc(&img, 8, 8, msg, sizeof msg), SDFT_OK);
    for (int k = 0; k < 10; k++) {
        sdft_render_params p = sdft_render_defaults();
        p.width = p.height = 8;
        p.camera = sc->camera;
        switch (k) {
        case 0:
            p.eps_min = -1e-3f;
            break;
        case 1:
            p.eps_min = NAN;
            break;
        case 2:
            p.reflect_bounces = SDFT_MAX_BOUNCES + 1;
            break;
        case 3:
            p.refract_bounces = -1;
            break;
        case 4:
            p.smooth_iters = -1;
            break;
        case 5:
            p.smooth_iters = SDFT_MAX_SMOOTH_ITERS + 1;
            break;
        case 6:
            p.soft_shadows = NAN;
            break;
        case 7:
            p.soft_shadows = -8.0f;
            break;
        case 8:
            p.material.reflectance = 1.5f;
            break;
        default:
            p.material.ior = 0.5f;
            break;
        }
        msg[0] = '\0';
        assert_int_equal(sdft_render(&sc->field, &p, &img, NULL, msg, sizeof msg), SDFT_EINVAL);
        assert_true(strlen(msg) > 10);
    }
    sdft_image_free(&img);
}

static sdft_render_stats render_jewel(int convex)
{
    const sdft_scene *sc = sdft_scene_find("jewel");
    sdft_render_params p = sdft_render_defaults();
    p.width = 64, p.height = 40, p.camera = sc->camera, p.light = sc->light;
    p.materials = 1, p.convex = convex, p.threads = 2;
    sdft_image img;
    sdft_render_stats st;
    char msg[256];
    assert_int_equal(sdft_image_alloc(&img, p.width, p.height, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_render(&sc->field, &p, &img, &st, msg, sizeof msg), SDFT_OK);
    uint64_t sum = 0;
    for (int i = 0; i < p.width * p.height; i++)
        sum += img.steps[i];
    assert_int_equal(sum, st.steps); /* the image's counts are the totals' */
    sdft_image_free(&img);
    return st;
}

static void jewel_counts_add_up_and_convex_takes_fewer(void **state)
{
    (void)state;
    const sdft_render_stats with = render_jewel(1), without = render_jewel(0);
    assert_true(with.secondary_rays > with.primary_rays / 4);
    assert_int_equal(with.steps, with.primary_steps + with.shadow_steps + with.secondary_steps);
    assert_int_equal(without.steps, without.primary_steps + without.shadow_steps + without.secondary_steps);
    assert_int_equal(with.primary_steps, without.primary_steps);
    assert_true(with.secondary_steps < without.secondary_steps);
    print_message("secondary evaluations: %llu with the convex optimization, %llu without\n",
                  (unsigned long long)with.secondary_steps, (unsigned long long)without.secondary_steps);
}

static void grid_renders_with_every_technique(void **state)
{
    (void)state;
    char grid[512], exr[512];
    tu_tmp(grid, sizeof grid, "secondary_dodecahedron.nvdb");
    tu_tmp(exr, sizeof exr, "secondary_grid.exr");
    assert_int_equal(tu_run(out, sizeof out, "%s bake --scene dodecahedron --res 96 --quiet -o %s", SDFT_CLI, grid), 0);
    remove(exr);
    assert_int_equal(tu_run(out, sizeof out,
                            "%s render --grid %s --scene dodecahedron --width 48 --height 27 -o %s --quiet --json "
                            "--material 0.9,0.95,1,0,1.5 --bounces 2,8 --eps-min 1e-3 --smooth-iters 3 "
                            "--soft-shadows 8 --ao 2>&1",
                            SDFT_CLI, grid, exr),
                     0);
    assert_true(tu_file_exists(exr));
    const char *sec = strstr(out, "\"secondary_rays\": ");
    assert_non_null(sec);
    assert_true(strtod(sec + strlen("\"secondary_rays\": "), NULL) > 100.0);
    remove(grid), remove(exr);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bad_flag_values_are_one_line_and_no_output),
        cmocka_unit_test(render_refuses_bad_shading_parameters),
        cmocka_unit_test(jewel_counts_add_up_and_convex_takes_fewer),
        cmocka_unit_test(grid_renders_with_every_technique),
    };
    return cmocka_run_group_tests_name("render_secondary", tests, NULL, NULL);
}
