/* Tests of the five tracing variants (src/core/trace*.c) against
 * independent truth: analytic ray intersections, a field that counts its own
 * evaluations, and brute-force marching through every scene. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sdftrace/scene.h"
#include "sdftrace/trace.h"
#include "testutil.h"

/* ---- analytic fields: a sphere, a plane and a box --------------------- */

typedef struct shape {
    sdft_vec3 centre;
    float radius;       /* sphere */
    sdft_vec3 half;     /* box half extents */
    sdft_vec3 normal;   /* plane through centre */
    int counter_offset; /* unused padding for clarity */
} shape;

/* Every field also counts its evaluations in the thread's scratch, so the
 * count test can compare the tracer's `steps` with the truth. */
static uint64_t *counter(sdft_scratch *s) { return (uint64_t *)s->bytes; }

static float sphere_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    const shape *sh = ctx;
    ++*counter(s);
    return sdft_length(sdft_sub(p, sh->centre)) - sh->radius;
}

static float plane_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    const shape *sh = ctx;
    ++*counter(s);
    return sdft_dot(sdft_sub(p, sh->centre), sh->normal);
}

static float box_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    const shape *sh = ctx;
    ++*counter(s);
    sdft_vec3 q = sdft_sub(sdft_abs3(sdft_sub(p, sh->centre)), sh->half);
    return sdft_length(sdft_max3(q, 0.0f)) + fminf(sdft_maxcomp(q), 0.0f);
}

static void zero_counter(const void *ctx, sdft_scratch *s)
{
    (void)ctx;
    *counter(s) = 0;
}

static const sdft_aabb world = {{-50, -50, -50}, {50, 50, 50}};

static sdft_field make_field(float (*distance)(const void *, sdft_scratch *, sdft_vec3), const shape *sh)
{
    return (sdft_field){.distance = distance, .scratch_init = zero_counter, .ctx = sh, .bounds = world};
}

/* Analytic first intersection of a ray with a sphere; INFINITY if none. */
static float ray_sphere(sdft_vec3 o, sdft_vec3 d, sdft_vec3 c, float r)
{
    sdft_vec3 oc = sdft_sub(o, c);
    double b = sdft_dot(oc, d), cc = (double)sdft_dot(oc, oc) - (double)r * r;
    double disc = b * b - cc;
    if (disc < 0)
        return INFINITY;
    double t = -b - sqrt(disc);
    return t >= 0 ? (float)t : INFINITY;
}

/* Analytic slab test against an axis-aligned box; INFINITY if none. */
static float ray_box(sdft_vec3 o, sdft_vec3 d, sdft_vec3 c, sdft_vec3 h)
{
    float t0, t1;
    sdft_aabb b = {sdft_sub(c, h), sdft_add(c, h)};
    if (!sdft_aabb_clip(b, o, d, 0.0f, INFINITY, &t0, &t1))
        return INFINITY;
    return t0;
}

static sdft_vec3 random_direction(tu_rng *rng)
{
    for (;;) {
        sdft_vec3 v = {tu_uniform(rng, -1, 1), tu_uniform(rng, -1, 1), tu_uniform(rng, -1, 1)};
        float len = sdft_length(v);
        if (len > 0.1f && len <= 1.0f)
            return sdft_scale(v, 1.0f / len);
    }
}

static sdft_trace_params params_for(sdft_method m, float omega)
{
    sdft_trace_params p = sdft_trace_defaults();
    p.method = m;
    p.omega = omega;
    p.eps = 1e-4f;
    return p;
}

/* Every variant with the papers' parameters, plus the most aggressive legal
 * over-relaxation to stress the fallback. */
static const struct {
    sdft_method method;
    float omega, beta;
} variants[] = {
    {SDFT_SPHERE, 1.0f, 0.3f},      {SDFT_RELAXED, 1.2f, 0.3f},    {SDFT_RELAXED, 1.5f, 0.3f},
    {SDFT_RELAXED, 1.95f, 0.3f},    {SDFT_RELAXED_BV, 1.2f, 0.3f}, {SDFT_RELAXED_BV, 1.5f, 0.3f},
    {SDFT_RELAXED_BV, 1.95f, 0.3f}, {SDFT_ENHANCED, 0.88f, 0.3f},  {SDFT_ENHANCED, 1.0f, 0.3f},
    {SDFT_AUTO, 1.0f, 0.3f},        {SDFT_AUTO, 1.0f, 0.2f},       {SDFT_AUTO, 1.0f, 0.9f},
};
enum { VARIANT_COUNT = sizeof variants / sizeof variants[0] };

