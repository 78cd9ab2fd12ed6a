/* sdftrace tests — the camera and the whole-image renderer, against an
 * analytic sphere (and a sphere over a plane for shadows). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sdftrace/render.h"
#include "testutil.h"

/* A sphere of radius `radius` at `centre`, optionally over the plane y = floor_y;
 * counts its own evaluations when `calls` is set (single-threaded use). */
typedef struct test_scene {
    sdft_vec3 centre;
    float radius;
    int has_floor;
    float floor_y;
    unsigned long *calls;
} test_scene;

static float test_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)s;
    const test_scene *sc = ctx;
    if (sc->calls)
        (*sc->calls)++;
    float d = sdft_length(sdft_sub(p, sc->centre)) - sc->radius;
    return sc->has_floor ? fminf(d, p.y - sc->floor_y) : d;
}

static sdft_field test_field(const test_scene *sc)
{
    float r = sc->radius;
    sdft_aabb box = {sdft_sub(sc->centre, sdft_v3(r, r, r)), sdft_add(sc->centre, sdft_v3(r, r, r))};
    if (sc->has_floor)
        box = (sdft_aabb){sdft_v3(-20, sc->floor_y - 1, -20), sdft_v3(20, sc->centre.y + r + 1, 20)};
    return (sdft_field){.distance = test_distance, .ctx = sc, .bounds = box};
}

/* The first t > 0 where the ray meets the sphere, or INFINITY. */
static float ray_sphere(sdft_ray ray, sdft_vec3 c, float r, float *disc_out)
{
    sdft_vec3 oc = sdft_sub(ray.org, c);
    float b = sdft_dot(oc, ray.dir), cc = sdft_dot(oc, oc) - r * r;
    float disc = b * b - cc;
    *disc_out = disc;
    if (disc < 0.0f)
        return INFINITY;
    float t = -b - sqrtf(disc);
    return t > 0.0f ? t : INFINITY;
}

static sdft_render_params small_params(void)
{
    sdft_render_params p = sdft_render_defaults();
    p.width = 64, p.height = 48;
    p.camera = (sdft_camera){.from = {0, 0, 4}, .at = {0, 0, 0}, .up = {0, 1, 0}, .fov_deg = 40};
    p.light = sdft_v3(3, 5, 4);
    return p;
}

static void test_camera_frame(void **state)
{
    (void)state;
    sdft_camera cam = {.from = {1, 2, 3}, .at = {1, 2, -7}, .up = {0, 1, 0}, .fov_deg = 90};
    /* Centre of a 2x2 image: straight ahead. */
    sdft_ray r = sdft_camera_ray(&cam, 2, 2, 1.0f, 1.0f);
    assert_true(fabsf(r.dir.x) < 1e-6f && fabsf(r.dir.y) < 1e-6f && fabsf(r.dir.z + 1.0f) < 1e-6f);
    assert_true(r.tnear == 0.0f && isinf(r.tfar));
    /* fov 90: the top edge of the image is 45 degrees up; y grows downwards. */
    r = sdft_camera_ray(&cam, 2, 2, 1.0f, 0.0f);
    assert_true(fabsf(r.dir.y - sqrtf(0.5f)) < 1e-5f && fabsf(r.dir.z + sqrtf(0.5f)) < 1e-5f);
    /* The right edge of a 4:2 image: x = aspect * tan(45) = 2 at unit distance. */
    r = sdft_camera_ray(&cam, 4, 2, 4.0f, 1.0f);
    assert_true(fabsf(r.dir.x / -r.dir.z - 2.0f) < 1e-5f);
    /* Half a pixel's height at unit distance: tan(45) / height. */
    assert_true(fabsf(sdft_camera_pixel_radius(&cam, 100) - 0.01f) < 1e-6f);
    /* An up hint parallel to the view still gives a unit frame. */
    sdft_camera down = {.from = {0, 5, 0}, .at = {0, 0, 0}, .up = {0, 1, 0}, .fov_deg = 60};
    r = sdft_camera_ray(&down, 8, 8, 3.0f, 5.0f);
    assert_true(fabsf(sdft_length(r.dir) - 1.0f) < 1e-5f && r.dir.y < 0.0f);
}

