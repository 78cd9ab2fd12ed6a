/* sdftrace — choosing a variant, its parameters, each variant's entry
 * points, and clipping rays to the field's bounds. */
#include <float.h>
#include <stdio.h>
#include <string.h>

#include "fail.h"
#include "march.h"

static const char *const method_names[SDFT_METHOD_COUNT] = {"sphere", "relaxed", "enhanced", "auto", "relaxed-bv"};

const char *sdft_method_name(sdft_method m) { return (unsigned)m < SDFT_METHOD_COUNT ? method_names[m] : "unknown"; }

sdft_error sdft_method_parse(const char *name, sdft_method *out, char *msg, size_t msg_len)
{
    if (!name || !out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_method_parse: NULL %s", name ? "out" : "name");
    for (int m = 0; m < SDFT_METHOD_COUNT; m++)
        if (strcmp(name, method_names[m]) == 0) {
            *out = (sdft_method)m;
            return SDFT_OK;
        }
    return fail_with(msg, msg_len, SDFT_EINVAL, "unknown method '%s' (sphere, relaxed, relaxed-bv, enhanced or auto)",
                     name);
}

/* Over-relaxation (both forms) in [1, 2). */
static int relaxes(sdft_method m) { return m == SDFT_RELAXED || m == SDFT_RELAXED_BV; }

float sdft_default_omega(sdft_method m) { return relaxes(m) ? 1.5f : m == SDFT_ENHANCED ? 0.88f : 1.0f; }

sdft_trace_params sdft_trace_defaults(void)
{
    return (sdft_trace_params){
        .method = SDFT_AUTO,
        .omega = 1.0f,
        .beta = 0.3f,
        .eps = 1e-4f,
        .pixel_radius = 0.0f,
        .max_steps = 1000,
        .exact_root = 1,
    };
}

sdft_error sdft_trace_params_check(const sdft_trace_params *p, char *msg, size_t msg_len)
{
    const char *why = NULL;
    if (!p)
        why = "no trace parameters (NULL)";
    else if ((unsigned)p->method >= SDFT_METHOD_COUNT)
        why = "unknown tracing method";
    else if (relaxes(p->method) && !(p->omega >= 1.0f && p->omega < 2.0f))
        why = "omega must be in [1, 2) for relaxed tracing";
    else if (p->method == SDFT_ENHANCED && !(p->omega > 0.0f && p->omega <= 1.0f))
        why = "omega must be in (0, 1] for enhanced tracing";
    else if (p->method == SDFT_AUTO && !(p->beta > 0.0f && p->beta < 1.0f))
        why = "beta must be in (0, 1) for auto-relaxed tracing";
    else if (!(p->eps >= 0.0f) || !isfinite(p->eps))
        why = "eps must be a finite number >= 0";
    else if (!(p->pixel_radius >= 0.0f) || !isfinite(p->pixel_radius))
        why = "pixel radius must be a finite number >= 0";
    else if (p->eps == 0.0f && p->pixel_radius == 0.0f)
        why = "eps and pixel radius cannot both be 0";
    else if (p->max_steps < 1)
        why = "max steps must be at least 1";
    return why ? fail_with(msg, msg_len, SDFT_EINVAL, "%s", why) : SDFT_OK;
}

/* Why sdft_trace would refuse (f, s, p), or NULL. Once per call, never per
 * evaluation. */
static const char *refusal(const sdft_field *f, const sdft_scratch *s, const sdft_trace_params *p)
{
    if (!f || !f->distance)
        return "no field, or a field without a distance function";
    if (!s)
        return "no scratch (NULL)";
    if (!p)
        return "no trace parameters (NULL)";
    if ((unsigned)p->method >= SDFT_METHOD_COUNT)
        return "unknown tracing method";
    if (!sdft_scratch_serves(s, f))
        return "the scratch was prepared for another field (sdft_scratch_init it for this one)";
    return NULL;
}

sdft_error sdft_trace_check(const sdft_field *f, const sdft_scratch *s, const sdft_trace_params *p, char *msg,
                            size_t msg_len)
{
    const char *why = refusal(f, s, p);
    return why ? fail_with(msg, msg_len, SDFT_EINVAL, "%s", why) : sdft_trace_params_check(p, msg, msg_len);
}

static sdft_hit refused(void) { return (sdft_hit){.t = NAN, .distance = NAN, .status = SDFT_INVALID}; }

/* Each variant's two entries (variants.h lists them): sdft_trace_NAME, one
 * ray on its own, and march_stream_NAME, a stream; each with the
 * variant's start and step folded into the loop. */
#define VARIANT_ENTRIES(method, name)                                                                                  \
    sdft_hit sdft_trace_##name(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)  \
    {                                                                                                                  \
        return march_one(f, s, *ray, *p, name##_start, name##_step);                                                   \
    }                                                                                                                  \
    void march_stream_##name(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,     \
                             const sdft_trace_params *p)                                                               \
    {                                                                                                                  \
        march_many(f, s, rays, hits, n, p, name##_start, name##_step);                                                 \
    }
MARCH_VARIANTS(VARIANT_ENTRIES)
#undef VARIANT_ENTRIES

/* The entries by method; refusal() rules out any other method before the
 * table is read. */
#define VARIANT_ROW(method, name) [method] = {sdft_trace_##name, march_stream_##name},
static const struct {
    sdft_hit (*one)(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p);
    void (*stream)(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                   const sdft_trace_params *p);
} variants[SDFT_METHOD_COUNT] = {MARCH_VARIANTS(VARIANT_ROW)};
#undef VARIANT_ROW

sdft_hit sdft_trace(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)
{
    if (!ray || refusal(f, s, p))
        return refused();
    sdft_ray clipped;
    sdft_hit miss;
    if (!march_clip(f, *ray, &clipped, &miss))
        return miss;
    return variants[p->method].one(f, s, &clipped, p);
}

void sdft_trace_stream(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                       const sdft_trace_params *p)
{
    if (!hits)
        return;
    if ((!rays && n) || refusal(f, s, p)) {
        for (size_t i = 0; i < n; i++)
            hits[i] = refused();
        return;
    }
    variants[p->method].stream(f, s, rays, hits, n, p);
}