static sdft_trace_params variant_params(int v)
{
    sdft_trace_params p = params_for(variants[v].method, variants[v].omega);
    p.beta = variants[v].beta;
    return p;
}

/* ---- hits at the analytic t -------------------------------------------- */

/* Rays from random origins outside the shape towards random targets near
 * it. A hit must be at the analytic t (within eps) and an analytic miss must
 * be a miss. Near-tangent rays are skipped: there "hit within eps of the
 * surface" and "analytic miss" are both right. */
static void check_shape(float (*distance)(const void *, sdft_scratch *, sdft_vec3), const shape *sh,
                        float (*truth)(sdft_vec3, sdft_vec3, const shape *), uint64_t seed)
{
    sdft_field f = make_field(distance, sh);
    tu_rng rng = tu_rng_seed(seed);
    int hits = 0, misses = 0;
    for (int n = 0; n < 400; n++) {
        sdft_ray ray;
        ray.org = sdft_add(sh->centre, sdft_scale(random_direction(&rng), tu_uniform(&rng, 3.0f, 8.0f)));
        sdft_scratch s;
        sdft_scratch_init(&f, &s);
        if (distance(sh, &s, ray.org) < 0.0f) /* start outside: a plane's lower half-space is inside */
            ray.org =
                sdft_sub(ray.org, sdft_scale(sh->normal, 2 * sdft_dot(sdft_sub(ray.org, sh->centre), sh->normal)));
        sdft_vec3 target = sdft_add(sh->centre, sdft_scale(random_direction(&rng), tu_uniform(&rng, 0.0f, 2.5f)));
        /* half the rays aim near the shape, half go anywhere */
        ray.dir = n % 2 ? sdft_normalize(sdft_sub(target, ray.org)) : random_direction(&rng);
        ray.tnear = 0.0f;
        ray.tfar = 40.0f;
        float t_true = truth(ray.org, ray.dir, sh);
        if (t_true > ray.tfar)
            t_true = INFINITY;

        /* Skip rays that pass within 1e-2 of the surface without a clear
         * crossing: the minimum of f along the ray, found by fine sampling. */
        float fmin = INFINITY;
        for (float t = 0; t < 20.0f; t += 2e-3f)
            fmin = fminf(fmin, distance(sh, &s, sdft_madd(ray.org, ray.dir, t)));
        if (fmin > -1e-2f && fmin < 1e-2f)
            continue;
        /* and grazing hits, where t is ill-conditioned (slope of f along the ray tiny) */
        if (isfinite(t_true)) {
            sdft_vec3 q = sdft_madd(ray.org, ray.dir, t_true);
            float h = 1e-3f;
            float slope =
                (distance(sh, &s, sdft_madd(q, ray.dir, h)) - distance(sh, &s, sdft_madd(q, ray.dir, -h))) / (2 * h);
            if (slope > -0.05f)
                continue;
        }

        for (int v = 0; v < VARIANT_COUNT; v++) {
            sdft_trace_params p = variant_params(v);
            sdft_hit hit = sdft_trace(&f, &s, &ray, &p);
            if (isfinite(t_true)) {
                if (hit.status != SDFT_HIT || fabsf(hit.t - t_true) > p.eps)
                    fail_msg("%s omega %g beta %g: status %d t %.6f, analytic t %.6f (ray %d)",
                             sdft_method_name(p.method), p.omega, p.beta, hit.status, hit.t, t_true, n);
            } else if (hit.status != SDFT_MISS) {
                fail_msg("%s omega %g: status %d at t %.6f, analytic miss (ray %d)", sdft_method_name(p.method),
                         p.omega, hit.status, hit.t, n);
            }
        }
        isfinite(t_true) ? hits++ : misses++;
    }
    /* The sample must exercise both outcomes. */
    assert_true(hits > 50);
    assert_true(misses > 50);
}