/* Depth equals the analytic ray-sphere intersection for every variant. */
static void test_depth_is_analytic(void **state)
{
    (void)state;
    test_scene sc = {.centre = {0.2f, -0.1f, 0.0f}, .radius = 1.0f};
    sdft_field f = test_field(&sc);
    for (int m = 0; m < SDFT_METHOD_COUNT; m++) {
        sdft_render_params p = small_params();
        p.trace.method = (sdft_method)m;
        p.trace.omega = sdft_default_omega((sdft_method)m);
        sdft_image img;
        assert_int_equal(sdft_image_alloc(&img, p.width, p.height, NULL, 0), 0);
        sdft_render_stats st;
        char msg[128] = "";
        assert_int_equal(sdft_render(&f, &p, &img, &st, msg, sizeof msg), 0);
        int hits = 0;
        for (int y = 0; y < p.height; y++) {
            for (int x = 0; x < p.width; x++) {
                size_t i = (size_t)y * (size_t)p.width + (size_t)x;
                sdft_ray ray = sdft_camera_ray(&p.camera, p.width, p.height, x + 0.5f, y + 0.5f);
                float disc, t = ray_sphere(ray, sc.centre, sc.radius, &disc);
                if (fabsf(disc) < 0.02f)
                    continue; /* grazing the silhouette: either answer is right */
                if (isinf(t)) {
                    assert_int_equal(img.status[i], SDFT_MISS);
                    assert_true(isinf(img.depth[i]));
                    assert_true(img.normal[3 * i] == 0.0f && img.normal[3 * i + 1] == 0.0f);
                    continue;
                }
                hits++;
                assert_int_equal(img.status[i], SDFT_HIT);
                assert_true(fabsf(img.depth[i] - t) < 1e-3f);
                /* The normal is the sphere's radial direction. */
                sdft_vec3 q = sdft_madd(ray.org, ray.dir, t);
                sdft_vec3 n = sdft_normalize(sdft_sub(q, sc.centre));
                sdft_vec3 got = {img.normal[3 * i], img.normal[3 * i + 1], img.normal[3 * i + 2]};
                assert_true(sdft_dot(n, got) > 0.999f);
            }
        }
        assert_true(hits > 300);
        assert_true(st.hits >= (uint64_t)hits && st.primary_rays == (uint64_t)p.width * p.height);
        sdft_image_free(&img);
    }
}

static int images_equal(const sdft_image *a, const sdft_image *b)
{
    size_t n = (size_t)a->width * (size_t)a->height;
    return memcmp(a->rgb, b->rgb, 3 * n * sizeof(float)) == 0 && memcmp(a->depth, b->depth, n * sizeof(float)) == 0 &&
           memcmp(a->normal, b->normal, 3 * n * sizeof(float)) == 0 &&
           memcmp(a->steps, b->steps, n * sizeof(uint32_t)) == 0 &&
           memcmp(a->fallbacks, b->fallbacks, n * sizeof(uint32_t)) == 0 && memcmp(a->status, b->status, n) == 0;
}

/* Bit-for-bit the same image and counts with 1, 2 and 3 threads. */
static void test_thread_count_invariant(void **state)
{
    (void)state;
    test_scene sc = {.centre = {0, 0, 0}, .radius = 0.8f, .has_floor = 1, .floor_y = -0.8f};
    sdft_field f = test_field(&sc);
    sdft_render_params p = small_params();
    p.width = 77, p.height = 53; /* partial tiles on both edges */
    p.trace.method = SDFT_RELAXED, p.trace.omega = 1.5f;
    sdft_image img[3];
    sdft_render_stats st[3];
    for (int k = 0; k < 3; k++) {
        p.threads = k + 1;
        assert_int_equal(sdft_image_alloc(&img[k], p.width, p.height, NULL, 0), 0);
        assert_int_equal(sdft_render(&f, &p, &img[k], &st[k], NULL, 0), 0);
    }
    for (int k = 1; k < 3; k++) {
        assert_true(images_equal(&img[0], &img[k]));
        assert_true(st[0].rays == st[k].rays && st[0].steps == st[k].steps && st[0].hits == st[k].hits &&
                    st[0].fallbacks == st[k].fallbacks && st[0].nonconverged == st[k].nonconverged);
    }
    for (int k = 0; k < 3; k++)
        sdft_image_free(&img[k]);
}

