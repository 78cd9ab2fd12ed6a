/* sdftrace tests — the procedural scenes: each is a true signed distance
 * bound (1-Lipschitz everywhere, close pairs at the surface included; empty
 * unbounding spheres), lies inside its bounding box, and its default camera
 * and light see it. And the registry finds each by its unique name. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "sdftrace/camera.h"
#include "sdftrace/scene.h"
#include "testutil.h"

static float field_at(const sdft_scene *s, sdft_vec3 p)
{
    sdft_scratch scratch;
    sdft_scratch_init(&s->field, &scratch);
    return sdft_field_distance(&s->field, &scratch, p);
}

/* Component `axis` (0, 1, 2) of v, by address. */
static float *component(sdft_vec3 *v, int axis) { return axis == 0 ? &v->x : axis == 1 ? &v->y : &v->z; }

static sdft_vec3 box_size(const sdft_scene *s) { return sdft_sub(s->field.bounds.hi, s->field.bounds.lo); }

/* A random point of the bounds grown by `grow` of their size each side. */
static sdft_vec3 point_in_bounds(tu_rng *r, const sdft_scene *s, float grow)
{
    sdft_vec3 lo = s->field.bounds.lo, hi = s->field.bounds.hi, g = sdft_scale(box_size(s), grow);
    return sdft_v3(tu_uniform(r, lo.x - g.x, hi.x + g.x), tu_uniform(r, lo.y - g.y, hi.y + g.y),
                   tu_uniform(r, lo.z - g.z, hi.z + g.z));
}

static sdft_vec3 unit_vector(tu_rng *r)
{
    for (;;) {
        sdft_vec3 v = sdft_v3(tu_uniform(r, -1, 1), tu_uniform(r, -1, 1), tu_uniform(r, -1, 1));
        float l = sdft_length(v);
        if (l > 0.1f && l <= 1.0f)
            return sdft_scale(v, 1.0f / l);
    }
}

/* A point near the surface: a random point walked down the gradient by its
 * own distance until |f| is tiny. Thin rods and plates are found too, since
 * each walk ends at the surface nearest its start. */
static sdft_vec3 point_near_surface(tu_rng *r, const sdft_scene *s)
{
    sdft_scratch scratch;
    sdft_scratch_init(&s->field, &scratch);
    sdft_vec3 p = point_in_bounds(r, s, 0.0f);
    for (int i = 0; i < 40; i++) {
        float f = sdft_field_distance(&s->field, &scratch, p);
        if (fabsf(f) < 1e-5f)
            break;
        p = sdft_madd(p, sdft_field_normal(&s->field, &scratch, p), -f);
    }
    return p;
}

/* Float rounding of an evaluation at p: a few ulps of the coordinates. */
static float rounding(sdft_vec3 p, float f)
{
    return 8.0f * FLT_EPSILON * (1.0f + sdft_maxcomp(sdft_abs3(p)) + fabsf(f));
}

/* The four scenes, each test looping over all of them. */
static const sdft_scene *const *all(size_t *n)
{
    const sdft_scene *const *s = sdft_scenes(n);
    assert_non_null(s);
    return s;
}

static void test_registry(void **state)
{
    (void)state;
    size_t n;
    const sdft_scene *const *s = all(&n);
    assert_int_equal(n, 5);
    const char *wanted[] = {"temple", "figure", "dodecahedron", "city", "jewel"};
    for (size_t w = 0; w < 5; w++) {
        const sdft_scene *found = sdft_scene_find(wanted[w]);
        assert_non_null(found);
        assert_string_equal(found->name, wanted[w]);
    }
    for (size_t i = 0; i < n; i++) {
        assert_ptr_equal(sdft_scene_find(s[i]->name), s[i]);
        for (size_t j = i + 1; j < n; j++)
            assert_true(strcmp(s[i]->name, s[j]->name) != 0);
        assert_non_null(s[i]->description);
        assert_true(strlen(s[i]->description) > 10);
        assert_null(strchr(s[i]->description, '\n'));
        assert_non_null(s[i]->field.distance);
    }
    assert_null(sdft_scene_find("teapot"));
    assert_null(sdft_scene_find("Temple"));
    assert_null(sdft_scene_find(""));
    assert_null(sdft_scene_find(NULL));
}

