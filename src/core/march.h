/* sdftrace — the tracing variants' loop in the C library: the field
 * interface that src/portable/march_loop.h asks of its includer (a field's
 * distance callback and its accel's exact root), and what only the CPU
 * does: marching a stream of rays interleaved. Internal header. */
#ifndef SDFTRACE_MARCH_H
#define SDFTRACE_MARCH_H

#include <math.h>

#include "march_state.h"
#include "sdftrace/trace.h"

/* The field as march_loop.h sees it: a callback and its accel. */
#define MARCH_FIELD const sdft_field *
#define MARCH_SCRATCH sdft_scratch *
/* F(t) = f(o + t d): the field along the ray. */
#define MARCH_EVAL(f, s, ray, t) (f)->distance((f)->ctx, (s), sdft_madd((ray).org, (ray).dir, (t)))
#define MARCH_HAS_ROOT(f, p) ((p).exact_root && (f)->accel && (f)->accel->root)
/* The reach march_root_due compares with, read once per ray or stream:
 * the field's root_reach where the tracer may ask for its exact root,
 * else -infinity (no r is below it). */
#define MARCH_ROOT_REACH(f, p) (MARCH_HAS_ROOT(f, p) ? (f)->accel->root_reach : -INFINITY)
#define MARCH_ROOT(f, s, org, dir, t0, t1, t, normal, reads)                                                           \
    (f)->accel->root((f)->accel->ctx, (s), (org), (dir), (t0), (t1), &(t), &(normal), &(reads))
#define MARCH_BOUNDS(f) ((f)->bounds)
/* A variant's start and step: inlined into the drivers, which take them as
 * constants. */
typedef void (*march_start_fn)(march_state *m, sdft_trace_params p);
typedef void (*march_step_fn)(march_state *m, float T, float R, sdft_trace_params p);
#define MARCH_START(fn, m, p) (fn)((m), (p))
#define MARCH_STEP(fn, m, T, R, p) (fn)((m), (T), (R), (p))

#include "march_loop.h"
#include "variants.h"

#define MARCH_INLINE PORT_INLINE

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
        if (march_clip(f, rays[i], &lane->ray, &hits[i])) {
            lane->index = i, lane->T = lane->ray.tnear, lane->next = LANE_FRESH;
            return 1;
        }
    }
    return 0;
}

MARCH_INLINE void march_many(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                             const sdft_trace_params *tp, march_start_fn start, march_step_fn step)
{
    const sdft_trace_params p = *tp;
    march_lane lane[MARCH_LANES];
    float R[MARCH_LANES];
    const float reach = MARCH_ROOT_REACH(f, p);
    size_t next = 0;
    int live = 0;
    while (live < MARCH_LANES && march_take(f, rays, hits, n, &next, &lane[live]))
        live++;
    while (live > 0) {
        /* No sdft_field_accel.prefetch hints here: a ray's next point mostly lies in
         * the cache lines of its last, and on every grid of the bench the
         * hints cost more than they saved (frames 2-8% slower with them). */
        for (int k = 0; k < live; k++) /* independent: their loads overlap */
            R[k] = MARCH_EVAL(f, s, lane[k].ray, lane[k].T);
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
            if (march_on(p, l->ray, l->m.t, l->m.r, l->m.i)) {
                float at;
                sdft_vec3 nrm;
                if (!march_root_due(reach, &l->m)) {
                    l->T = l->m.t + l->m.z;
                    continue;
                }
                if (!march_root(f, s, l->ray, &l->m, &at, &nrm)) {
                    l->next = at > l->m.t ? LANE_RESTART : LANE_STEP;
                    l->T = at > l->m.t ? at : l->m.t + l->m.z;
                    continue;
                }
                hits[l->index] = march_exact_hit(&l->m, at, nrm);
            } else {
                hits[l->index] = march_end(f, s, l->ray, p, &l->m);
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

/* Each variant's stream entry (march_many with its start and step; trace.c). */
#define MARCH_STREAM_DECL(method, name)                                                                                \
    void march_stream_##name(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,     \
                             const sdft_trace_params *p);
MARCH_VARIANTS(MARCH_STREAM_DECL)
#undef MARCH_STREAM_DECL

#endif
