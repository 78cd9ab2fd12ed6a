/* sdftrace — a signed distance field as the tracer sees it.
 *
 * A field is data plus one function: `distance` returns a signed distance
 * bound at a world point (negative inside; |f(p)| never exceeds the true
 * distance to the surface, so a sphere of radius f(p) around p is empty).
 * Procedural scenes, a user's own SDF and discrete grids are all fields, and
 * every tracing variant and the renderer accept any of them unchanged.
 *
 * Thread safety follows Open VKL's volume/sampler split: the field itself is
 * immutable and shared by all threads; each thread owns an `sdft_scratch`
 * (its sampler: e.g. a NanoVDB read accessor), initialised once with
 * sdft_scratch_init() and passed to every call. Nothing is global and nothing
 * is allocated on the trace path. */
#ifndef SDFTRACE_FIELD_H
#define SDFTRACE_FIELD_H

#include <stddef.h>
#include <stdint.h>

#include "sdftrace/config.h"
#include "vec3.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Axis-aligned box in world units; the field's surface lies inside it. */
typedef struct sdft_aabb {
    sdft_vec3 lo, hi;
} sdft_aabb;

/* The points p with lo <= n . p <= hi, between two parallel planes (n need
 * not be unit length; n = 0 with lo <= 0 <= hi: everywhere). */
typedef struct sdft_slab {
    sdft_vec3 n;
    float lo, hi;
} sdft_slab;

/* Per-thread mutable state of a field (its sampler: a grid keeps its NanoVDB
 * read accessor here). Plain bytes, so it lives on a thread's stack;
 * SDFT_SCRATCH_BYTES bounds every field's need, and a field's scratch_init
 * and callbacks use `bytes` only. `owner` records the field the scratch was
 * prepared for (sdft_scratch_init): the tracer and the renderer refuse a
 * scratch prepared for another field rather than read through another
 * grid's cached accessor. Never set it by hand. */
#define SDFT_SCRATCH_BYTES 192
#ifdef __cplusplus
#define SDFT_ALIGNAS(n) alignas(n)
#else
#define SDFT_ALIGNAS(n) _Alignas(n)
#endif
struct sdft_scratch;
typedef void (*sdft_scratch_init_fn)(const void *ctx, struct sdft_scratch *scratch);
typedef struct sdft_scratch_owner {
    const void *ctx;           /* the field's ctx */
    sdft_scratch_init_fn init; /* and its scratch_init */
} sdft_scratch_owner;
typedef struct sdft_scratch {
    SDFT_ALIGNAS(16) unsigned char bytes[SDFT_SCRATCH_BYTES];
    sdft_scratch_owner owner;
} sdft_scratch;

/* How a surface looks (Whitted shading, Keinert et al. Section 4): its
 * colour; the fraction of light an opaque surface mirrors; and its index of
 * refraction, 0 for an opaque surface, > 1 for a clear dielectric (glass
 * 1.5), whose reflection and refraction Fresnel's term weighs (Schlick's
 * approximation), its colour tinting the light that passes through. */
typedef struct sdft_material {
    sdft_vec3 colour;  /* linear RGB, each in [0, 1] */
    float reflectance; /* opaque: [0, 1]; ignored for a dielectric */
    float ior;         /* 0: opaque; else >= 1 */
} sdft_material;

/* One convex part of a field (Keinert et al. Section 3.5): its own signed
 * distance bound, negative inside, whose surface is the field's within
 * `radius` of `centre` (the part's convex bounding volume, a sphere holding
 * the part and nothing else of the field's surface). A ray
 * that starts inside the part then finds its way out from the sphere's far
 * side, tracing backwards, instead of marching through the inside. */
typedef struct sdft_convex_part {
    float (*distance)(const void *ctx, sdft_scratch *scratch, sdft_vec3 p); /* required */
    const void *ctx; /* handed to distance; owned by whoever made the field */
    sdft_vec3 centre;
    float radius; /* world units, > 0 */
} sdft_convex_part;

/* What a field may add where it knows its own form (a grid does): its
 * exact first root along a ray, memory hints, and a hull around its
 * surface. The tracer and the renderer use each member that is set and do
 * without the others. It grows with each new speed-up, where sdft_field
 * does not: make one with sdft_field_accel_defaults() and set what you
 * provide. Owned by whoever made the field (a grid keeps its own); it must
 * outlive every field that points to it. Its callbacks get its own `ctx`,
 * so a field that wraps another and replaces the field's ctx may point to
 * the inner field's accel unchanged, as long as its distance is the inner
 * field's (the root and the hull describe that one); a wrapper that changes
 * the distance points to NULL or to its own. */