static float truth_sphere(sdft_vec3 o, sdft_vec3 d, const shape *sh)
{
    return ray_sphere(o, d, sh->centre, sh->radius);
}
static float truth_box(sdft_vec3 o, sdft_vec3 d, const shape *sh) { return ray_box(o, d, sh->centre, sh->half); }
static float truth_plane(sdft_vec3 o, sdft_vec3 d, const shape *sh)
{
    float denom = sdft_dot(d, sh->normal);
    float t = -sdft_dot(sdft_sub(o, sh->centre), sh->normal) / denom;
    return (denom < 0 && t >= 0) ? t : INFINITY;
}

static void test_hits_sphere(void **state)
{
    (void)state;
    shape sh = {.centre = {0.3f, -0.2f, 0.1f}, .radius = 1.3f};
    check_shape(sphere_distance, &sh, truth_sphere, 1);
}

static void test_hits_box(void **state)
{
    (void)state;
    shape sh = {.centre = {-0.1f, 0.2f, 0.0f}, .half = {1.2f, 0.7f, 1.0f}};
    check_shape(box_distance, &sh, truth_box, 2);
}

static void test_hits_plane(void **state)
{
    (void)state;
    shape sh = {.centre = {0.0f, -0.5f, 0.0f}, .normal = sdft_normalize(sdft_v3(0.2f, 1.0f, -0.1f))};
    check_shape(plane_distance, &sh, truth_plane, 3);
}

/* ---- counts ------------------------------------------------------------- */

static void test_steps_count_evaluations(void **state)
{
    (void)state;
    shape sh = {.centre = {0, 0, 0}, .half = {1, 0.5f, 0.8f}};
    sdft_field f = make_field(box_distance, &sh);
    tu_rng rng = tu_rng_seed(7);
    for (int n = 0; n < 300; n++) {
        sdft_ray ray = {.org = sdft_scale(random_direction(&rng), 6.0f), .tnear = 0, .tfar = 40};
        ray.dir = sdft_normalize(sdft_sub(sdft_scale(random_direction(&rng), 1.5f), ray.org));
        for (int v = 0; v < VARIANT_COUNT; v++) {
            sdft_trace_params p = variant_params(v);
            p.max_steps = 1 + n % 40; /* hit every termination: converged, miss, i_max */
            sdft_scratch s;
            sdft_scratch_init(&f, &s);
            sdft_hit hit = sdft_trace(&f, &s, &ray, &p);
            assert_int_equal(hit.steps, *counter(&s));
            if (hit.status == SDFT_NOT_CONVERGED)
                assert_int_equal(hit.steps, p.max_steps);
            if (p.method == SDFT_SPHERE)
                assert_int_equal(hit.fallbacks, 0);
        }
    }
}

/* Rays towards a plane: sphere tracing converges geometrically (ratio
 * 1 - cos theta); auto-relaxation learns the slope and needs fewer
 * evaluations. (Perpendicular to the plane both need exactly two.) */
static void test_auto_fewer_steps_than_sphere_on_plane(void **state)
{
    (void)state;
    shape sh = {.centre = {0, 0, 0}, .normal = {0, 1, 0}};
    sdft_field f = make_field(plane_distance, &sh);
    const float angles[] = {45, 60, 75, 85};
    for (unsigned a = 0; a < sizeof angles / sizeof angles[0]; a++) {
        float th = angles[a] * 3.14159265f / 180.0f;
        sdft_ray ray = {.org = {0, 2, 0}, .dir = {sinf(th), -cosf(th), 0}, .tnear = 0, .tfar = 1000};
        sdft_scratch s;
        sdft_scratch_init(&f, &s);
        sdft_trace_params ps = params_for(SDFT_SPHERE, 1), pa = params_for(SDFT_AUTO, 1);
        sdft_hit hs = sdft_trace(&f, &s, &ray, &ps), ha = sdft_trace(&f, &s, &ray, &pa);
        assert_int_equal(hs.status, SDFT_HIT);
        assert_int_equal(ha.status, SDFT_HIT);
        assert_true(ha.steps < hs.steps);
        float t_true = 2.0f / cosf(th);
        assert_float_equal(ha.t, t_true, 1e-4f * t_true);
        assert_float_equal(hs.t, t_true, 1e-4f * t_true);
    }
}

