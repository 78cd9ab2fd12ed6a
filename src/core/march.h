/* sdftrace — what the five tracing variants share: evaluating f along the
 * ray, the termination rule, the screen-space candidate, hit refinement.
 * Internal header. */
#ifndef SDFTRACE_MARCH_H
#define SDFTRACE_MARCH_H

#include <math.h>

#include "sdftrace/trace.h"

/* F(t) = f(o + t d): the field along the ray. */
static inline float march_eval(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, float t)
{
    return f->distance(f->ctx, s, sdft_madd(ray->org, ray->dir, t));
}

/* eps(t) = eps + pixel_radius * t: a constant radius, Keinert's screen-space
 * radius, or both. One expression, so the loops do not branch on it. */
static inline float march_eps(const sdft_trace_params *p, float t) { return p->eps + p->pixel_radius * t; }

/* The shared loop condition: r > eps(t), t + r < t_max, i < i_max. */
static inline int march_on(const sdft_trace_params *p, const sdft_ray *ray, float t, float r, uint32_t i)
{
    return r > march_eps(p, t) && t + r < ray->tfar && i < p->max_steps;
}

/* Keinert §3.2: the accepted point with the smallest error r / eps(t). */
typedef struct march_candidate {
    float t, r, error;
} march_candidate;

static inline void march_offer(march_candidate *c, const sdft_trace_params *p, float t, float r)
{
    float error = r / sdft_maxf(march_eps(p, t), 1e-30f);
    if (error < c->error)
        *c = (march_candidate){t, r, error};
}

/* Turns the final state of a march into a hit: classifies it, refines a hit
 * onto the surface from the last two accepted samples (t0, r0), (t, r), and
 * on non-convergence with the screen-space criterion returns the candidate. */
sdft_hit march_finish(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p, float t0,
                      float r0, float t, float r, uint32_t steps, uint32_t fallbacks, march_candidate best);

/* What Algorithms 1-4 and Keinert's Listing 2 keep between iterations: the
 * accepted point (t, r), the step z to the next trial point T = t + z,
 * auto's slope m, the relaxation omega in force (Listing 2 drops it to 1 for
 * the rest of the ray), the point accepted before (t0, r0) for refinement,
 * the count i of evaluations, the fallbacks and the screen-space candidate;
 * and root_t, up to where the field's exact root was last asked for
 * (march_root). */
typedef struct march_state {
    float t, r, z, m, omega;
    float t0, r0;
    uint32_t i, fallbacks;
    march_candidate best;
    float root_t;
} march_state;

/* A variant is two functions of the state: `start` completes line 4 once
 * f(tnear) is in (t, r) (it sets z, and m for auto); `step` is the body of
 * the loop given R = f(T) at the trial point T = t + z: it accepts or falls
 * back and sets the next z. The drivers below count i. */
typedef void (*march_start_fn)(march_state *m, const sdft_trace_params *p);
typedef void (*march_step_fn)(march_state *m, float T, float R, const sdft_trace_params *p);

/* Line 4's first evaluation: (t, r) = (t, f(t)), i = 1, omega as given;
 * the variant's start sets z (and m). */
static inline void march_begin(march_state *m, const sdft_trace_params *p, float t, float r)
{
    *m = (march_state){
        .t = t, .r = r, .omega = p->omega, .t0 = t, .r0 = r, .i = 1, .best = {t, r, INFINITY}, .root_t = -INFINITY};
    march_offer(&m->best, p, t, r);
}

/* Marching resumes at t, r = f(t), after the field's root proved the ray
 * free up to t: like line 4 (the variant's start follows), but the counts,
 * the candidate and the omega in force go on. */
static inline void march_restart(march_state *m, const sdft_trace_params *p, float t, float r)
{
    m->t0 = m->t, m->r0 = m->r;
    m->t = t, m->r = r;
    m->i++;
    march_offer(&m->best, p, t, r);
}

/* t := T, r := R, keeping the point before for refinement. */
static inline void march_accept(march_state *m, const sdft_trace_params *p, float T, float R)
{
    m->t0 = m->t, m->r0 = m->r;
    m->t = T, m->r = R;
    march_offer(&m->best, p, T, R);
}

