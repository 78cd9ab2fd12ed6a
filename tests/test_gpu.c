/* Tests of the Vulkan component (sdftrace/gpu.h), run on whatever device
 * the machine has (CI: Mesa's lavapipe, a CPU device; the GPU path needs
 * no GPU): against analytic truth on a sphere's grid, against the CPU's
 * sdft_render on the test scenes' grids (the same trace code, compiled for
 * the device), and the one-line errors of bad input. Images are small:
 * lavapipe is slow, and compiles each variant's shader once per process
 * (Mesa caches it on disk for the next). */
#define _GNU_SOURCE /* dl_iterate_phdr, RTLD_NODELETE */
#include <dlfcn.h>
#include <link.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "grid_support.h"
#include "sdftrace/gpu.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/sdf.h"
#include "testutil.h"

enum { W = 48, H = 32 };

/* What every test shares: the device, opened once (each variant's shader
 * is compiled on first use and kept). */
static sdft_gpu *gpu;

/* Keeps a loaded Vulkan driver loaded to the end of the process: Mesa's
 * drivers keep a few allocations to the end, and LeakSanitizer can name
 * (and tests/support/vulkan.supp suppress) only a library still mapped
 * when it looks; the loader unloads the driver with its last instance. */
static int keep_driver(struct dl_phdr_info *info, size_t size, void *data)
{
    (void)size, (void)data;
    if (strstr(info->dlpi_name, "libvulkan_") && !strstr(info->dlpi_name, "libvulkan.so"))
        dlopen(info->dlpi_name, RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE);
    return 0;
}

static int open_device(void **state)
{
    (void)state;
    char msg[256] = "";
    sdft_gpu_options o = sdft_gpu_options_defaults();
    if (sdft_gpu_create(&o, &gpu, msg, sizeof msg)) {
        print_error("no Vulkan device (%s): the GPU tests need one; mesa-vulkan-drivers has lavapipe\n", msg);
        return -1;
    }
    print_message("device: %s\n", sdft_gpu_device_name(gpu));
    dl_iterate_phdr(keep_driver, NULL);
    return 0;
}

static int close_device(void **state)
{
    (void)state;
    sdft_gpu_release(gpu);
    return 0;
}

/* g rendered on the device with params p into img; fails the test on an error. */
static sdft_render_stats gpu_render(const sdft_grid *g, const sdft_render_params *p, sdft_image *img)
{
    char msg[256] = "";
    sdft_gpu_grid *gg = NULL;
    sdft_render_stats st;
    assert_int_equal(sdft_image_alloc(img, p->width, p->height, msg, sizeof msg), SDFT_OK);
    if (sdft_gpu_grid_create(gpu, g, &gg, msg, sizeof msg) || sdft_gpu_render(gg, p, img, &st, msg, sizeof msg))
        fail_msg("GPU render: %s", msg);
    sdft_gpu_grid_release(gg);
    return st;
}

/* The same on the CPU (sdft_render of the grid's field, far bound). */
static sdft_render_stats cpu_render(const sdft_grid *g, const sdft_render_params *p, sdft_image *img)
{
    char msg[256] = "";
    const sdft_field f = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_render_stats st;
    assert_int_equal(sdft_image_alloc(img, p->width, p->height, msg, sizeof msg), SDFT_OK);
    if (sdft_render(&f, p, img, &st, msg, sizeof msg))
        fail_msg("CPU render: %s", msg);
    return st;
}

/* ---- a sphere's grid against the sphere ---------------------------------- */

static float sphere_at_origin(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    return sdft_sd_sphere(p, 0.6f);
}

/* Every pixel whose ray passes the sphere by more than two voxels is a miss;
 * every one that meets it more than two voxels inside its silhouette hits it
 * where the ray meets the sphere, to within a tenth of a voxel (a baked
 * sphere's trilinear surface lies that close to the sphere). With each
 * variant's step counted, the GPU traced the rays itself. */