typedef struct sdft_field_accel {
    /* Shared data, handed to root and prefetch (a grid: the grid). */
    const void *ctx;
    /* Optional: the exact first root along a ray, where the field knows its
     * own form (a grid: the trilinear interpolant, a cubic along the ray in
     * each voxel cell). The tracer asks once f(org + t0 dir) lies in (0,
     * root_reach): it looks along [t0, t1] and returns 1 with *t the first t
     * where f reaches 0 and *normal the unit outward normal there (f's
     * gradient, normalized; a grid: its interpolant's, in the root's cell;
     * (0, 0, 0) where it has none), or 0 with *t the t up to which it proved
     * there is none (t0 <= *t <= t1; the tracer marches on from there). It
     * adds to *reads the evaluations' worth of data it read (a grid: one per
     * cell). `scratch` is the calling thread's, prepared for the field
     * (sdft_scratch_init). NULL: not provided; the tracer steps to eps, as
     * the papers do. */
    int (*root)(const void *ctx, sdft_scratch *scratch, sdft_vec3 org, sdft_vec3 dir, float t0, float t1, float *t,
                sdft_vec3 *normal, uint32_t *reads);
    float root_reach; /* world units; with root */
    /* Optional: a hint that distance(p) will be asked soon. The field may
     * start loading the memory that call will read (a grid: its leaf
     * directory's entry and the cell's voxel rows) and must not change any
     * result. For callers that evaluate many scattered points
     * (sdft_field_distances gives the hints), and for a renderer
     * that knows where rays will start: sdft_render hints each primary ray's
     * entry into the hull a block of rays ahead. The tracer does not hint
     * its steps, as a ray's next point mostly shares its last one's cache
     * lines. NULL: no hint. */
    void (*prefetch)(const void *ctx, sdft_vec3 p);
    /* Optional: boxes (world units) whose union holds every place where a
     * ray that starts where the field is positive can first reach 0 (a
     * grid: its leaves' cells). A renderer may start each primary ray at its
     * entry into the first of them and end it at its exit from the last.
     * hull_count 0: none. */
    const sdft_aabb *hull;
    size_t hull_count;
    /* Optional, with hull: hull_count slabs, the ith holding all of the
     * ith box's share of those places too, so a ray's part in box i is
     * where it is also in slab i (a grid: the slab along its leaf's
     * surface normal that holds the leaf's surface cells, thinner than
     * their box where the surface runs aslant). NULL: the boxes alone. */
    const sdft_slab *hull_slabs;
    /* Optional, with hull: hull_count boxes of gradients (world units),
     * the ith holding the field's gradient wherever the ith box's share of
     * those places lies. Along a ray with direction d the field changes at
     * the rate d . grad, and it can first reach 0 only where that is <= 0;
     * so where d . g > 0 for every g in the ith gradient box, the ray
     * cannot first reach 0 in box i, and a renderer may leave that box out
     * of the ray's span (a grid: bounds from its leaf's surface cells,
     * narrow where the surface is smooth, so the boxes on the far side of
     * an object drop out of a view). NULL: no such bounds. */
    const sdft_aabb *hull_gradients;
    /* Optional: the field's convex parts (above), convex_count of them, for
     * Keinert's convex-object optimization of rays that start inside one (a
     * refraction ray through a gem). NULL: none (a grid: convexity is never
     * assumed). */
    const sdft_convex_part *convex;
    size_t convex_count;
} sdft_field_accel;

/* Nothing provided: every member NULL or 0. */
SDFT_API sdft_field_accel sdft_field_accel_defaults(void);

/* What every field has. Make one with sdft_field_defaults() and set at
 * least distance and bounds (and ctx, where distance reads one), never
 * with an aggregate initializer alone: a later version may add members. */