/* The two relaxed forms apart, step by step, on the field f(p) = p.y (the
 * plane y = 0) along a ray from (0, 1, 0) that falls 3/4 per unit: F(t) =
 * 1 - 3t/4, every value below exact in float. With omega = 3/2 the first
 * relaxed step, to t = 3/2, lands at F = -1/8 and the unbounding spheres
 * miss each other (1 + 1/8 < 3/2). Keinert's Listing 2 steps back by
 * stepLength (1 - omega) = -3/4 to t = 3/4 and traces plainly from there
 * (F quarters each step: 7/16, 7/64, ...; one fallback). Bán–Valasek's
 * Algorithm 2 takes the basic step to t = 1 (F = 1/4) and relaxes again,
 * overshooting every other step (three fallbacks in seven evaluations). */
enum { RECORDED = 16 };

static float *recorded(sdft_scratch *s) { return (float *)(s->bytes + sizeof(uint64_t)); }

static float height_recorded(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx;
    if (*counter(s) < RECORDED)
        recorded(s)[*counter(s)] = p.y;
    ++*counter(s);
    return p.y;
}

static void test_relaxed_forms_step_by_step(void **state)
{
    (void)state;
    const sdft_field f = {.distance = height_recorded, .scratch_init = zero_counter, .bounds = world};
    const sdft_ray ray = {.org = {0, 1, 0}, .dir = {sqrtf(7.0f) / 4.0f, -0.75f, 0}, .tnear = 0, .tfar = 40};
    static const struct {
        sdft_method method;
        uint32_t fallbacks;
        float F[7]; /* f at each evaluation, in order */
    } forms[] = {
        {SDFT_RELAXED, 1, {1.0f, -0.125f, 0.4375f, 0.109375f, 0.02734375f, 0.0068359375f, 0.001708984375f}},
        {SDFT_RELAXED_BV, 3, {1.0f, -0.125f, 0.25f, -0.03125f, 0.0625f, -0.0078125f, 0.015625f}},
    };
    for (size_t k = 0; k < sizeof forms / sizeof forms[0]; k++) {
        sdft_trace_params p = params_for(forms[k].method, 1.5f);
        p.eps = 1e-6f, p.max_steps = 7;
        sdft_scratch s;
        sdft_scratch_init(&f, &s);
        const sdft_hit hit = sdft_trace(&f, &s, &ray, &p);
        assert_int_equal(hit.status, SDFT_NOT_CONVERGED);
        assert_int_equal(hit.steps, 7);
        assert_int_equal(hit.fallbacks, forms[k].fallbacks);
        for (int i = 0; i < 7; i++)
            if (recorded(&s)[i] != forms[k].F[i])
                fail_msg("%s: evaluation %d at F = %.9g, by hand %.9g", sdft_method_name(forms[k].method), i,
                         recorded(&s)[i], forms[k].F[i]);
        /* run to the end: both converge on the plane at t = 4/3 */
        p.max_steps = 1000;
        const sdft_hit end = sdft_trace(&f, &s, &ray, &p);
        assert_int_equal(end.status, SDFT_HIT);
        assert_float_equal(end.t, 4.0f / 3.0f, 1e-5f);
    }
}

/* ---- streams ------------------------------------------------------------ */

static void assert_same_hit(sdft_hit a, sdft_hit b)
{
    /* bit for bit: the stream takes the same points in the same order */
    assert_memory_equal(&a.t, &b.t, sizeof a.t);
    assert_memory_equal(&a.distance, &b.distance, sizeof a.distance);
    assert_int_equal(a.status, b.status);
    assert_int_equal(a.steps, b.steps);
    assert_int_equal(a.fallbacks, b.fallbacks);
}

/* sdft_trace_stream interleaves rays; each must come out exactly as
 * sdft_trace traces it alone, whatever the stream's length (fewer rays than
 * lanes, not a multiple of them), with rays that miss the bounds at once
 * and every termination; and the field must be evaluated exactly as often
 * as the hits' steps say. */