/* The floor under the sphere is in shadow; shadow rays are counted, and the
 * reported steps, each ray's plus the cones' shared ones, are exactly the
 * field's calls minus the normals'. */
static void test_shadows_and_counts(void **state)
{
    (void)state;
    unsigned long calls = 0;
    test_scene sc = {.centre = {0, 0.5f, 0}, .radius = 0.5f, .has_floor = 1, .floor_y = -0.5f, .calls = &calls};
    sdft_field f = test_field(&sc);
    sdft_render_params p = small_params();
    p.camera = (sdft_camera){.from = {0, 6, 0.01f}, .at = {0, 0, 0}, .up = {0, 0, -1}, .fov_deg = 30};
    p.light = sdft_v3(6, 6, 0); /* the shadow falls around x = -1.09, z = 0 */
    p.threads = 1;
    sdft_image img;
    assert_int_equal(sdft_image_alloc(&img, p.width, p.height, NULL, 0), 0);
    sdft_render_stats st;
    assert_int_equal(sdft_render(&f, &p, &img, &st, NULL, 0), 0);

    uint64_t steps = 0, surfaces = 0, shadowed = 0, lit_floor = 0;
    for (int y = 0; y < p.height; y++) {
        for (int x = 0; x < p.width; x++) {
            size_t i = (size_t)y * (size_t)p.width + (size_t)x;
            steps += img.steps[i];
            surfaces += img.status[i] == SDFT_HIT;
            if (img.status[i] != SDFT_HIT || img.normal[3 * i + 1] < 0.99f)
                continue;
            sdft_ray ray = sdft_camera_ray(&p.camera, p.width, p.height, x + 0.5f, y + 0.5f);
            sdft_vec3 q = sdft_madd(ray.org, ray.dir, img.depth[i]);
            if (q.y > -0.45f)
                continue;                                             /* the sphere's top, not the floor */
            if (q.x > -1.25f && q.x < -0.95f && fabsf(q.z) < 0.25f) { /* in the shadow: only ambient light */
                shadowed++;
                assert_true(img.rgb[3 * i + 1] < 0.15f);
            } else if (q.x > 0.8f) { /* the side facing the light */
                lit_floor++;
                assert_true(img.rgb[3 * i + 1] > 0.5f);
            }
        }
    }
    assert_true(shadowed > 10 && lit_floor > 100);
    assert_int_equal(steps, st.steps);
    assert_true(st.rays > st.primary_rays && st.rays <= st.primary_rays + surfaces);
    /* Every evaluation is a trace or cone step, except four per normal. */
    assert_true(st.cone_steps > 0);
    assert_int_equal(calls, st.steps + st.cone_steps + 4 * surfaces);
    sdft_image_free(&img);
}

/* A field that charges each of its evaluations to the pixel whose primary
 * ray passes through the point, by projecting the point back through a
 * camera at (0, 0, 4) looking down -z (fov 40): what the primary-steps
 * plane must hold, found without the renderer's bookkeeping. */
typedef struct pixel_counter {
    test_scene scene;
    int width, height;
    uint32_t *per_pixel;
    unsigned long stray; /* evaluations off every primary ray's pixel */
} pixel_counter;

static float counted_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    const pixel_counter *pc = ctx;
    pixel_counter *mut = (pixel_counter *)ctx; /* single-threaded test */
    const float th = tanf(20.0f * 3.14159265f / 180.0f), tw = th * (float)pc->width / (float)pc->height;
    const float depth = 4.0f - p.z; /* along the view axis */
    const float qx = p.x / depth, qy = p.y / depth;
    const float px = (qx + tw) / (2.0f * tw) * (float)pc->width, py = (th - qy) / (2.0f * th) * (float)pc->height;
    const int x = (int)floorf(px), y = (int)floorf(py);
    if (depth > 0.0f && x >= 0 && y >= 0 && x < pc->width && y < pc->height && fabsf(px - (float)x - 0.5f) < 0.01f &&
        fabsf(py - (float)y - 0.5f) < 0.01f)
        mut->per_pixel[(size_t)y * (size_t)pc->width + (size_t)x]++;
    else
        mut->stray++;
    return test_distance(&pc->scene, s, p);
}

/* The primary-steps plane holds what the field saw of each pixel's primary
 * ray; shadow rays add to steps and fallbacks, never to it; the stats split
 * the totals the same way. */
