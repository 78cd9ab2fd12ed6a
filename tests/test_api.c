/* sdftrace tests — the public C API's contract: one error convention
 * (sdftrace/error.h), so every bad argument of every fallible public
 * function gets its code and one line, and writes no file; the refusals of
 * the tracing entry points; the error names; the version. Expected values
 * are written out here, never taken from the library. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sdftrace/error.h"
#include "sdftrace/grid.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/trace.h"
#include "sdftrace/vdb.h"
#include "testutil.h"

static char msg[512];

/* A call returned `want`, with a reason on one line. */
#define expect_code(call, want)                                                                                        \
    do {                                                                                                               \
        memset(msg, 0, sizeof msg);                                                                                    \
        const int got_ = (int)(call);                                                                                  \
        if (got_ != (int)(want) || !msg[0] || strchr(msg, '\n'))                                                       \
            fail_msg("%s: got %s '%s', want %s", #call, sdft_error_name((sdft_error)got_), msg,                        \
                     sdft_error_name(want));                                                                           \
    } while (0)

static float unit_sphere(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    return sdft_length(p) - 1.0f;
}

static void keep_nothing(const void *ctx, sdft_scratch *s) { (void)ctx, (void)s; }

static sdft_field sphere_field(void)
{
    sdft_field f = sdft_field_defaults();
    f.distance = unit_sphere;
    f.bounds = (sdft_aabb){{-1, -1, -1}, {1, 1, 1}};
    return f;
}

/* A field and its accel start with nothing set; a field without a
 * distance is refused. */
static void test_field_defaults(void **state)
{
    (void)state;
    const sdft_field f = sdft_field_defaults();
    assert_true(!f.distance && !f.normal && !f.scratch_init && !f.ctx && !f.accel && f.feature_size == 0.0f);
    const sdft_field_accel a = sdft_field_accel_defaults();
    assert_true(!a.ctx && !a.root && a.root_reach == 0.0f && !a.prefetch);
    assert_true(!a.hull && a.hull_count == 0 && !a.hull_slabs && !a.hull_gradients);
    sdft_scratch s;
    sdft_scratch_init(&f, &s);
    sdft_trace_params p = sdft_trace_defaults();
    const sdft_ray ray = {.org = {0, 0, 5}, .tnear = 0, .dir = {0, 0, -1}, .tfar = INFINITY};
    assert_int_equal(sdft_trace(&f, &s, &ray, &p).status, SDFT_INVALID);
}

static void test_error_names(void **state)
{
    (void)state;
    static const struct {
        sdft_error code;
        const char *name;
    } all[] = {{SDFT_OK, "SDFT_OK"},
               {SDFT_EINVAL, "SDFT_EINVAL"},
               {SDFT_EIO, "SDFT_EIO"},
               {SDFT_EFORMAT, "SDFT_EFORMAT"},
               {SDFT_ENOTSCALAR, "SDFT_ENOTSCALAR"},
               {SDFT_ENOTFOUND, "SDFT_ENOTFOUND"},
               {SDFT_EEMPTY, "SDFT_EEMPTY"},
               {SDFT_ENOMEM, "SDFT_ENOMEM"},
               {SDFT_ECANCELED, "SDFT_ECANCELED"},
               {SDFT_EINTERNAL, "SDFT_EINTERNAL"}};
    assert_int_equal(SDFT_OK, 0);
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        assert_string_equal(sdft_error_name(all[i].code), all[i].name);
    assert_string_equal(sdft_error_name((sdft_error)(SDFT_EINTERNAL + 1)), "SDFT_E?");
    assert_string_equal(sdft_error_name((sdft_error)-1), "SDFT_E?");
}

/* The version: the macros agree with each other and with the project's
 * VERSION in CMakeLists.txt, and the library is the headers'. */
static void test_version(void **state)
{
    (void)state;
    char want[64];
    snprintf(want, sizeof want, "%d.%d.%d", SDFT_VERSION_MAJOR, SDFT_VERSION_MINOR, SDFT_VERSION_PATCH);
    assert_string_equal(SDFT_VERSION_STRING, want);
    assert_int_equal(SDFT_VERSION, SDFT_VERSION_MAJOR * 10000 + SDFT_VERSION_MINOR * 100 + SDFT_VERSION_PATCH);
    assert_int_equal(sdft_version(), SDFT_VERSION);
    char project[256];
    FILE *f = fopen(SDFT_SOURCE_DIR "/CMakeLists.txt", "r");
    assert_non_null(f);
    int found = 0;
    while (!found && fgets(project, sizeof project, f))
        found = strncmp(project, "project(sdftrace VERSION ", 25) == 0;
    fclose(f);
    assert_true(found);
    assert_int_equal(strncmp(project + 25, want, strlen(want)), 0);
    assert_true(project[25 + strlen(want)] == ' ' || project[25 + strlen(want)] == ')');
}