static void test_stream_same_as_single_rays(void **state)
{
    (void)state;
    shape sh = {.centre = {0, 0, 0}, .half = {1, 0.5f, 0.8f}};
    sdft_field f = make_field(box_distance, &sh);
    f.bounds = (sdft_aabb){{-3, -3, -3}, {3, 3, 3}};
    tu_rng rng = tu_rng_seed(11);
    enum { MOST = 41 };
    sdft_ray rays[MOST];
    sdft_hit stream[MOST];
    const size_t lengths[] = {1, 3, 4, 5, 16, MOST};
    for (unsigned l = 0; l < sizeof lengths / sizeof lengths[0]; l++) {
        const size_t n = lengths[l];
        for (size_t k = 0; k < n; k++) {
            rays[k] = (sdft_ray){.org = sdft_scale(random_direction(&rng), 6.0f), .tnear = 0, .tfar = 40};
            /* every third ray points away from the box: clipped away at once */
            sdft_vec3 target = k % 3 == 2 ? sdft_scale(rays[k].org, 2.0f) : sdft_scale(random_direction(&rng), 1.5f);
            rays[k].dir = sdft_normalize(sdft_sub(target, rays[k].org));
        }
        for (int v = 0; v < VARIANT_COUNT; v++) {
            sdft_trace_params p = variant_params(v);
            p.max_steps = 3 + (uint32_t)(l * 7 + (unsigned)v) % 30; /* some rays run out of steps */
            sdft_scratch s;
            sdft_scratch_init(&f, &s);
            sdft_trace_stream(&f, &s, rays, stream, n, &p);
            uint64_t evaluations = *counter(&s), steps = 0;
            for (size_t k = 0; k < n; k++) {
                assert_same_hit(stream[k], sdft_trace(&f, &s, &rays[k], &p));
                steps += stream[k].steps;
                if (k % 3 == 2) /* pointing away: clipped away, no evaluation */
                    assert_true(stream[k].status == SDFT_MISS && stream[k].steps == 0);
            }
            assert_int_equal(evaluations, steps);
        }
    }
}

/* The same through every scene, primary rays of its camera, with the
 * papers' eps and with the screen-space criterion. */
static void test_stream_same_as_single_in_scenes(void **state)
{
    (void)state;
    size_t count;
    const sdft_scene *const *scenes = sdft_scenes(&count);
    enum { N = 23 };
    for (size_t k = 0; k < count; k++) {
        const sdft_field *f = &scenes[k]->field;
        sdft_scratch s;
        sdft_scratch_init(f, &s);
        tu_rng rng = tu_rng_seed(200 + k);
        sdft_ray rays[N];
        sdft_hit stream[N];
        for (int n = 0; n < N; n++)
            rays[n] = sdft_camera_ray(&scenes[k]->camera, 320, 180, tu_uniform(&rng, 0, 320), tu_uniform(&rng, 0, 180));
        for (int v = 0; v < VARIANT_COUNT; v++)
            for (int screen_space = 0; screen_space <= 1; screen_space++) {
                sdft_trace_params p = variant_params(v);
                if (screen_space)
                    p.eps = 0.0f, p.pixel_radius = sdft_camera_pixel_radius(&scenes[k]->camera, 180);
                sdft_trace_stream(f, &s, rays, stream, N, &p);
                int hits = 0;
                for (int n = 0; n < N; n++) {
                    assert_same_hit(stream[n], sdft_trace(f, &s, &rays[n], &p));
                    hits += stream[n].status == SDFT_HIT;
                }
                assert_true(hits > 0);
            }
    }
}

/* ---- termination rules -------------------------------------------------- */

static void test_ray_missing_bounds_costs_nothing(void **state)
{
    (void)state;
    shape sh = {.centre = {0, 0, 0}, .radius = 1};
    sdft_field f = make_field(sphere_distance, &sh);
    f.bounds = (sdft_aabb){{-1, -1, -1}, {1, 1, 1}};
    sdft_ray ray = {.org = {5, 5, 5}, .dir = {1, 0, 0}, .tnear = 0, .tfar = INFINITY};
    sdft_scratch s;
    sdft_scratch_init(&f, &s);
    sdft_trace_params p = sdft_trace_defaults();
    sdft_hit hit = sdft_trace(&f, &s, &ray, &p);
    assert_int_equal(hit.status, SDFT_MISS);
    assert_int_equal(hit.steps, 0);
    assert_int_equal(*counter(&s), 0);
}