static void test_primary_steps_plane(void **state)
{
    (void)state;
    sdft_render_params p = small_params();
    sdft_render_papers(&p); /* every evaluation on one pixel's own ray: no cones shared by a tile */
    p.threads = 1;
    p.trace.method = SDFT_RELAXED, p.trace.omega = 1.5f; /* fallbacks too */
    /* A sphere alone: its box leaves the eye outside, so that no evaluation is at the eye, where every ray meets. */
    pixel_counter pc = {.scene = {.centre = {0, 0.3f, 0}, .radius = 0.8f}, .width = p.width, .height = p.height};
    const size_t n = (size_t)p.width * (size_t)p.height;
    pc.per_pixel = calloc(n, sizeof *pc.per_pixel);
    assert_non_null(pc.per_pixel);
    sdft_field f = test_field(&pc.scene);
    f.distance = counted_distance, f.ctx = &pc;

    sdft_image depth, full;
    sdft_render_stats sd, sf;
    assert_int_equal(sdft_image_alloc(&depth, p.width, p.height, NULL, 0), 0);
    assert_int_equal(sdft_image_alloc(&full, p.width, p.height, NULL, 0), 0);
    p.depth_only = 1; /* primary rays alone: no normals, no shadow rays */
    assert_int_equal(sdft_render(&f, &p, &depth, &sd, NULL, 0), 0);
    assert_int_equal(pc.stray, 0);
    uint64_t sum = 0;
    for (size_t i = 0; i < n; i++) {
        assert_int_equal(depth.primary_steps[i], pc.per_pixel[i]);
        assert_int_equal(depth.steps[i], pc.per_pixel[i]);
        sum += pc.per_pixel[i];
    }
    assert_true(sd.primary_steps == sum && sd.steps == sum && sd.primary_fallbacks == sd.fallbacks);

    p.depth_only = 0; /* with normals and shadow rays */
    assert_int_equal(sdft_render(&f, &p, &full, &sf, NULL, 0), 0);
    assert_memory_equal(full.primary_steps, depth.primary_steps, n * sizeof(uint32_t));
    uint64_t shadow = 0, shadowed_pixels = 0;
    for (size_t i = 0; i < n; i++) {
        assert_true(full.steps[i] >= full.primary_steps[i] && full.fallbacks[i] >= depth.fallbacks[i]);
        shadow += full.steps[i] - full.primary_steps[i];
        shadowed_pixels += full.steps[i] > full.primary_steps[i];
    }
    assert_true(shadowed_pixels > 100);
    assert_true(sf.primary_steps == sd.primary_steps && sf.steps - sf.primary_steps == shadow);
    assert_true(sf.primary_fallbacks == sd.fallbacks && sf.fallbacks >= sf.primary_fallbacks);
    sdft_image_free(&depth);
    sdft_image_free(&full);
    free(pc.per_pixel);
}

static void test_screen_space(void **state)
{
    (void)state;
    test_scene sc = {.centre = {0, 0, 0}, .radius = 1.0f};
    sdft_field f = test_field(&sc);
    sdft_render_params p = small_params();
    p.screen_space = 1;
    p.trace.eps = 0.0f;
    sdft_image img;
    assert_int_equal(sdft_image_alloc(&img, p.width, p.height, NULL, 0), 0);
    sdft_render_stats st;
    assert_int_equal(sdft_render(&f, &p, &img, &st, NULL, 0), 0);
    assert_true(st.hits > 300);
    /* Without it, eps 0 alone is rejected by the parameter check. */
    p.screen_space = 0;
    char msg[128] = "";
    assert_int_not_equal(sdft_render(&f, &p, &img, &st, msg, sizeof msg), 0);
    assert_true(strlen(msg) > 0 && strchr(msg, '\n') == NULL);
    sdft_image_free(&img);
}

/* A cone's spread covers every ray through its rectangle, and its march
 * never passes a surface any of them meets: against analytic ray-sphere
 * hits of rays through random points of each block, over a sphere seen
 * from several views (union of the sphere and its far twin, exact SDF). */
static float two_spheres(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    return fminf(sdft_length(p) - 0.7f, sdft_length(sdft_sub(p, sdft_v3(1.5f, 0.3f, -2.0f))) - 0.5f);
}

