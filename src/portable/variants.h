/* sdftrace — the tracing variants, one portable file each (variant_*.h),
 * and the one list of them that both targets expand: the C library into
 * each variant's entry points (trace.c), the shader into a dispatch on the
 * method. To add a variant: its file, in the shape of the others (its start
 * and step beside its listing's lines), a line here, its sdft_method value
 * (sdftrace/trace.h, and SDFT_ below in portable.h for GLSL) and name
 * (trace.c), and a row in tests/test_trace.c's variants[]. Portable
 * (portable.h). */
#ifndef SDFTRACE_VARIANTS_H
#define SDFTRACE_VARIANTS_H

#include "variant_auto.h"
#include "variant_enhanced.h"
#include "variant_relaxed.h"
#include "variant_relaxed_bv.h"
#include "variant_sphere.h"

/* X(method, name): name_start and name_step are the variant's. */
#define MARCH_VARIANTS(X)                                                                                              \
    X(SDFT_SPHERE, sphere)                                                                                             \
    X(SDFT_RELAXED, relaxed)                                                                                           \
    X(SDFT_ENHANCED, enhanced)                                                                                         \
    X(SDFT_AUTO, auto)                                                                                                 \
    X(SDFT_RELAXED_BV, relaxed_bv)

#if defined(SDFT_GLSL)
/* GLSL has no function pointers: the loop names a variant by its method,
 * a constant of the shader's (a specialization constant), so that these
 * fold to the one variant's code. */
#define MARCH_START_CASE(method, name)                                                                                 \
    if (variant == method)                                                                                             \
        name##_start(m, p);
#define MARCH_STEP_CASE(method, name)                                                                                  \
    if (variant == method)                                                                                             \
        name##_step(m, T, R, p);

void march_variant_start(int variant, inout march_state m, sdft_trace_params p) { MARCH_VARIANTS(MARCH_START_CASE) }

void march_variant_step(int variant, inout march_state m, float T, float R, sdft_trace_params p)
{
    MARCH_VARIANTS(MARCH_STEP_CASE)
}
#endif

#endif