static void test_sphere_grid_against_the_sphere(void **state)
{
    (void)state;
    sdft_field f = sdft_field_defaults();
    f.distance = sphere_at_origin;
    f.bounds = (sdft_aabb){{-1, -1, -1}, {1, 1, 1}};
    sdft_grid *g = bake(&f, 64, 0, NULL);
    const float voxel = sdft_grid_voxel_size(g).x;
    sdft_render_params p = sdft_render_defaults();
    p.width = W, p.height = H;
    p.camera = (sdft_camera){.from = {0.3f, 0.4f, 2.5f}, .at = {0, 0, 0}, .up = {0, 1, 0}, .fov_deg = 40.0f};
    sdft_image img;
    const sdft_render_stats st = gpu_render(g, &p, &img);
    const sdft_view view = sdft_camera_view(&p.camera, W, H);
    int hits = 0, misses = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const sdft_ray r = sdft_view_ray(&view, (float)x + 0.5f, (float)y + 0.5f);
            const double b = -(double)sdft_dot(r.org, r.dir), c2 = (double)sdft_dot(r.org, r.org) - b * b;
            const double pass = sqrt(c2 > 0.0 ? c2 : 0.0); /* the ray's closest approach to the centre */
            if (pass > 0.6 + 2.0 * voxel) {
                assert_int_equal(img.status[i], SDFT_MISS);
                assert_true(isinf(img.depth[i]));
                misses++;
            } else if (pass < 0.6 - 2.0 * voxel) {
                const double t = b - sqrt(0.36 - c2);
                assert_int_equal(img.status[i], SDFT_HIT);
                if (fabs(img.depth[i] - t) > 0.1 * voxel)
                    fail_msg("pixel (%d, %d): depth %.6f, the sphere at %.6f", x, y, img.depth[i], t);
                assert_true(img.primary_steps[i] >= 2);
                hits++;
            }
        }
    print_message("%d hits, %d misses checked; %.2f evaluations per pixel\n", hits, misses, (double)st.steps / (W * H));
    assert_true(hits > 100 && misses > 100);
    sdft_image_free(&img);
    sdft_grid_free(g);
}

/* ---- the GPU against the CPU on the scenes' grids -------------------------- */

/* The share of pixels whose hit masks differ, and the checks on the rest:
 * depth within 1e-4 voxel where both hit, the same status, normals and
 * colours alike, each pixel's counts alike. */
static double compare_images(const sdft_image *a, const sdft_image *b, float voxel)
{
    const size_t n = (size_t)a->width * (size_t)a->height;
    size_t differ = 0, counts_differ = 0;
    for (size_t i = 0; i < n; i++) {
        const int ha = a->status[i] == SDFT_HIT, hb = b->status[i] == SDFT_HIT;
        if (ha != hb) {
            differ++;
            continue;
        }
        if (ha && fabsf(a->depth[i] - b->depth[i]) > 1e-4f * voxel)
            fail_msg("pixel %zu: depth %.7f on the GPU, %.7f on the CPU", i, a->depth[i], b->depth[i]);
        for (int k = 0; k < 3; k++) {
            if (fabsf(a->normal[3 * i + k] - b->normal[3 * i + k]) > 1e-3f)
                fail_msg("pixel %zu: normal %d %.5f on the GPU, %.5f on the CPU", i, k, a->normal[3 * i + k],
                         b->normal[3 * i + k]);
            /* a shadow ray that goes the other way darkens one of them */
            counts_differ += fabsf(a->rgb[3 * i + k] - b->rgb[3 * i + k]) > 1e-3f;
        }
        counts_differ += a->primary_steps[i] != b->primary_steps[i];
    }
    print_message("  %zu of %zu pixels' hit masks differ, %zu other differences\n", differ, n, counts_differ);
    assert_true(counts_differ <= n / 100);
    return (double)differ / (double)n;
}

/* Counts within 1% (the device rounds divisions and square roots its own
 * way, so a few rays may take another step; lavapipe gives them exactly). */
static void assert_counts_close(uint64_t gpu_count, uint64_t cpu_count, const char *what)
{
    const double d = fabs((double)gpu_count - (double)cpu_count);
    if (d > 0.01 * (double)cpu_count + 2.0)
        fail_msg("%s: %llu on the GPU, %llu on the CPU", what, (unsigned long long)gpu_count,
                 (unsigned long long)cpu_count);
}