static void test_cones_never_pass_a_surface(void **state)
{
    (void)state;
    sdft_field f = {.distance = two_spheres, .bounds = {{-0.7f, -0.7f, -2.5f}, {2.0f, 0.8f, 0.7f}}};
    sdft_scratch s;
    tu_rng r = tu_rng_seed(21);
    int blocks = 0, advanced = 0;
    for (int view = 0; view < 6; view++) {
        sdft_camera cam = {.from = sdft_v3(tu_uniform(&r, -3, 3), tu_uniform(&r, -1, 2), tu_uniform(&r, 3, 6)),
                           .at = sdft_v3(tu_uniform(&r, -0.3f, 1.0f), 0, -0.5f),
                           .up = {0, 1, 0},
                           .fov_deg = tu_uniform(&r, 30, 80)};
        const int w = 96, h = 64;
        sdft_view v = sdft_camera_view(&cam, w, h);
        for (int n = 4; n <= 16; n *= 4)
            for (int y0 = 0; y0 < h; y0 += n)
                for (int x0 = 0; x0 < w; x0 += n) {
                    sdft_vec3 axis;
                    const float spread =
                        sdft_view_cone(&v, (float)x0, (float)y0, (float)(x0 + n), (float)(y0 + n), &axis);
                    uint32_t steps = 0;
                    const float t = sdft_cone_march(&f, &s, cam.from, axis, spread, 0.0f, 100.0f, &steps);
                    assert_true(steps >= 1 && steps <= 64);
                    blocks++;
                    advanced += t > 0.0f;
                    for (int k = 0; k < 64; k++) {
                        sdft_ray ray =
                            sdft_view_ray(&v, x0 + tu_uniform(&r, 0, (float)n), y0 + tu_uniform(&r, 0, (float)n));
                        assert_true(sdft_length(sdft_sub(ray.dir, axis)) <= spread);
                        float d0, d1;
                        const float hit = fminf(ray_sphere(ray, sdft_v3(0, 0, 0), 0.7f, &d0),
                                                ray_sphere(ray, sdft_v3(1.5f, 0.3f, -2.0f), 0.5f, &d1));
                        if (t > hit)
                            fail_msg("view %d block (%d, %d) of %d: the cone reached %g, a ray hits at %g", view, x0,
                                     y0, n, t, hit);
                    }
                }
    }
    assert_true(advanced > blocks / 2); /* the cones do move */
}

/* With cones the picture is the same: every pixel's status, and depth to
 * within the convergence radius's reach, for every variant; the total
 * evaluations (per ray plus shared) drop; and the result does not depend
 * on the thread count. Depth-only renders give the same depths and counts
 * as full ones without shadows, and leave colour and normals zero. */
static void test_cones_and_depth_only(void **state)
{
    (void)state;
    test_scene sc = {.centre = {0, 0, 0}, .radius = 0.8f, .has_floor = 1, .floor_y = -0.8f};
    sdft_field f = test_field(&sc);
    for (int m = 0; m < SDFT_METHOD_COUNT; m++) {
        sdft_render_params p = small_params();
        sdft_render_papers(&p); /* every ray from the eye first */
        p.width = 77, p.height = 53;
        p.shadows = 0;
        p.trace.method = (sdft_method)m;
        p.trace.omega = sdft_default_omega((sdft_method)m);
        sdft_image plain, coned, coned1, depth;
        sdft_render_stats sp, sc2, sc1, sd;
        assert_int_equal(sdft_image_alloc(&plain, p.width, p.height, NULL, 0), 0);
        assert_int_equal(sdft_image_alloc(&coned, p.width, p.height, NULL, 0), 0);
        assert_int_equal(sdft_image_alloc(&coned1, p.width, p.height, NULL, 0), 0);
        assert_int_equal(sdft_image_alloc(&depth, p.width, p.height, NULL, 0), 0);
        assert_int_equal(sdft_render(&f, &p, &plain, &sp, NULL, 0), 0);
        p.depth_only = 1;
        assert_int_equal(sdft_render(&f, &p, &depth, &sd, NULL, 0), 0);
        p.depth_only = 0;
        p.cones = 1;
        assert_int_equal(sdft_render(&f, &p, &coned, &sc2, NULL, 0), 0);
        p.threads = 1;
        assert_int_equal(sdft_render(&f, &p, &coned1, &sc1, NULL, 0), 0);
        assert_true(images_equal(&coned, &coned1));
        assert_true(sc2.steps == sc1.steps && sc2.cone_steps == sc1.cone_steps);
        assert_true(sp.cone_steps == 0 && sc2.cone_steps > 0);
        assert_true(sc2.steps + sc2.cone_steps < sp.steps);
        assert_true(sd.steps == sp.steps && sd.hits == sp.hits);
        for (size_t i = 0; i < (size_t)p.width * p.height; i++) {
            assert_int_equal(coned.status[i], plain.status[i]);
            if (plain.status[i] == SDFT_HIT)
                assert_true(fabsf(coned.depth[i] - plain.depth[i]) < 1e-3f);
            assert_memory_equal(&depth.depth[i], &plain.depth[i], sizeof(float));
            assert_true(depth.rgb[3 * i] == 0.0f && depth.normal[3 * i + 1] == 0.0f);
        }
        print_message("%s: %.2f evaluations per pixel, %.2f with cones (%.2f of them shared)\n",
                      sdft_method_name((sdft_method)m), (double)sp.steps / sp.primary_rays,
                      (double)(sc2.steps + sc2.cone_steps) / sp.primary_rays, (double)sc2.cone_steps / sp.primary_rays);
        sdft_image_free(&plain);
        sdft_image_free(&coned);
        sdft_image_free(&coned1);
        sdft_image_free(&depth);
    }
}