/* |f(a) - f(b)| <= |a - b| (1 + 1e-4) on random pairs: far apart, close,
 * and very close at the surface, where thin features and blends live. */
static void test_lipschitz(void **state)
{
    (void)state;
    size_t n;
    const sdft_scene *const *s = all(&n);
    for (size_t k = 0; k < n; k++) {
        tu_rng rng = tu_rng_seed(100 + k);
        float diag = sdft_length(box_size(s[k]));
        for (int i = 0; i < 24000; i++) {
            int near = i % 3 == 0;
            sdft_vec3 a = near ? point_near_surface(&rng, s[k]) : point_in_bounds(&rng, s[k], 0.1f);
            float sep = near ? expf(tu_uniform(&rng, logf(1e-4f), logf(0.1f)))
                             : expf(tu_uniform(&rng, logf(1e-3f), logf(0.3f * diag)));
            sdft_vec3 b = sdft_madd(a, unit_vector(&rng), sep);
            float fa = field_at(s[k], a), fb = field_at(s[k], b);
            float allowed = sdft_length(sdft_sub(a, b)) * (1.0f + 1e-4f) + rounding(a, fa) + rounding(b, fb);
            if (!(fabsf(fa - fb) <= allowed))
                print_error("%s: f(%g %g %g) = %g, f(%g %g %g) = %g, |a-b| = %g\n", s[k]->name, (double)a.x,
                            (double)a.y, (double)a.z, (double)fa, (double)b.x, (double)b.y, (double)b.z, (double)fb,
                            (double)sdft_length(sdft_sub(a, b)));
            assert_true(fabsf(fa - fb) <= allowed);
        }
    }
}

/* The unbounding sphere of a point outside is empty: no point within f(p)
 * of p is inside. Sampled mostly near the sphere's rim, where an
 * overestimate would show first. */
static void test_empty_spheres(void **state)
{
    (void)state;
    size_t n;
    const sdft_scene *const *s = all(&n);
    for (size_t k = 0; k < n; k++) {
        tu_rng rng = tu_rng_seed(200 + k);
        int checked = 0;
        for (int i = 0; i < 3000; i++) {
            sdft_vec3 p = point_in_bounds(&rng, s[k], 0.05f);
            if (i % 2) /* half of them just off the surface */
                p = sdft_madd(point_near_surface(&rng, s[k]), unit_vector(&rng), tu_uniform(&rng, 0, 0.2f));
            float f = field_at(s[k], p);
            if (!(f > 1e-4f))
                continue;
            checked++;
            for (int j = 0; j < 32; j++) {
                float radius = f * (1.0f - 1e-3f) * cbrtf(tu_uniform(&rng, j < 24 ? 0.9f : 0.0f, 1.0f));
                sdft_vec3 q = sdft_madd(p, unit_vector(&rng), radius);
                float fq = field_at(s[k], q);
                if (!(fq >= 0.0f))
                    print_error("%s: f(p) = %g but f = %g at %g from p\n", s[k]->name, (double)f, (double)fq,
                                (double)radius);
                assert_true(fq >= 0.0f);
            }
        }
        assert_true(checked > 1000);
    }
}

/* Outside the bounding box f > 0, and the box is tight: the surface comes
 * within 5% of the box's size to each of its six faces. */