/* sdft_aabb_clip (and the tracer's own clip, the same code) against brute
 * force: 2000 points along each ray, those clear of the box's faces by
 * more than rounding lie in the box exactly when their t is within the
 * clipped span. Rays whose direction has components exactly 0 or -0, and
 * whose origins lie on the box's planes (a ray in a face's plane is in
 * the closed box), in it, or outside it. */
static void test_aabb_clip_against_points(void **state)
{
    (void)state;
    const sdft_aabb b = {{-0.7f, -0.3f, 0.2f}, {0.9f, 0.5f, 1.4f}};
    const float lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    tu_rng r = tu_rng_seed(5);
    int met = 0, flat = 0;
    for (int i = 0; i < 3000; i++) {
        float o[3], d[3];
        for (int k = 0; k < 3; k++) {
            const int kind = (int)tu_uniform(&r, 0.0f, 5.99f); /* 0 lo, 1 hi, 2-5 anywhere near */
            o[k] = kind == 0 ? lo[k] : kind == 1 ? hi[k] : tu_uniform(&r, lo[k] - 0.3f, hi[k] + 0.3f);
            const int zero = (int)tu_uniform(&r, 0.0f, 3.99f); /* 0 +0, 1 -0, else any */
            d[k] = zero == 0 ? 0.0f : zero == 1 ? -0.0f : tu_uniform(&r, -1.0f, 1.0f);
        }
        if (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f)
            continue;
        flat += d[0] == 0.0f || d[1] == 0.0f || d[2] == 0.0f;
        const sdft_vec3 org = sdft_v3(o[0], o[1], o[2]), dir = sdft_v3(d[0], d[1], d[2]);
        const float tnear = tu_uniform(&r, -1.0f, 0.5f), tfar = tnear + tu_uniform(&r, 0.1f, 6.0f);
        float t0 = NAN, t1 = NAN;
        const int in = sdft_aabb_clip(b, org, dir, tnear, tfar, &t0, &t1);
        met += in;
        for (int j = 0; j <= 2000; j++) {
            const float t = tnear + (tfar - tnear) * (float)j / 2000.0f;
            float clear = INFINITY; /* signed distance inside the box, per axis the least */
            for (int k = 0; k < 3; k++) {
                const float x = o[k] + t * d[k];
                if (d[k] == 0.0f) /* exact: in the closed slab or not */
                    clear = o[k] >= lo[k] && o[k] <= hi[k] ? clear : -INFINITY;
                else
                    clear = fminf(clear, fminf(x - lo[k], hi[k] - x));
            }
            if (fabsf(clear) <= 1e-5f)
                continue; /* on a face the ray crosses, to rounding */
            const int within = in && t >= t0 - 1e-5f && t <= t1 + 1e-5f;
            const int strictly = in && t > t0 + 1e-5f && t < t1 - 1e-5f;
            if ((clear > 0.0f && !within) || (clear < 0.0f && strictly))
                fail_msg("ray %d (o %a %a %a, d %a %a %a): t = %g is %s the box, clip %s [%g, %g]", i, o[0], o[1], o[2],
                         d[0], d[1], d[2], t, clear > 0.0f ? "in" : "outside", in ? "gives" : "refuses, not", t0, t1);
        }
        if (in)
            assert_true(t0 >= tnear && t1 <= tfar && t0 <= t1);
    }
    print_message("%d rays meet the box, %d of them with a direction component 0\n", met, flat);
    assert_true(met > 500 && flat > 1000);
}

/* With the screen-space criterion a ray that runs out of steps returns the
 * point of smallest r / t along its way (Keinert §3.2), not the last one. */
