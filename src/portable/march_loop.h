/* sdftrace — the loop every tracing variant runs, one ray at a time:
 * Algorithms 1-4's `repeat` with the variant's start and step folded in,
 * the exact root near the surface, the termination rule, hit refinement
 * and the screen-space candidate. Portable (portable.h).
 *
 * The includer says what the field is, before including this:
 *   MARCH_FIELD, MARCH_SCRATCH   the types of the field and of the
 *       thread's mutable state (C: const sdft_field *, sdft_scratch *;
 *       the shader: its grid, and its NanoVDB read accessor, inout);
 *   MARCH_EVAL(f, s, ray, t)     f at ray.org + t ray.dir;
 *   MARCH_HAS_ROOT(f, p)         whether the tracer may ask f's exact root;
 *   MARCH_ROOT_REACH(f, p)       then the reach within which it asks, else
 *       -INFINITY;
 *   MARCH_ROOT(f, s, org, dir, t0, t1, t, normal, reads)  the exact root
 *       (sdft_field_accel.root), into the lvalues t, normal and reads;
 *   MARCH_BOUNDS(f)              the box rays are clipped to;
 *   march_start_fn, march_step_fn, MARCH_START(fn, m, p),
 *       MARCH_STEP(fn, m, T, R, p)  a variant's start and step (C: function
 *       pointers, constants where march_one inlines; GLSL: the method,
 *       variants.h's dispatch).
 * In C, march_finish is defined once, out of line, where MARCH_FINISH_BODY
 * is defined (march.c); elsewhere this declares it. */
#ifndef SDFTRACE_MARCH_LOOP_H
#define SDFTRACE_MARCH_LOOP_H

#include "march_state.h"
#include "ray_box.h"

/* A ray against its field's box: the shader inlines ray_box_clip; the
 * library calls it out of line (sdft_aabb_clip), out of the stream's
 * loop, where inlined it cost more than the call. */
#if defined(SDFT_GLSL)
#define MARCH_CLIP_BOX ray_box_clip
#else
#define MARCH_CLIP_BOX sdft_aabb_clip
#endif

#if defined(SDFT_GLSL) || defined(MARCH_FINISH_BODY)
/* Secant steps towards F(t) = 0 through the last two samples, until the
 * step the secant asks for is under a tenth of eps(t): the root is then
 * known to that accuracy, and evaluating there would only confirm it (at
 * the papers' distances and eps, t's own float resolution is a hundredth of
 * eps). Each step is clamped to what the unbounding spheres allow: ahead of
 * a point outside (r > 0) the root is no nearer than r, since |F'| <= 1,
 * and we step at most 32 r, so a grazing hit (slope down to 1/32) still
 * lands on the surface while the step stays within a few eps; behind a
 * point inside (r < 0) the root is at least |r| back and no farther back
 * than the last outside sample. A step that does not bring |F| down is
 * discarded. At most three steps. */
PORT_INLINE void march_refine(MARCH_FIELD f, MARCH_SCRATCH s, sdft_ray ray, sdft_trace_params p, float t0, float r0,
                              PORT_INOUT(float) t, PORT_INOUT(float) r, PORT_INOUT(uint32_t) steps)
{
    PORT_NO_UNROLL for (int k = 0; k < 3; k++)
    {
        float t1 = PORT_DEREF(t), r1 = PORT_DEREF(r);
        float dt = (r1 != r0) ? -r1 * (t1 - t0) / (r1 - r0) : r1;
        if (!isfinite(dt))
            dt = r1;
        if (r1 > 0.0f)
            dt = sdft_minf(sdft_maxf(dt, r1), 32.0f * r1);
        else
            dt = (r0 > 0.0f && t0 < t1) ? sdft_minf(sdft_maxf(dt, t0 - t1), r1) : r1;
        if (!(fabsf(dt) > 0.1f * march_eps(p, t1)))
            break;
        float tn = t1 + dt, rn = MARCH_EVAL(f, s, ray, tn);
        PORT_DEREF(steps)++;
        if (!(fabsf(rn) < fabsf(r1)))
            break;
        t0 = t1;
        r0 = r1;
        PORT_DEREF(t) = tn;
        PORT_DEREF(r) = rn;
    }
}