static void test_bounds(void **state)
{
    (void)state;
    size_t n;
    const sdft_scene *const *s = all(&n);
    for (size_t k = 0; k < n; k++) {
        sdft_aabb b = s[k]->field.bounds;
        sdft_vec3 size = box_size(s[k]);
        assert_true(sdft_isfinite3(b.lo) && sdft_isfinite3(b.hi));
        assert_true(size.x > 0 && size.y > 0 && size.z > 0);
        tu_rng rng = tu_rng_seed(300 + k);
        for (int i = 0; i < 20000; i++) {
            sdft_vec3 p = point_in_bounds(&rng, s[k], 0.5f);
            /* half of them pushed just outside one face */
            if (i % 2) {
                int axis = i % 3, hi = (i / 2) % 2;
                float off = expf(tu_uniform(&rng, logf(1e-4f), 0.0f));
                *component(&p, axis) = hi ? *component(&b.hi, axis) + off : *component(&b.lo, axis) - off;
            }
            int outside = p.x < b.lo.x || p.y < b.lo.y || p.z < b.lo.z || p.x > b.hi.x || p.y > b.hi.y || p.z > b.hi.z;
            if (outside && !(field_at(s[k], p) > 0.0f))
                print_error("%s: f = %g outside the box at %g %g %g\n", s[k]->name, (double)field_at(s[k], p),
                            (double)p.x, (double)p.y, (double)p.z);
            assert_true(!outside || field_at(s[k], p) > 0.0f);
        }
        /* tightness: on each face, some point is within 5% of the size */
        for (int face = 0; face < 6; face++) {
            int axis = face / 2;
            float best = INFINITY;
            for (int i = 0; i < 40000; i++) {
                sdft_vec3 p = point_in_bounds(&rng, s[k], 0.0f);
                *component(&p, axis) = *component(face % 2 ? &b.hi : &b.lo, axis);
                best = fminf(best, field_at(s[k], p));
            }
            float extent = *component(&size, axis);
            if (!(best <= 0.05f * extent))
                print_error("%s: face %d of the box is %g from the surface\n", s[k]->name, face, (double)best);
            assert_true(best <= 0.05f * extent);
        }
    }
}

/* The default view: eye and light outside every object, the centre ray hits
 * with Hart's tracer and the default one alike, and at least a sixth of a
 * coarse 1280x720 frame is covered by the scene. */
static void test_camera_sees_scene(void **state)
{
    (void)state;
    size_t n;
    const sdft_scene *const *s = all(&n);
    for (size_t k = 0; k < n; k++) {
        const sdft_camera *cam = &s[k]->camera;
        assert_true(field_at(s[k], cam->from) > 0.0f);
        assert_true(field_at(s[k], s[k]->light) > 0.0f);
        assert_true(cam->fov_deg > 0.0f && cam->fov_deg < 180.0f);
        sdft_scratch scratch;
        sdft_scratch_init(&s[k]->field, &scratch);
        sdft_ray centre = {cam->from, 0.0f, sdft_normalize(sdft_sub(cam->at, cam->from)), INFINITY};
        sdft_trace_params hart = sdft_trace_defaults(), dflt = sdft_trace_defaults();
        hart.method = SDFT_SPHERE;
        sdft_hit h = sdft_trace(&s[k]->field, &scratch, &centre, &hart);
        sdft_hit d = sdft_trace(&s[k]->field, &scratch, &centre, &dflt);
        if (h.status != SDFT_HIT)
            print_error("%s: the centre ray does not hit (status %d)\n", s[k]->name, (int)h.status);
        assert_int_equal(h.status, SDFT_HIT);
        assert_int_equal(d.status, SDFT_HIT);
        assert_true(fabsf(h.t - d.t) <= 1e-3f * (1.0f + h.t));
        int hits = 0, total = 0;
        for (int y = 0; y < 720; y += 40)
            for (int x = 0; x < 1280; x += 40, total++) {
                sdft_ray ray = sdft_camera_ray(cam, 1280, 720, (float)x + 20.0f, (float)y + 20.0f);
                hits += sdft_trace(&s[k]->field, &scratch, &ray, &dflt).status == SDFT_HIT;
            }
        if (!(hits * 6 >= total))
            print_error("%s: only %d of %d rays hit\n", s[k]->name, hits, total);
        assert_true(hits * 6 >= total);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_registry), cmocka_unit_test(test_lipschitz),         cmocka_unit_test(test_empty_spheres),
        cmocka_unit_test(test_bounds),   cmocka_unit_test(test_camera_sees_scene),
    };
    return cmocka_run_group_tests_name("scenes", tests, NULL, NULL);
}