static void test_screen_space_candidate(void **state)
{
    (void)state;
    shape sh = {.centre = {0, 0, 0}, .radius = 1};
    sdft_field f = make_field(sphere_distance, &sh);
    /* grazes the sphere at distance 1.001: many small steps near x = 0 */
    sdft_ray ray = {.org = {-10, 1.001f, 0}, .dir = {1, 0, 0}, .tnear = 0, .tfar = 40};
    for (int m = 0; m < SDFT_METHOD_COUNT; m++) {
        sdft_trace_params p = params_for((sdft_method)m, sdft_default_omega((sdft_method)m));
        p.eps = 0.0f;
        p.pixel_radius = 1e-5f;
        p.max_steps = 60;
        sdft_scratch s;
        sdft_scratch_init(&f, &s);
        sdft_hit hit = sdft_trace(&f, &s, &ray, &p);
        if (hit.status == SDFT_NOT_CONVERGED) {
            /* the candidate is near the point of closest approach, t = 10 */
            assert_float_equal(hit.t, 10.0f, 1.0f);
            assert_float_equal(hit.distance, 0.001f, 0.01f);
        } else {
            assert_int_equal(hit.status, SDFT_MISS);
        }
    }
}

static void test_params_check(void **state)
{
    (void)state;
    char msg[128];
    sdft_trace_params p = sdft_trace_defaults();
    assert_int_equal(sdft_trace_params_check(&p, msg, sizeof msg), 0);
    p.method = SDFT_RELAXED, p.omega = 2.0f;
    assert_int_equal(sdft_trace_params_check(&p, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "omega"));
    p.omega = 0.99f;
    assert_int_equal(sdft_trace_params_check(&p, msg, sizeof msg), SDFT_EINVAL);
    p.method = SDFT_ENHANCED, p.omega = 0.0f;
    assert_int_equal(sdft_trace_params_check(&p, msg, sizeof msg), SDFT_EINVAL);
    p.omega = 1.0f;
    assert_int_equal(sdft_trace_params_check(&p, msg, sizeof msg), 0);
    p.method = SDFT_AUTO, p.beta = 1.0f;
    assert_int_equal(sdft_trace_params_check(&p, msg, sizeof msg), SDFT_EINVAL);
    p.beta = NAN;
    assert_int_equal(sdft_trace_params_check(&p, msg, sizeof msg), SDFT_EINVAL);
    p.beta = 0.3f, p.eps = NAN;
    assert_int_equal(sdft_trace_params_check(&p, msg, sizeof msg), SDFT_EINVAL);
    p.eps = 1e-4f, p.max_steps = 0;
    assert_int_equal(sdft_trace_params_check(&p, msg, sizeof msg), SDFT_EINVAL);
    sdft_method m = SDFT_SPHERE;
    assert_int_equal(sdft_method_parse("enhanced", &m, msg, sizeof msg), SDFT_OK);
    assert_int_equal(m, SDFT_ENHANCED);
    assert_int_equal(sdft_method_parse("hart", &m, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "hart"));
    assert_int_equal(m, SDFT_ENHANCED);
}

/* ---- safety through every scene ----------------------------------------- */

/* The first t in [t0, t1] where f changes sign, marching with a fixed step
 * no larger than `step`; INFINITY if none. Independent of every tracer. */
static float brute_first_crossing(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, float t0, float t1,
                                  float step)
{
    float prev = f->distance(f->ctx, s, sdft_madd(ray->org, ray->dir, t0));
    if (prev <= 0)
        return t0;
    for (float t = t0 + step; t <= t1 + step; t += step) {
        float d = f->distance(f->ctx, s, sdft_madd(ray->org, ray->dir, t));
        if (d <= 0)
            return t;
    }
    return INFINITY;
}