/* Turns the final state of a march into a hit: classifies it, refines a hit
 * onto the surface from the last two accepted samples (t0, r0), (t, r), and
 * on non-convergence with the screen-space criterion returns the candidate. */
sdft_hit march_finish(MARCH_FIELD f, MARCH_SCRATCH s, sdft_ray ray, sdft_trace_params p, float t0, float r0, float t,
                      float r, uint32_t steps, uint32_t fallbacks, march_candidate best)
{
    sdft_hit hit;
    hit.t = t;
    hit.distance = r;
    hit.status = SDFT_HIT;
    hit.steps = steps;
    hit.fallbacks = fallbacks;
    hit.normal = sdft_v3(0.0f, 0.0f, 0.0f);
    if (r <= march_eps(p, t)) {
        /* A field with an exact root gives the hit itself, from the last
         * point known outside (a step may have landed inside). */
        const float from = r > 0.0f ? t : t0;
        float at;
        if (MARCH_HAS_ROOT(f, p) && (r > 0.0f || (r0 > 0.0f && t0 < t))) {
            if (MARCH_ROOT(f, s, ray.org, ray.dir, from, ray.tfar, at, hit.normal, hit.steps) != 0) {
                hit.t = at;
                hit.distance = 0.0f;
                return hit;
            }
            /* Within eps of the surface, but it proved there is no root
             * before the ray's end: the ray passes the surface by (whether
             * a march lands within eps of it there depends on where the
             * march started; the root does not). */
            if (at >= ray.tfar) {
                hit.status = SDFT_MISS;
                return hit;
            }
        }
        march_refine(f, s, ray, p, t0, r0, PORT_REF(hit.t), PORT_REF(hit.distance), PORT_REF(hit.steps));
    } else if (t + r >= ray.tfar || !isfinite(r)) {
        hit.status = SDFT_MISS;
    } else {
        hit.status = SDFT_NOT_CONVERGED;
        if (p.pixel_radius > 0.0f) {
            hit.t = best.t;
            hit.distance = best.r;
        }
    }
    return hit;
}
#else
sdft_hit march_finish(MARCH_FIELD f, MARCH_SCRATCH s, sdft_ray ray, sdft_trace_params p, float t0, float r0, float t,
                      float r, uint32_t steps, uint32_t fallbacks, march_candidate best);
#endif

PORT_INLINE sdft_hit march_end(MARCH_FIELD f, MARCH_SCRATCH s, sdft_ray ray, sdft_trace_params p,
                               PORT_IN(march_state) m)
{
    return march_finish(f, s, ray, p, PORT_DEREF(m).t0, PORT_DEREF(m).r0, PORT_DEREF(m).t, PORT_DEREF(m).r,
                        PORT_DEREF(m).i, PORT_DEREF(m).fallbacks, PORT_DEREF(m).best);
}

/* THE EXACT LAST CELL. A field that knows its own form near the surface
 * (sdft_field_accel.root: a grid's trilinear cells, where f along the ray is a
 * cubic) is asked for the exact first root once the accepted point is
 * within its reach (eps(t) < r < root_reach) instead of stepping on to eps:
 * its answer is the hit, on the surface itself, or a stretch [t, t') it
 * proved free, after which marching restarts at t' (the variant's state
 * begins anew there; its history does not span the jump). It is asked at
 * most once per stretch (root_t), and the data it reads counts as
 * evaluations. Only with p.exact_root and a field that has one
 * (MARCH_ROOT_REACH). */
PORT_INLINE bool march_root_due(float reach, PORT_IN(march_state) m)
{
    return PORT_DEREF(m).r < reach && PORT_DEREF(m).t > PORT_DEREF(m).root_t;
}

/* Asks the field; 1 when it found the root (t_out: where, normal: the
 * normal there), else 0 with t_out where marching resumes (m.t when the
 * field could not go on). */