static inline sdft_hit march_end(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p,
                                 const march_state *m)
{
    return march_finish(f, s, ray, p, m->t0, m->r0, m->t, m->r, m->i, m->fallbacks, m->best);
}

/* THE EXACT LAST CELL. A field that knows its own form near the surface
 * (sdft_field_accel.root: a grid's trilinear cells, where f along the ray is a
 * cubic) is asked for the exact first root once the accepted point is
 * within its reach (eps(t) < r < root_reach) instead of stepping on to eps:
 * its answer is the hit, on the surface itself, or a stretch [t, t') it
 * proved free, after which marching restarts at t' (the variant's state
 * begins anew there; its history does not span the jump). It is asked at
 * most once per stretch (root_t), and the data it reads counts as
 * evaluations. Only with p->exact_root and a field that has one
 * (march_root_reach). */
static inline int march_root_due(float reach, const march_state *m) { return m->r < reach && m->t > m->root_t; }

/* The reach march_root_due compares with, read once per ray or stream:
 * the field's root_reach where the tracer may ask for its exact root,
 * else -infinity (no r is below it). */
static inline float march_root_reach(const sdft_field *f, const sdft_trace_params *p)
{
    return p->exact_root && f->accel && f->accel->root ? f->accel->root_reach : -INFINITY;
}

/* Asks the field; 1 when it found the root (*t_out: where, *normal: the
 * normal there), else 0 with *t_out where marching resumes (m->t when the
 * field could not go on). */
static inline int march_root(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, march_state *m, float *t_out,
                             sdft_vec3 *normal)
{
    float t = m->t;
    const int found = f->accel->root(f->accel->ctx, s, ray->org, ray->dir, m->t, ray->tfar, &t, normal, &m->i);
    m->root_t = found ? m->root_t : sdft_maxf(t, m->t);
    *t_out = found ? t : sdft_maxf(t, m->t);
    return found;
}

/* The hit at the field's exact root t, with the normal n the field gave there. */
static inline sdft_hit march_exact_hit(const march_state *m, float t, sdft_vec3 n)
{
    return (sdft_hit){
        .t = t, .distance = 0.0f, .status = SDFT_HIT, .steps = m->i, .fallbacks = m->fallbacks, .normal = n};
}

#if defined(__GNUC__)
#define MARCH_INLINE static inline __attribute__((always_inline))
#else
#define MARCH_INLINE static inline
#endif
/* A variant's start and step: inlined into the drivers below, which take
 * them as constants. */
#define MARCH_VARIANT MARCH_INLINE

/* One ray, on [ray->tnear, ray->tfar] (already clipped): the listings'
 * loop. Inlined into each variant with its start and step folded in. */
MARCH_INLINE sdft_hit march_one(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p,
                                march_start_fn start, march_step_fn step)
{
    march_state m;
    const float reach = march_root_reach(f, p);
    march_begin(&m, p, ray->tnear, march_eval(f, s, ray, ray->tnear)); /* line 4 */
    start(&m, p);
    while (march_on(p, ray, m.t, m.r, m.i)) {
        float at;
        sdft_vec3 n;
        if (march_root_due(reach, &m)) {
            if (march_root(f, s, ray, &m, &at, &n))
                return march_exact_hit(&m, at, n);
            if (at > m.t) {
                march_restart(&m, p, at, march_eval(f, s, ray, at));
                start(&m, p);
                continue;
            }
        }
        const float T = m.t + m.z;
        step(&m, T, march_eval(f, s, ray, T), p);
        m.i++;
    }
    return march_end(f, s, ray, p, &m);
}

/* The ray clipped to the field's bounds, in *clipped; 0 when it misses
 * them, and then *miss is its hit: a miss at tfar after no evaluation. */
static inline int march_clip(const sdft_field *f, const sdft_ray *ray, sdft_ray *clipped, sdft_hit *miss)
{
    *clipped = *ray;
    if (sdft_aabb_clip(f->bounds, ray->org, ray->dir, ray->tnear, ray->tfar, &clipped->tnear, &clipped->tfar))
        return 1;
    *miss = (sdft_hit){.t = ray->tfar, .distance = INFINITY, .status = SDFT_MISS};
    return 0;
}