static void test_no_hit_beyond_first_crossing_in_scenes(void **state)
{
    (void)state;
    size_t count;
    const sdft_scene *const *scenes = sdft_scenes(&count);
    assert_true(count >= 4);
    for (size_t k = 0; k < count; k++) {
        const sdft_scene *sc = scenes[k];
        const sdft_field *f = &sc->field;
        sdft_scratch s;
        sdft_scratch_init(f, &s);
        float diag = sdft_length(sdft_sub(f->bounds.hi, f->bounds.lo));
        float eps = 2e-5f * diag, step = eps;
        tu_rng rng = tu_rng_seed(100 + k);
        int checked = 0, tunnel_checks = 0;
        for (int n = 0; n < 48; n++) {
            /* primary rays through random pixels of the default camera */
            sdft_ray ray = sdft_camera_ray(&sc->camera, 320, 180, tu_uniform(&rng, 0, 320), tu_uniform(&rng, 0, 180));
            float t0, t1;
            if (!sdft_aabb_clip(f->bounds, ray.org, ray.dir, ray.tnear, fminf(ray.tfar, 4 * diag), &t0, &t1))
                continue;
            float truth = INFINITY;
            int truth_known = 0;
            for (int v = 0; v < VARIANT_COUNT; v++) {
                sdft_trace_params p = variant_params(v);
                p.eps = eps;
                sdft_hit hit = sdft_trace(f, &s, &ray, &p);
                if (hit.status == SDFT_NOT_CONVERGED)
                    continue;
                if (!truth_known) {
                    /* marching the whole clipped ray is costly: up to the hit suffices for hits */
                    float end = hit.status == SDFT_HIT ? fminf(hit.t + 4 * step, t1) : t1;
                    truth = brute_first_crossing(f, &s, &ray, t0, end, step);
                    truth_known = hit.status != SDFT_HIT || isfinite(truth);
                    if (hit.status != SDFT_HIT)
                        tunnel_checks++;
                }
                if (hit.status == SDFT_HIT) {
                    if (hit.t > truth + 2 * step + eps)
                        fail_msg("%s: %s omega %g beta %g hit at t %.5f beyond the first crossing %.5f (ray %d)",
                                 sc->name, sdft_method_name(p.method), p.omega, p.beta, hit.t, truth, n);
                    checked++;
                } else if (truth_known && isfinite(truth)) {
                    fail_msg("%s: %s omega %g beta %g missed a crossing at %.5f (tunnelled, ray %d)", sc->name,
                             sdft_method_name(p.method), p.omega, p.beta, truth, n);
                }
            }
        }
        assert_true(checked > 0);
        (void)tunnel_checks;
    }
}

/* A field with per-thread state (here, its evaluation counter) refuses a
 * scratch prepared for another field: nothing is traced, nothing counted. */
static void test_scratch_belongs_to_its_field(void **state)
{
    (void)state;
    const shape ball = {.centre = {0, 0, 0}, .radius = 1.0f}, block = {.centre = {0, 0, 0}, .half = {1, 1, 1}};
    sdft_field fs = make_field(sphere_distance, &ball), fb = make_field(box_distance, &block);
    sdft_scratch s;
    sdft_scratch_init(&fs, &s);
    const sdft_ray ray = {.org = {0, 0, 5}, .tnear = 0, .dir = {0, 0, -1}, .tfar = INFINITY};
    const sdft_trace_params p = sdft_trace_defaults();
    sdft_hit h = sdft_trace(&fb, &s, &ray, &p);
    assert_int_equal(h.status, SDFT_INVALID);
    assert_int_equal(*counter(&s), 0);
    h = sdft_trace(&fs, &s, &ray, &p);
    assert_int_equal(h.status, SDFT_HIT);
    assert_int_equal(*counter(&s), h.steps);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scratch_belongs_to_its_field),
        cmocka_unit_test(test_hits_sphere),
        cmocka_unit_test(test_aabb_clip_against_points),
        cmocka_unit_test(test_hits_box),
        cmocka_unit_test(test_hits_plane),
        cmocka_unit_test(test_steps_count_evaluations),
        cmocka_unit_test(test_auto_fewer_steps_than_sphere_on_plane),
        cmocka_unit_test(test_relaxed_forms_step_by_step),
        cmocka_unit_test(test_stream_same_as_single_rays),
        cmocka_unit_test(test_stream_same_as_single_in_scenes),
        cmocka_unit_test(test_ray_missing_bounds_costs_nothing),
        cmocka_unit_test(test_screen_space_candidate),
        cmocka_unit_test(test_params_check),
        cmocka_unit_test(test_no_hit_beyond_first_crossing_in_scenes),
    };
    return cmocka_run_group_tests_name("trace", tests, NULL, NULL);
}
