/* sdftrace — choosing a variant, its parameters, and clipping rays to the
 * field's bounds. */
#include <float.h>
#include <stdio.h>
#include <string.h>

#include "march.h"

static const char *const method_names[SDFT_METHOD_COUNT] = {"sphere", "relaxed", "enhanced", "auto"};

const char *sdft_method_name(sdft_method m)
{
    return (unsigned)m < SDFT_METHOD_COUNT ? method_names[m] : "unknown";
}

int sdft_method_parse(const char *name)
{
    for (int m = 0; m < SDFT_METHOD_COUNT; m++)
        if (name && strcmp(name, method_names[m]) == 0)
            return m;
    return -1;
}

float sdft_default_omega(sdft_method m)
{
    return m == SDFT_RELAXED ? 1.5f : m == SDFT_ENHANCED ? 0.88f : 1.0f;
}

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

int sdft_trace_params_check(const sdft_trace_params *p, char *msg, unsigned msg_len)
{
    const char *why = NULL;
    if ((unsigned)p->method >= SDFT_METHOD_COUNT)
        why = "unknown tracing method";
    else if (p->method == SDFT_RELAXED && !(p->omega >= 1.0f && p->omega < 2.0f))
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
    if (why && msg && msg_len)
        snprintf(msg, msg_len, "%s", why);
    return why != NULL;
}

sdft_hit sdft_trace(const sdft_field *f, sdft_scratch *s, const sdft_ray *ray, const sdft_trace_params *p)
{
    sdft_ray clipped;
    sdft_hit miss;
    if (!march_clip(f, ray, &clipped, &miss))
        return miss;
    switch (p->method) {
    case SDFT_SPHERE: return sdft_trace_sphere(f, s, &clipped, p);
    case SDFT_RELAXED: return sdft_trace_relaxed(f, s, &clipped, p);
    case SDFT_ENHANCED: return sdft_trace_enhanced(f, s, &clipped, p);
    default: return sdft_trace_auto(f, s, &clipped, p);
    }
}

void sdft_trace_stream(const sdft_field *f, sdft_scratch *s, const sdft_ray *rays, sdft_hit *hits, size_t n,
                       const sdft_trace_params *p)
{
    switch (p->method) {
    case SDFT_SPHERE: march_stream_sphere(f, s, rays, hits, n, p); break;
    case SDFT_RELAXED: march_stream_relaxed(f, s, rays, hits, n, p); break;
    case SDFT_ENHANCED: march_stream_enhanced(f, s, rays, hits, n, p); break;
    default: march_stream_auto(f, s, rays, hits, n, p); break;
    }
}