/* Rays marched together, each exactly as sdft_trace marches it alone: the
 * same points in the same order, so the same hits and counts. One ray's
 * evaluations form a chain (each point depends on the last value), and on
 * a grid most of an evaluation is waiting for memory; interleaving
 * MARCH_LANES independent chains lets those waits overlap. A lane whose ray
 * ends takes the next. */
enum { MARCH_LANES = 16 };

enum { LANE_STEP, LANE_FRESH, LANE_RESTART };

typedef struct march_lane {
    march_state m;
    sdft_ray ray; /* clipped */
    size_t index; /* in rays[] and hits[] */
    float T;      /* where the lane's next value is taken */
    int next;     /* what that value is: LANE_FRESH line 4's f(tnear), LANE_RESTART where the root left off,
                   * LANE_STEP the variant's trial point */
} march_lane;

/* Gives the lane the next ray that survives clipping (the others' hits are
 * misses at once); 0 when there is none left. */
static inline int march_take(const sdft_field *f, const sdft_ray *rays, sdft_hit *hits, size_t n, size_t *next,
                             march_lane *lane)
{
    while (*next < n) {
        const size_t i = (*next)++;
        if (march_clip(f, &rays[i], &lane->ray, &hits[i])) {
            lane->index = i, lane->T = lane->ray.tnear, lane->next = LANE_FRESH;
            return 1;
        }
    }
    return 0;
}

MARCH_INLINE void march_many(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                             const sdft_trace_params *p, march_start_fn start, march_step_fn step)
{
    march_lane lane[MARCH_LANES];
    float R[MARCH_LANES];
    const float reach = march_root_reach(f, p);
    size_t next = 0;
    int live = 0;
    while (live < MARCH_LANES && march_take(f, rays, hits, n, &next, &lane[live]))
        live++;
    while (live > 0) {
        /* No sdft_field_accel.prefetch hints here: a ray's next point mostly lies in
         * the cache lines of its last, and on every grid of the bench the
         * hints cost more than they saved (frames 2-8% slower with them). */
        for (int k = 0; k < live; k++) /* independent: their loads overlap */
            R[k] = march_eval(f, s, &lane[k].ray, lane[k].T);
        for (int k = 0; k < live; k++) {
            march_lane *l = &lane[k];
            if (l->next == LANE_STEP) {
                step(&l->m, l->T, R[k], p);
                l->m.i++;
            } else {
                if (l->next == LANE_FRESH)
                    march_begin(&l->m, p, l->T, R[k]);
                else
                    march_restart(&l->m, p, l->T, R[k]);
                start(&l->m, p);
                l->next = LANE_STEP;
            }
            if (march_on(p, &l->ray, l->m.t, l->m.r, l->m.i)) {
                float at;
                sdft_vec3 n;
                if (!march_root_due(reach, &l->m)) {
                    l->T = l->m.t + l->m.z;
                    continue;
                }
                if (!march_root(f, s, &l->ray, &l->m, &at, &n)) {
                    l->next = at > l->m.t ? LANE_RESTART : LANE_STEP;
                    l->T = at > l->m.t ? at : l->m.t + l->m.z;
                    continue;
                }
                hits[l->index] = march_exact_hit(&l->m, at, n);
            } else {
                hits[l->index] = march_end(f, s, &l->ray, p, &l->m);
            }
            if (march_take(f, rays, hits, n, &next, l))
                continue;
            /* None left: the last lane moves here and is stepped in its turn. */
            live--;
            lane[k] = lane[live], R[k] = R[live];
            k--;
        }
    }
}

/* Each variant's stream entry (march_many with its start and step). */
void march_stream_sphere(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                         const sdft_trace_params *p);
void march_stream_relaxed(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                          const sdft_trace_params *p);
void march_stream_relaxed_bv(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                             const sdft_trace_params *p);
void march_stream_enhanced(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                           const sdft_trace_params *p);
void march_stream_auto(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                       const sdft_trace_params *p);

#endif