/* Cones are the default, and sdft_render_papers turns them off. */
static void test_defaults_and_the_papers_counting(void **state)
{
    (void)state;
    sdft_render_params p = sdft_render_defaults();
    assert_true(p.cones == 1 && p.trace.exact_root == 1);
    sdft_render_papers(&p);
    assert_true(p.cones == 0 && p.trace.exact_root == 0);
    assert_true(p.trace.method == sdft_trace_defaults().method && p.width == 1280);
}

/* An image of `width` x p.height, every plane first filled with 0xff
 * bytes (NaNs, huge counts), rendered by a camera that sees nothing of f:
 * every plane holds a miss's values. */
static void culled_planes_written(const sdft_field *f, sdft_render_params p, int width)
{
    p.width = width;
    sdft_image a;
    sdft_render_stats sa;
    assert_int_equal(sdft_image_alloc(&a, p.width, p.height, NULL, 0), 0);
    const size_t n = (size_t)p.width * p.height;
    memset(a.steps, 0xff, n * sizeof *a.steps);
    memset(a.primary_steps, 0xff, n * sizeof *a.primary_steps);
    memset(a.fallbacks, 0xff, n * sizeof *a.fallbacks);
    memset(a.rgb, 0xff, 3 * n * sizeof *a.rgb);
    memset(a.normal, 0xff, 3 * n * sizeof *a.normal);
    memset(a.depth, 0xff, n * sizeof *a.depth);
    memset(a.status, 0xff, n * sizeof *a.status);
    assert_int_equal(sdft_render(f, &p, &a, &sa, NULL, 0), 0);
    assert_true(sa.hits == 0 && sa.steps == 0 && sa.cone_steps == 0 && sa.rays == n);
    for (size_t i = 0; i < n; i++) {
        assert_true(a.status[i] == SDFT_MISS && isinf(a.depth[i]) && a.depth[i] > 0.0f);
        assert_true(a.rgb[3 * i] > 0.25f && a.rgb[3 * i + 1] > 0.45f && a.rgb[3 * i + 2] > 0.8f); /* sky */
        assert_true(a.normal[3 * i] == 0.0f && a.normal[3 * i + 1] == 0.0f && a.normal[3 * i + 2] == 0.0f);
        assert_true(a.steps[i] == 0 && a.primary_steps[i] == 0 && a.fallbacks[i] == 0);
    }
    sdft_image_free(&a);
}

/* Tiles whose rays all pass the field's box by are filled without a trace
 * (render.c): the picture is the one tracing every ray gives. A small
 * sphere off to one side of a wide view, with its own box, against the
 * same sphere in a box around the whole view (nothing culled): every
 * pixel's colour, depth, normal and status agree; the culled frame does
 * less work; and a camera turned away from the sphere gives sky alone,
 * without a single evaluation. */