typedef struct sdft_field {
    /* Signed distance bound at world point p. `ctx` is the shared, read-only
     * data below; `scratch` is the calling thread's own state. Required. */
    float (*distance)(const void *ctx, sdft_scratch *scratch, sdft_vec3 p);
    /* Unit outward normal at p (e.g. a grid's own gradient). Optional: NULL
     * means tetrahedral differences of `distance` (sdft_field_normal). */
    sdft_vec3 (*normal)(const void *ctx, sdft_scratch *scratch, sdft_vec3 p);
    /* Prepares a thread's scratch (its `bytes`). Optional: NULL when the
     * field keeps no per-thread state; then any scratch will do. */
    sdft_scratch_init_fn scratch_init;
    /* Shared data; owned by whoever made the field, must outlive it. Every
     * callback above gets it: a field that wraps another and replaces ctx
     * must wrap (or clear) each of the inner field's callbacks too. */
    const void *ctx;
    /* Every point with distance <= 0 lies in this box; rays are clipped to it. */
    sdft_aabb bounds;
    /* Length scale for numerical differences (normals), world units; 0 picks
     * 1e-4 of the box diagonal. Grids set one voxel. */
    float feature_size;
    /* Optional: what the field adds where it knows its own form (above; a
     * grid's). NULL: nothing, as for a procedural field. */
    const sdft_field_accel *accel;
    /* Optional: the material at surface point p (a scene's glass, its
     * checker floor). `ctx` as for distance. NULL: one material for the
     * whole field, the renderer's (sdft_render_params.material). */
    sdft_material (*material)(const void *ctx, sdft_vec3 p);
} sdft_field;

/* A field with nothing set yet: every member NULL or 0 (no distance, so
 * the tracer refuses it until distance is set). */
SDFT_API sdft_field sdft_field_defaults(void);

/* Prepares s for field f on the calling thread: f's scratch_init, and s
 * remembers f (its ctx and scratch_init). Call it once per thread and field,
 * before the first trace. */
static inline void sdft_scratch_init(const sdft_field *f, sdft_scratch *s)
{
    if (f->scratch_init)
        f->scratch_init(f->ctx, s);
    s->owner.ctx = f->ctx;
    s->owner.init = f->scratch_init;
}

/* 1 when s may serve f: f keeps no per-thread state, or s was prepared for
 * f (or for a field with the same ctx and scratch_init, e.g. the same grid
 * with another bound). sdft_trace, sdft_trace_stream and sdft_cone_march
 * check it once per call. */
static inline int sdft_scratch_serves(const sdft_scratch *s, const sdft_field *f)
{
    return !f->scratch_init || (s->owner.ctx == f->ctx && s->owner.init == f->scratch_init);
}

/* f at world point p: the distance callback itself, unchecked (the hot path). */
static inline float sdft_field_distance(const sdft_field *f, sdft_scratch *s, sdft_vec3 p)
{
    return f->distance(f->ctx, s, p);
}

/* f at the n world points p[i], into d[i]: the values n calls of
 * sdft_field_distance would give, in order. Where the field takes hints
 * (accel->prefetch), each point is hinted SDFT_FIELD_DISTANCES_AHEAD points
 * before its evaluation, so that scattered points wait for their memory
 * together rather than one after another (bench/sample_bench measures
 * what that saves). For many independent points (queries for learning, a
 * batch of probes); a ray's own steps depend on each other and gain
 * nothing. s must serve f (sdft_scratch_serves). */
#define SDFT_FIELD_DISTANCES_AHEAD 16
SDFT_API void sdft_field_distances(const sdft_field *f, sdft_scratch *s, const sdft_vec3 *p, size_t n, float *d);

/* The length scale for numerical differences: feature_size, or 1e-4 of the
 * bounds' diagonal when that is 0. World units. */
SDFT_API float sdft_field_feature_size(const sdft_field *f);

/* Unit normal at p: the field's own `normal`, else tetrahedral differences
 * (four evaluations, step = sdft_field_feature_size). s must serve f
 * (sdft_scratch_serves); this is per hit, so it is not checked here. */
SDFT_API sdft_vec3 sdft_field_normal(const sdft_field *f, sdft_scratch *s, sdft_vec3 p);

/* Ray-box slab test: on overlap sets [*t0, *t1] (clamped to [tnear, tfar])
 * and returns 1; returns 0 when the ray misses the box within that range. */
SDFT_API int sdft_aabb_clip(sdft_aabb box, sdft_vec3 org, sdft_vec3 dir, float tnear, float tfar, float *t0, float *t1);

#ifdef __cplusplus
}
#endif
#endif