/* The scene's grid at 64^3, rendered from the scene's camera both ways with
 * `method`, the papers' counting or not, the screen-space criterion or
 * not: hit masks equal but for at most 0.2% of the pixels (silhouettes),
 * depths within 1e-4 of a voxel, counts within 1%. */
static void gpu_against_cpu(const char *scene_name, sdft_method method, int papers, int screen_space)
{
    const sdft_scene *scene = sdft_scene_find(scene_name);
    assert_non_null(scene);
    sdft_grid *g = bake(&scene->field, 64, 0, NULL);
    sdft_render_params p = sdft_render_defaults();
    p.width = W, p.height = H;
    p.camera = scene->camera, p.light = scene->light;
    p.trace.method = method;
    p.trace.omega = sdft_default_omega(method);
    p.screen_space = screen_space;
    if (papers)
        sdft_render_papers(&p);
    sdft_image on_gpu, on_cpu;
    const sdft_render_stats sg = gpu_render(g, &p, &on_gpu), sc = cpu_render(g, &p, &on_cpu);
    print_message("%s, %s%s%s: %llu steps on the GPU, %llu on the CPU\n", scene_name, sdft_method_name(method),
                  papers ? ", papers" : "", screen_space ? ", screen-space" : "", (unsigned long long)sg.steps,
                  (unsigned long long)sc.steps);
    assert_true(compare_images(&on_gpu, &on_cpu, sdft_grid_voxel_size(g).x) <= 0.002);
    assert_counts_close(sg.primary_steps, sc.primary_steps, "primary steps");
    assert_counts_close(sg.steps, sc.steps, "steps");
    assert_counts_close(sg.rays, sc.rays, "rays");
    assert_counts_close(sg.fallbacks, sc.fallbacks, "fallbacks");
    assert_counts_close(sg.hits, sc.hits, "hits");
    assert_true(sg.hits > (uint64_t)(W * H / 10));
    sdft_image_free(&on_gpu), sdft_image_free(&on_cpu);
    sdft_grid_free(g);
}

static void test_auto_on_the_temple(void **state)
{
    (void)state;
    gpu_against_cpu("temple", SDFT_AUTO, 0, 0);
}

static void test_relaxed_papers_screen_space_on_the_figure(void **state)
{
    (void)state;
    gpu_against_cpu("figure", SDFT_RELAXED, 1, 1);
}

/* ---- bad input --------------------------------------------------------------- */