static void test_culled_tiles_match_traced_ones(void **state)
{
    (void)state;
    test_scene sc = {.centre = {1.1f, 0.4f, 0.0f}, .radius = 0.3f};
    sdft_field small = test_field(&sc), wide = small;
    wide.bounds = (sdft_aabb){{-30, -30, -30}, {30, 30, 30}};
    sdft_render_params p = small_params();
    p.width = 160, p.height = 90;
    sdft_image a, b;
    sdft_render_stats sa, sb;
    assert_int_equal(sdft_image_alloc(&a, p.width, p.height, NULL, 0), 0);
    assert_int_equal(sdft_image_alloc(&b, p.width, p.height, NULL, 0), 0);
    assert_int_equal(sdft_render(&small, &p, &a, &sa, NULL, 0), 0);
    assert_int_equal(sdft_render(&wide, &p, &b, &sb, NULL, 0), 0);
    const size_t n = (size_t)p.width * p.height;
    size_t hits = 0;
    for (size_t i = 0; i < n; i++) {
        assert_int_equal(a.status[i], b.status[i]);
        hits += a.status[i] == SDFT_HIT;
        if (a.status[i] == SDFT_HIT) {
            assert_true(fabsf(a.depth[i] - b.depth[i]) < 1e-3f);
            continue;
        }
        assert_memory_equal(&a.rgb[3 * i], &b.rgb[3 * i], 3 * sizeof(float));
        assert_true(isinf(a.depth[i]) && a.normal[3 * i] == 0.0f && a.normal[3 * i + 2] == 0.0f);
    }
    assert_true(hits > 100 && hits < n / 4);
    assert_true(sa.steps + sa.cone_steps < sb.steps + sb.cone_steps);
    p.camera.at = sdft_add(p.camera.from, sdft_sub(p.camera.from, p.camera.at)); /* turned around */
    /* Every plane of a culled tile is written, the counts too: an image
     * reused from an earlier frame keeps nothing of it. At 160 pixels across
     * each tile's rows are written whole (render.c: non-temporal stores); at
     * 150 the last tile's rows of 6 are written word by word. */
    sdft_image_free(&a);
    sdft_image_free(&b);
    for (int wide_image = 1; wide_image >= 0; wide_image--)
        culled_planes_written(&small, p, wide_image ? 160 : 150);
}

static void test_bad_params(void **state)
{
    (void)state;
    test_scene sc = {.centre = {0, 0, 0}, .radius = 1.0f};
    sdft_field f = test_field(&sc);
    sdft_render_params good = small_params();
    sdft_image img;
    assert_int_equal(sdft_image_alloc(&img, good.width, good.height, NULL, 0), 0);
    sdft_render_params bad[6];
    for (int k = 0; k < 6; k++)
        bad[k] = good;
    bad[0].width = 0;
    bad[1].trace.method = SDFT_RELAXED, bad[1].trace.omega = 2.0f;
    bad[2].trace.beta = NAN;
    bad[3].camera.fov_deg = 180.0f;
    bad[4].camera.at = bad[4].camera.from;
    bad[5].width = good.width + 1; /* not the image's size */
    for (int k = 0; k < 6; k++) {
        char msg[128] = "";
        assert_int_not_equal(sdft_render(&f, &bad[k], &img, NULL, msg, sizeof msg), 0);
        assert_true(strlen(msg) > 0);
    }
    sdft_image_free(&img);
    assert_int_not_equal(sdft_image_alloc(&img, 0, 5, NULL, 0), 0);
    assert_null(img.rgb);
    sdft_image_free(&img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_camera_frame),
        cmocka_unit_test(test_depth_is_analytic),
        cmocka_unit_test(test_thread_count_invariant),
        cmocka_unit_test(test_shadows_and_counts),
        cmocka_unit_test(test_primary_steps_plane),
        cmocka_unit_test(test_screen_space),
        cmocka_unit_test(test_bad_params),
        cmocka_unit_test(test_cones_never_pass_a_surface),
        cmocka_unit_test(test_cones_and_depth_only),
        cmocka_unit_test(test_defaults_and_the_papers_counting),
        cmocka_unit_test(test_culled_tiles_match_traced_ones),
    };
    return cmocka_run_group_tests_name("render", tests, NULL, NULL);
}