PORT_INLINE int march_root(MARCH_FIELD f, MARCH_SCRATCH s, sdft_ray ray, PORT_INOUT(march_state) m,
                           PORT_OUT(float) t_out, PORT_INOUT(sdft_vec3) normal)
{
    float t = PORT_DEREF(m).t;
    const int found =
        MARCH_ROOT(f, s, ray.org, ray.dir, PORT_DEREF(m).t, ray.tfar, t, PORT_DEREF(normal), PORT_DEREF(m).i);
    PORT_DEREF(m).root_t = found != 0 ? PORT_DEREF(m).root_t : sdft_maxf(t, PORT_DEREF(m).t);
    PORT_DEREF(t_out) = found != 0 ? t : sdft_maxf(t, PORT_DEREF(m).t);
    return found;
}

/* The hit at the field's exact root t, with the normal n the field gave there. */
PORT_INLINE sdft_hit march_exact_hit(PORT_IN(march_state) m, float t, sdft_vec3 n)
{
    sdft_hit hit;
    hit.t = t;
    hit.distance = 0.0f;
    hit.status = SDFT_HIT;
    hit.steps = PORT_DEREF(m).i;
    hit.fallbacks = PORT_DEREF(m).fallbacks;
    hit.normal = n;
    return hit;
}

/* What the value the loop takes next is: line 4's f(tnear), f where the
 * exact root left off (marching restarts there), or f at the variant's
 * trial point. */
#define MARCH_FRESH 0
#define MARCH_RESTART 1
#define MARCH_STEP_NEXT 2

/* One ray, on [ray.tnear, ray.tfar] (already clipped): the listings'
 * loop. Inlined (in C) into each variant with its start and step folded
 * in. Written with one evaluation of f in it, at T, whatever the value is
 * for: the shader inlines everything, and f (a grid's sampler) is its
 * largest part. */
PORT_INLINE sdft_hit march_one(MARCH_FIELD f, MARCH_SCRATCH s, sdft_ray ray, sdft_trace_params p, march_start_fn start,
                               march_step_fn step)
{
    const float reach = MARCH_ROOT_REACH(f, p);
    march_state m;
    float T = ray.tnear;
    int next = MARCH_FRESH;
    for (;;) {
        const float R = MARCH_EVAL(f, s, ray, T);
        if (next == MARCH_STEP_NEXT) {
            MARCH_STEP(step, PORT_REF(m), T, R, p);
            m.i++;
        } else {
            if (next == MARCH_FRESH)
                march_begin(PORT_REF(m), p, T, R); /* line 4 */
            else
                march_restart(PORT_REF(m), p, T, R);
            MARCH_START(start, PORT_REF(m), p);
            next = MARCH_STEP_NEXT;
        }
        if (!march_on(p, ray, m.t, m.r, m.i))
            break;
        if (march_root_due(reach, PORT_REF(m))) {
            float at;
            sdft_vec3 n;
            if (march_root(f, s, ray, PORT_REF(m), PORT_REF(at), PORT_REF(n)) != 0)
                return march_exact_hit(PORT_REF(m), at, n);
            if (at > m.t) {
                next = MARCH_RESTART;
                T = at;
                continue;
            }
        }
        T = m.t + m.z;
    }
    return march_end(f, s, ray, p, PORT_REF(m));
}

/* The ray clipped to the field's bounds, in clipped; 0 when it misses
 * them, and then miss is its hit: a miss at tfar after no evaluation. */
PORT_INLINE int march_clip(MARCH_FIELD f, sdft_ray ray, PORT_OUT(sdft_ray) clipped, PORT_OUT(sdft_hit) miss)
{
    PORT_DEREF(clipped) = ray;
    if (MARCH_CLIP_BOX(MARCH_BOUNDS(f), ray.org, ray.dir, ray.tnear, ray.tfar, PORT_REF(PORT_DEREF(clipped).tnear),
                       PORT_REF(PORT_DEREF(clipped).tfar)) != 0)
        return 1;
    PORT_DEREF(miss).t = ray.tfar;
    PORT_DEREF(miss).distance = INFINITY;
    PORT_DEREF(miss).status = SDFT_MISS;
    PORT_DEREF(miss).steps = 0u;
    PORT_DEREF(miss).fallbacks = 0u;
    PORT_DEREF(miss).normal = sdft_v3(0.0f, 0.0f, 0.0f);
    return 0;
}

#endif