static void test_bad_input_is_refused(void **state)
{
    (void)state;
    char msg[256] = "";
    sdft_gpu_options o = sdft_gpu_options_defaults();
    sdft_gpu *none = (sdft_gpu *)1;
    assert_int_equal(sdft_gpu_create(NULL, &none, msg, sizeof msg), SDFT_EINVAL);
    assert_null(none);
    assert_int_equal(sdft_gpu_create(&o, NULL, msg, sizeof msg), SDFT_EINVAL);
    o.device = 99;
    assert_int_equal(sdft_gpu_create(&o, &none, msg, sizeof msg), SDFT_EINVAL);
    print_message("device 99: %s\n", msg);
    assert_int_equal(tu_lines(msg), 0);

    /* An Fp16 grid: the GPU renders float grids. */
    sdft_field f = spheres_field();
    sdft_bake_params bp = sdft_bake_defaults();
    bp.res = 32, bp.fp16 = 1;
    sdft_grid *half = NULL, *g = bake(&f, 32, 0, NULL);
    assert_int_equal(sdft_bake(&f, &bp, NULL, &half, NULL, msg, sizeof msg), SDFT_OK);
    sdft_gpu_grid *gg = NULL;
    assert_int_equal(sdft_gpu_grid_create(gpu, half, &gg, msg, sizeof msg), SDFT_ENOTSCALAR);
    print_message("fp16: %s\n", msg);
    assert_null(gg);
    assert_int_equal(sdft_gpu_grid_create(gpu, NULL, &gg, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_gpu_grid_create(NULL, g, &gg, msg, sizeof msg), SDFT_EINVAL);

    /* A grid too big for the device: here, for a budget of 64 KiB. */
    sdft_gpu *small = NULL;
    o = sdft_gpu_options_defaults();
    o.memory_budget = 64 << 10;
    assert_int_equal(sdft_gpu_create(&o, &small, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_gpu_grid_create(small, g, &gg, msg, sizeof msg), SDFT_ENOMEM);
    print_message("too big: %s\n", msg);
    assert_int_equal(tu_lines(msg), 0);
    assert_non_null(strstr(msg, "too big"));
    assert_null(gg);
    sdft_gpu_release(small);

    /* Shading the GPU does not do, a bad camera, an image of another size. */
    assert_int_equal(sdft_gpu_grid_create(gpu, g, &gg, msg, sizeof msg), SDFT_OK);
    sdft_render_params p = sdft_render_defaults();
    p.width = 8, p.height = 8;
    sdft_image img;
    assert_int_equal(sdft_image_alloc(&img, 8, 8, msg, sizeof msg), SDFT_OK);
    p.soft_shadows = 8.0f;
    assert_int_equal(sdft_gpu_render(gg, &p, &img, NULL, msg, sizeof msg), SDFT_EINVAL);
    print_message("soft shadows: %s\n", msg);
    p.soft_shadows = 0.0f, p.camera.fov_deg = 0.0f;
    assert_int_equal(sdft_gpu_render(gg, &p, &img, NULL, msg, sizeof msg), SDFT_EINVAL);
    p.camera.fov_deg = 45.0f, p.width = 9;
    assert_int_equal(sdft_gpu_render(gg, &p, &img, NULL, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_gpu_render(NULL, &p, &img, NULL, msg, sizeof msg), SDFT_EINVAL);
    sdft_image_free(&img);
    sdft_gpu_grid_release(gg);
    sdft_grid_free(half), sdft_grid_free(g);
}

/* ---- the command line ------------------------------------------------------- */

static char out[1 << 14];

/* render --device vulkan writes the image and says which device made it;
 * without a grid, or without a Vulkan driver, it says so in one line and
 * exits non-zero, writing nothing. */
static void test_cli_device_vulkan(void **state)
{
    (void)state;
    char grid[512], exr[512];
    tu_tmp(grid, sizeof grid, "gpu_spheres.nvdb");
    tu_tmp(exr, sizeof exr, "gpu_spheres.exr");
    sdft_field f = spheres_field();
    sdft_grid_free(bake(&f, 32, 0, grid));
    remove(exr);
    /* The tool's own leaks are test_cli's to find; here its Vulkan driver's
     * last allocations would be all LeakSanitizer sees (keep_driver). */
    assert_int_equal(tu_run(out, sizeof out,
                            "ASAN_OPTIONS=detect_leaks=0 %s render --grid %s --device vulkan --width 16 --height 12 "
                            "--json -o %s",
                            SDFT_CLI, grid, exr),
                     0);
    assert_non_null(strstr(out, "\"device\": \""));
    assert_null(strstr(out, "\"device\": \"cpu\""));
    assert_true(tu_file_exists(exr));
    remove(exr);

    assert_int_equal(tu_run(out, sizeof out, "%s render --scene temple --device vulkan -o %s", SDFT_CLI, exr), 2);
    assert_int_equal(tu_lines(out), 1);
    assert_non_null(strstr(out, "--grid"));
    assert_int_not_equal(
        tu_run(out, sizeof out,
               "ASAN_OPTIONS=detect_leaks=0 VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent "
               "%s render --grid %s "
               "--device vulkan --width 16 --height 12 -o %s",
               SDFT_CLI, grid, exr),
        0);
    print_message("no driver: %s", out);
    assert_int_equal(tu_lines(out), 1);
    assert_non_null(strstr(out, "Vulkan"));
    assert_false(tu_file_exists(exr));
    assert_int_equal(tu_run(out, sizeof out, "%s render --grid %s --device metal -o %s", SDFT_CLI, grid, exr), 2);
    assert_int_equal(tu_lines(out), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_grid_against_the_sphere),
        cmocka_unit_test(test_auto_on_the_temple),
        cmocka_unit_test(test_relaxed_papers_screen_space_on_the_figure),
        cmocka_unit_test(test_bad_input_is_refused),
        cmocka_unit_test(test_cli_device_vulkan),
    };
    return cmocka_run_group_tests_name("gpu", tests, open_device, close_device);
}