/* Truncation: a short buffer gets the line's start, NUL-terminated; a NULL
 * buffer gets nothing and the code still comes back. */
static void test_message_buffer(void **state)
{
    (void)state;
    char small[8];
    memset(small, 'x', sizeof small);
    assert_int_equal(sdft_trace_params_check(NULL, small, sizeof small), SDFT_EINVAL);
    assert_true(strlen(small) == sizeof small - 1);
    assert_int_equal(sdft_trace_params_check(NULL, NULL, 0), SDFT_EINVAL);
    assert_int_equal(sdft_trace_params_check(NULL, small, 0), SDFT_EINVAL);
}

static void test_trace_refusals(void **state)
{
    (void)state;
    sdft_field f = sphere_field(), stateful = f, none = {0};
    stateful.scratch_init = keep_nothing;
    sdft_scratch s;
    sdft_scratch_init(&f, &s);
    const sdft_ray ray = {.org = {0, 0, 5}, .tnear = 0, .dir = {0, 0, -1}, .tfar = INFINITY};
    sdft_trace_params p = sdft_trace_defaults();
    assert_int_equal(sdft_trace(&f, &s, &ray, &p).status, SDFT_HIT);

    sdft_trace_params unknown = p, negative = p;
    unknown.method = SDFT_METHOD_COUNT;
    negative.method = (sdft_method)-1;
    const struct {
        const sdft_field *f;
        sdft_scratch *s;
        const sdft_ray *ray;
        const sdft_trace_params *p;
        const char *why;
    } bad[] = {{NULL, &s, &ray, &p, "no field"},
               {&none, &s, &ray, &p, "no field"},
               {&f, NULL, &ray, &p, "no scratch"},
               {&f, &s, NULL, &p, NULL},
               {&f, &s, &ray, NULL, "no trace parameters"},
               {&f, &s, &ray, &unknown, "unknown tracing method"},
               {&f, &s, &ray, &negative, "unknown tracing method"},
               {&stateful, &s, &ray, &p, "another field"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sdft_hit h = sdft_trace(bad[i].f, bad[i].s, bad[i].ray, bad[i].p);
        if (h.status != SDFT_INVALID || h.steps != 0 || !isnan(h.t))
            fail_msg("case %zu: status %d, %u steps, t %g", i, h.status, h.steps, h.t);
        sdft_hit hits[3];
        sdft_ray rays[3] = {ray, ray, ray};
        sdft_trace_stream(bad[i].f, bad[i].s, bad[i].ray ? rays : NULL, hits, 3, bad[i].p);
        for (int k = 0; k < 3; k++)
            assert_int_equal(hits[k].status, SDFT_INVALID);
        if (bad[i].why) {
            expect_code(sdft_trace_check(bad[i].f, bad[i].s, bad[i].p, msg, sizeof msg), SDFT_EINVAL);
            if (!strstr(msg, bad[i].why))
                fail_msg("case %zu: '%s' lacks '%s'", i, msg, bad[i].why);
        }
        if (bad[i].p == &p && bad[i].ray) { /* the cases of the field and the scratch */
            uint32_t steps = 7;
            assert_true(sdft_cone_march(bad[i].f, bad[i].s, ray.org, ray.dir, 0.01f, 0.5f, 10.0f, &steps) == 0.5f);
            assert_int_equal(steps, 7);
        }
    }
    uint32_t steps = 0; /* and a good cone marches */
    assert_true(sdft_cone_march(&f, &s, ray.org, ray.dir, 0.01f, 0.0f, 10.0f, &steps) > 3.0f);
    assert_true(steps > 0);
    assert_int_equal(sdft_trace_check(&f, &s, &p, msg, sizeof msg), SDFT_OK);
    p.eps = -1.0f; /* sdft_trace_check also checks the parameters' ranges */
    expect_code(sdft_trace_check(&f, &s, &p, msg, sizeof msg), SDFT_EINVAL);
}

static void test_params_and_method_names(void **state)
{
    (void)state;
    const sdft_trace_params good = sdft_trace_defaults();
    assert_int_equal(good.method, SDFT_AUTO);
    assert_true(good.omega == 1.0f && good.beta == 0.3f && good.eps == 1e-4f && good.max_steps == 1000);
    sdft_trace_params bad[14];
    for (int i = 0; i < 14; i++)
        bad[i] = good;
    bad[0].method = (sdft_method)9;
    bad[1].method = SDFT_RELAXED, bad[1].omega = 2.0f;
    bad[2].method = SDFT_RELAXED, bad[2].omega = 0.99f;
    bad[3].method = SDFT_ENHANCED, bad[3].omega = 0.0f;
    bad[4].method = SDFT_ENHANCED, bad[4].omega = 1.01f;
    bad[5].beta = 0.0f;
    bad[6].beta = 1.0f;
    bad[7].eps = NAN;
    bad[8].eps = -1e-3f;
    bad[9].pixel_radius = INFINITY;
    bad[10].eps = 0.0f, bad[10].pixel_radius = 0.0f;
    bad[11].max_steps = 0;
    bad[12].method = SDFT_RELAXED_BV, bad[12].omega = 2.0f;
    bad[13].method = SDFT_RELAXED_BV, bad[13].omega = 0.99f;
    for (int i = 0; i < 14; i++)
        expect_code(sdft_trace_params_check(&bad[i], msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_trace_params_check(NULL, msg, sizeof msg), SDFT_EINVAL);

    static const char *const names[] = {"sphere", "relaxed", "enhanced", "auto", "relaxed-bv"};
    for (int m = 0; m < SDFT_METHOD_COUNT; m++) {
        sdft_method got = (sdft_method)-1;
        assert_int_equal(sdft_method_parse(names[m], &got, msg, sizeof msg), SDFT_OK);
        assert_int_equal(got, m);
        assert_string_equal(sdft_method_name((sdft_method)m), names[m]);
    }
    assert_string_equal(sdft_method_name(SDFT_METHOD_COUNT), "unknown");
    sdft_method m = SDFT_SPHERE;
    expect_code(sdft_method_parse("Sphere", &m, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_method_parse("", &m, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_method_parse(NULL, &m, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_method_parse("auto", NULL, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(m, SDFT_SPHERE);
}

static void test_image_and_render_errors(void **state)
{
    (void)state;
    sdft_image img;
    memset(&img, 0x5a, sizeof img);
    expect_code(sdft_image_alloc(&img, 0, 5, msg, sizeof msg), SDFT_EINVAL);
    assert_null(img.rgb);
    expect_code(sdft_image_alloc(&img, 5, -1, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_image_alloc(&img, 1 << 30, 1 << 30, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_image_alloc(NULL, 5, 5, msg, sizeof msg), SDFT_EINVAL);
    sdft_image_free(NULL);
    sdft_image_free(&img); /* all zero after a failure: nothing to free */

    sdft_field f = sphere_field(), none = {0};
    sdft_render_params good = sdft_render_defaults();
    good.width = 16, good.height = 9;
    assert_int_equal(sdft_image_alloc(&img, 16, 9, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_render(&f, &good, &img, NULL, msg, sizeof msg), SDFT_OK);
    enum { N = 12 };
    sdft_render_params bad[N];
    for (int i = 0; i < N; i++)
        bad[i] = good;
    bad[0].width = 0;
    bad[1].width = 17; /* not the image's size */
    bad[2].height = -9;
    bad[3].camera.at = bad[3].camera.from;
    bad[4].camera.from.x = NAN;
    bad[5].camera.up.y = INFINITY;
    bad[6].camera.fov_deg = 0.0f;
    bad[7].camera.fov_deg = 180.0f;
    bad[8].light.z = NAN;
    bad[9].threads = -1;
    bad[10].trace.beta = 2.0f;
    bad[11].trace.method = (sdft_method)7;
    for (int i = 0; i < N; i++) {
        expect_code(sdft_render(&f, &bad[i], &img, NULL, msg, sizeof msg), SDFT_EINVAL);
        /* the same checks without the image: all but bad[1], the image's size */
        if (i == 1)
            assert_int_equal(sdft_render_params_check(&f, &bad[i], msg, sizeof msg), SDFT_OK);
        else
            expect_code(sdft_render_params_check(&f, &bad[i], msg, sizeof msg), SDFT_EINVAL);
    }
    assert_int_equal(sdft_render_params_check(&f, &good, msg, sizeof msg), SDFT_OK);
    expect_code(sdft_render_params_check(NULL, &good, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_render_params_check(&none, &good, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_render_params_check(&f, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_render(NULL, &good, &img, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_render(&none, &good, &img, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_render(&f, NULL, &img, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_render(&f, &good, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    sdft_image unallocated = {.width = 16, .height = 9};
    expect_code(sdft_render(&f, &good, &unallocated, NULL, msg, sizeof msg), SDFT_EINVAL);
    sdft_image_free(&img);
}

/* A NanoVDB grid in memory, baked, and a file holding it. */
static sdft_grid *small_grid(const char *nvdb_path)
{
    sdft_field f = sphere_field();
    f.bounds = (sdft_aabb){{-1.2f, -1.2f, -1.2f}, {1.2f, 1.2f, 1.2f}};
    sdft_bake_params p = sdft_bake_defaults();
    p.res = 24;
    sdft_grid *g = NULL;
    assert_int_equal(sdft_bake(&f, &p, nvdb_path, &g, NULL, msg, sizeof msg), SDFT_OK);
    return g;
}

static int released;
static void count_release(void *p)
{
    released++;
    free(p);
}

static void test_grid_errors(void **state)
{
    (void)state;
    char nvdb[512];
    tu_tmp(nvdb, sizeof nvdb, "api.nvdb");
    sdft_grid *g = small_grid(nvdb), *out = (sdft_grid *)&out;
    size_t size;
    const void *bytes = sdft_grid_data(g, &size);

    expect_code(tu_open_nvdb(NULL, NULL, &out, msg, sizeof msg), SDFT_EINVAL);
    assert_null(out);
    expect_code(tu_open_nvdb(nvdb, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_nvdb(SDFT_TEST_TMP "/no-such.nvdb", NULL, &out, msg, sizeof msg), SDFT_EIO);
    expect_code(tu_open_nvdb(SDFT_TEST_TMP, NULL, &out, msg, sizeof msg), SDFT_EIO); /* a folder */
    expect_code(tu_open_nvdb(nvdb, "nosuch", &out, msg, sizeof msg), SDFT_ENOTFOUND);
    assert_null(out);

    static const unsigned char junk[64] = {1, 2, 3};
    expect_code(tu_open_buffer(NULL, size, NULL, SDFT_GRID_COPY, NULL, &out, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_buffer(bytes, 0, NULL, SDFT_GRID_COPY, NULL, &out, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_buffer(bytes, size, NULL, SDFT_GRID_COPY, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_buffer(junk, sizeof junk, NULL, SDFT_GRID_COPY, NULL, &out, msg, sizeof msg), SDFT_EFORMAT);
    expect_code(tu_open_buffer(bytes, size - 32, NULL, SDFT_GRID_COPY, NULL, &out, msg, sizeof msg), SDFT_EFORMAT);
    expect_code(tu_open_buffer(bytes, size, "nosuch", SDFT_GRID_COPY, NULL, &out, msg, sizeof msg), SDFT_ENOTFOUND);
    expect_code(tu_open_buffer(NULL, size, NULL, SDFT_GRID_BORROW, NULL, &out, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_buffer(bytes, size, NULL, SDFT_GRID_BORROW, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_buffer(junk, sizeof junk, NULL, SDFT_GRID_BORROW, NULL, &out, msg, sizeof msg), SDFT_EFORMAT);
    /* A grid starting off NanoVDB's 32-byte alignment cannot be read in place. */
    unsigned char *shifted = malloc(size + 8);
    assert_non_null(shifted);
    memcpy(shifted + 8, bytes, size);
    expect_code(tu_open_buffer(shifted + 8, size, NULL, SDFT_GRID_BORROW, NULL, &out, msg, sizeof msg), SDFT_EINVAL);
    assert_null(out);
    assert_int_equal(tu_open_buffer(shifted + 8, size, NULL, SDFT_GRID_COPY, NULL, &out, msg, sizeof msg),
                     SDFT_OK); /* copied */
    sdft_grid_free(out);
    free(shifted);

    /* An adopted buffer is released exactly once: when the grid is freed,
     * or at once when it is refused. */
    released = 0;
    expect_code(tu_open_buffer(NULL, size, NULL, SDFT_GRID_ADOPT, count_release, &out, msg, sizeof msg), SDFT_EINVAL);
    void *mine = aligned_alloc(32, (size + 31) & ~(size_t)31);
    assert_non_null(mine);
    memcpy(mine, bytes, size);
    expect_code(tu_open_buffer(mine, size, NULL, SDFT_GRID_ADOPT, NULL, &out, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_buffer(mine, size, "nosuch", SDFT_GRID_ADOPT, count_release, &out, msg, sizeof msg),
                SDFT_ENOTFOUND);
    assert_int_equal(released, 1);
    assert_null(out);
    mine = aligned_alloc(32, (size + 31) & ~(size_t)31);
    assert_non_null(mine);
    memcpy(mine, bytes, size);
    assert_int_equal(tu_open_buffer(mine, size, NULL, SDFT_GRID_ADOPT, count_release, &out, msg, sizeof msg), SDFT_OK);
    assert_int_equal(released, 1);
    assert_true(sdft_grid_data(out, NULL) == mine);
    assert_true(sdft_grid_voxel(out, 0, 0, 0, NULL) == sdft_grid_voxel(g, 0, 0, 0, NULL));
    sdft_grid_free(out);
    assert_int_equal(released, 2);

    /* The options: their defaults, none at all, an unknown memory, a .vdb
     * file (the OpenVDB component's call reads those). */
    const sdft_grid_options d = sdft_grid_options_defaults();
    assert_true(!d.path && !d.name && !d.data && d.memory == SDFT_GRID_COPY && !d.release && !d.fill);
    assert_true(d.defer == SDFT_DEFER_NONE && d.quant == SDFT_QUANT_NONE && d.stream == 1 && !d.progress);
    expect_code(sdft_grid_open(NULL, &out, msg, sizeof msg), SDFT_EINVAL);
    sdft_grid_options odd_memory = d;
    odd_memory.data = bytes, odd_memory.size = size, odd_memory.memory = (sdft_grid_memory)5;
    expect_code(sdft_grid_open(&odd_memory, &out, msg, sizeof msg), SDFT_EINVAL);
    assert_null(out);
    sdft_grid_options vdb_file = d;
    vdb_file.path = "x.vdb";
    expect_code(sdft_grid_open(&vdb_file, &out, msg, sizeof msg), SDFT_EFORMAT);

    /* Exporting: no grid or no place for the bytes. */
    void *exported = (void *)&out;
    size_t exported_size = 1;
    expect_code(sdft_grid_export(NULL, &exported, &exported_size, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_grid_export(g, NULL, &exported_size, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_grid_export(g, &exported, NULL, msg, sizeof msg), SDFT_EINVAL);

    /* Fields of no grid, or of an unknown bound, are empty; tracing refuses them. */
    sdft_field zero = sdft_grid_field(NULL, SDFT_GRID_BOUND_FAR), odd = sdft_grid_field(g, (sdft_grid_bound)3);
    assert_null(zero.distance);
    assert_null(odd.distance);
    sdft_scratch s;
    sdft_scratch_init(&zero, &s);
    sdft_trace_params p = sdft_trace_defaults();
    const sdft_ray ray = {.org = {0, 0, 5}, .tnear = 0, .dir = {0, 0, -1}, .tfar = INFINITY};
    assert_int_equal(sdft_trace(&zero, &s, &ray, &p).status, SDFT_INVALID);

    /* Materials: a NULL grid or table, none, too many, one out of range; a table grid that is none. */
    sdft_material m = {.colour = {0.5f, 0.5f, 0.5f}, .reflectance = 0.0f, .ior = 0.0f};
    expect_code(sdft_grid_set_materials(NULL, g, &m, 1, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_grid_set_materials(g, g, NULL, 1, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_grid_set_materials(g, g, &m, 0, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_grid_set_materials(g, g, &m, SDFT_GRID_MAX_MATERIALS + 1, msg, sizeof msg), SDFT_EINVAL);
    m.reflectance = 2.0f;
    expect_code(sdft_grid_set_materials(g, g, &m, 1, msg, sizeof msg), SDFT_EINVAL);
    size_t count;
    expect_code(sdft_grid_material_table(NULL, &m, 1, &count, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_grid_material_table(g, NULL, 1, &count, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_grid_material_table(g, &m, 1, NULL, msg, sizeof msg), SDFT_EINVAL);
    assert_null(sdft_grid_field(g, SDFT_GRID_BOUND_FAR).material);
    sdft_grid_free(NULL);
    sdft_grid_free(g);
}

static void test_vdb_errors(void **state)
{
    (void)state;
    sdft_grid *out = (sdft_grid *)&out;
    expect_code(tu_open_file(NULL, NULL, SDFT_QUANT_NONE, &out, msg, sizeof msg), SDFT_EINVAL);
    assert_null(out);
    expect_code(tu_open_file("x.vdb", NULL, SDFT_QUANT_NONE, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_file("x.vdb", NULL, (sdft_quant)9, &out, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_file(SDFT_TEST_TMP "/no-such.vdb", NULL, SDFT_QUANT_NONE, &out, msg, sizeof msg), SDFT_EIO);
    const sdft_grid_options vo = sdft_grid_options_defaults();
    assert_true(vo.quant == SDFT_QUANT_NONE && !vo.progress && vo.stream == 1);
    expect_code(tu_open_with("x.vdb", NULL, NULL, &out, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_with(NULL, NULL, &vo, &out, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_with("x.vdb", NULL, &vo, NULL, msg, sizeof msg), SDFT_EINVAL);
    sdft_grid_options odd = vo;
    odd.quant = (sdft_quant)9;
    expect_code(tu_open_with("x.vdb", NULL, &odd, &out, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_with(SDFT_TEST_TMP "/no-such.vdb", NULL, &vo, &out, msg, sizeof msg), SDFT_EIO);
    sdft_aabb box;
    expect_code(sdft_vdb_bounds(NULL, NULL, &box, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_vdb_bounds("x.vdb", NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_vdb_bounds(SDFT_TEST_TMP "/no-such.vdb", NULL, &box, msg, sizeof msg), SDFT_EIO);
    expect_code(tu_open_file(NULL, NULL, SDFT_QUANT_NONE, &out, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_file("x.vdb", NULL, SDFT_QUANT_NONE, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(tu_open_file("x.txt", NULL, SDFT_QUANT_NONE, &out, msg, sizeof msg), SDFT_EFORMAT);
    expect_code(tu_open_file(SDFT_TEST_TMP "/no-such.nvdb", NULL, SDFT_QUANT_NONE, &out, msg, sizeof msg), SDFT_EIO);

    /* sdft_bake: each bad argument, and no file written. */
    char path[512];
    tu_tmp(path, sizeof path, "api_never.vdb");
    remove(path);
    sdft_field f = sphere_field(), none = {0}, infinite = f, flat = f;
    infinite.bounds.hi.x = INFINITY;
    flat.bounds.hi = flat.bounds.lo;
    const sdft_bake_params good = sdft_bake_defaults();
    assert_true(good.res == 256 && good.band == 3.0f && !good.full && !good.fp16 && !good.grid_name && !good.progress &&
                good.threads == 0);
    enum { N = 7 };
    sdft_bake_params bad[N];
    for (int i = 0; i < N; i++)
        bad[i] = good, bad[i].res = 16;
    bad[0].res = 0;
    bad[1].res = SDFT_BAKE_MAX_RES + 1;
    bad[2].band = 0.0f;
    bad[3].band = NAN;
    bad[4].band = 1001.0f;
    bad[5].threads = -2;
    bad[6].res = -5;
    for (int i = 0; i < N; i++)
        expect_code(sdft_bake(&f, &bad[i], path, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    sdft_bake_params small = good;
    small.res = 16;
    expect_code(sdft_bake(NULL, &small, path, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_bake(&none, &small, path, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_bake(&f, NULL, path, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_bake(&infinite, &small, path, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_bake(&flat, &small, path, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_bake(&f, &small, SDFT_TEST_TMP "/api_never.exr", NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    expect_code(sdft_bake(&f, &small, SDFT_TEST_TMP "/no/such/dir/x.vdb", NULL, NULL, msg, sizeof msg), SDFT_EIO);
    expect_code(sdft_bake(&f, &small, SDFT_TEST_TMP, NULL, NULL, msg, sizeof msg), SDFT_EINVAL); /* no extension */
    assert_false(tu_file_exists(path));
    assert_false(tu_file_exists(SDFT_TEST_TMP "/api_never.exr"));
    tu_assert_no_temporaries(SDFT_TEST_TMP, "api_never.vdb");
}

/* A progress callback that stops the bake: SDFT_ECANCELED, no file; one
 * that goes on sees a fraction that never decreases and ends at 1. */
typedef struct progress_log {
    int calls, stop_after;
    float last;
    int decreased;
} progress_log;

static int log_progress(void *user, float done)
{
    progress_log *log = user;
    log->decreased |= done < log->last;
    log->last = done;
    return ++log->calls >= log->stop_after;
}

static void test_bake_progress_and_cancel(void **state)
{
    (void)state;
    char path[512];
    tu_tmp(path, sizeof path, "api_cancel.vdb");
    remove(path);
    sdft_field f = sphere_field();
    sdft_bake_params p = sdft_bake_defaults();
    p.res = 64;
    p.progress = log_progress;
    progress_log stop = {.stop_after = 3};
    p.progress_user = &stop;
    expect_code(sdft_bake(&f, &p, path, NULL, NULL, msg, sizeof msg), SDFT_ECANCELED);
    assert_int_equal(stop.calls, 3);
    assert_false(tu_file_exists(path));
    tu_assert_no_temporaries(SDFT_TEST_TMP, "api_cancel.vdb");
    progress_log go = {.stop_after = 1 << 30};
    p.progress_user = &go;
    assert_int_equal(sdft_bake(&f, &p, path, NULL, NULL, msg, sizeof msg), SDFT_OK);
    assert_true(go.calls >= 10 && go.calls <= 101);
    assert_false(go.decreased);
    assert_true(go.last == 1.0f);
    assert_true(tu_file_exists(path));
    remove(path);
}

/* Loading a .vdb reports its progress like a bake, and stops when told:
 * no grid then. Its box from the metadata alone is the loaded grid's. */
static void test_vdb_open_progress_and_cancel(void **state)
{
    (void)state;
    char path[512];
    tu_tmp(path, sizeof path, "api_load.vdb");
    sdft_field f = sphere_field();
    sdft_bake_params bp = sdft_bake_defaults();
    bp.res = 96;
    assert_int_equal(sdft_bake(&f, &bp, path, NULL, NULL, msg, sizeof msg), SDFT_OK);
    sdft_grid_options o = sdft_grid_options_defaults();
    o.progress = log_progress;
    progress_log stop = {.stop_after = 2};
    o.progress_user = &stop;
    sdft_grid *g = (sdft_grid *)&g;
    expect_code(tu_open_with(path, NULL, &o, &g, msg, sizeof msg), SDFT_ECANCELED);
    assert_null(g);
    assert_int_equal(stop.calls, 2);
    progress_log go = {.stop_after = 1 << 30};
    o.progress_user = &go;
    assert_int_equal(tu_open_with(path, NULL, &o, &g, msg, sizeof msg), SDFT_OK);
    assert_true(go.calls >= 10 && go.calls <= 101);
    assert_false(go.decreased);
    assert_true(go.last == 1.0f);
    sdft_aabb box;
    assert_int_equal(sdft_vdb_bounds(path, NULL, &box, msg, sizeof msg), SDFT_OK);
    const sdft_aabb want = sdft_grid_world_bounds(g);
    const float tol = 1e-5f * sdft_grid_voxel_size(g).x;
    assert_true(fabsf(box.lo.x - want.lo.x) <= tol && fabsf(box.lo.y - want.lo.y) <= tol &&
                fabsf(box.lo.z - want.lo.z) <= tol && fabsf(box.hi.x - want.hi.x) <= tol &&
                fabsf(box.hi.y - want.hi.y) <= tol && fabsf(box.hi.z - want.hi.z) <= tol);
    sdft_grid_free(g);
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_error_names),
        cmocka_unit_test(test_field_defaults),
        cmocka_unit_test(test_version),
        cmocka_unit_test(test_message_buffer),
        cmocka_unit_test(test_trace_refusals),
        cmocka_unit_test(test_params_and_method_names),
        cmocka_unit_test(test_image_and_render_errors),
        cmocka_unit_test(test_grid_errors),
        cmocka_unit_test(test_vdb_errors),
        cmocka_unit_test(test_bake_progress_and_cancel),
        cmocka_unit_test(test_vdb_open_progress_and_cancel),
    };
    return cmocka_run_group_tests_name("api", tests, NULL, NULL);
}
