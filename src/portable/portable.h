/* sdftrace — one source, two targets. The headers of src/portable hold what
 * a ray needs (the tracing variants and their loop, a grid's trilinear
 * sampling and its bounds, the exact root in the last cell, a pixel's
 * shading and shadow ray) and compile both as C11, into the library, and
 * as GLSL 4.50, into the Vulkan compute shader (src/gpu), the way
 * PNanoVDB.h compiles as C, HLSL and GLSL. They are written in the C that
 * GLSL also reads; the few differences go through this seam:
 *   - no pointers: a parameter the function changes is PORT_OUT(T) or
 *     PORT_INOUT(T), one it only reads in place PORT_IN(T) (C: pointers;
 *     GLSL: out, inout, a copy), each used through PORT_DEREF(x) and passed
 *     as PORT_REF(x) (PNanoVDB's idiom); small values pass by value; a grid
 *     is GRID(g).member, its tables GRID_WORD and friends (grid_layout.h);
 *   - the conversions GLSL does not make by itself: PORT_INT, PORT_UINT,
 *     PORT_FLOAT, PORT_DOUBLE, PORT_INDEX (a table index: size_t in C);
 *   - bool is not int in GLSL: conditions are comparisons, and a bool that
 *     counts goes through PORT_INT or PORT_UINT;
 *   - struct values are built member by member (no compound literals),
 *     constant tables are PORT_CONST and initialised with braces;
 *   - functions are PORT_INLINE (C: static, always inlined, so a caller
 *     specialised on constants keeps no branch on them) or PORT_COLD (C:
 *     static, never inlined: out of the hot loop's way); a GPU driver
 *     inlines every call, so a loop around a large call is PORT_NO_UNROLL
 *     (GLSL: [[dont_unroll]]; C: nothing) lest the shader grow by copies;
 *   - the C library's and sdftrace/vec3.h's names for math (fabsf, sqrtf,
 *     copysignf, nextafterf, isfinite, sdft_minf, sdft_madd, sdft_dot, ...)
 *     are defined for GLSL below with the same operations in the same order,
 *     so that both targets round alike where the hardware rounds as IEEE
 *     does (a GPU's division and square root may not: a hit's depth then
 *     differs in the last bits).
 * C includes this with nothing defined; the shader defines SDFT_GLSL
 * first. */
#ifndef SDFTRACE_PORTABLE_H
#define SDFTRACE_PORTABLE_H

#if !defined(SDFT_GLSL)

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sdftrace/trace.h"

#if defined(__GNUC__)
#define PORT_INLINE static inline __attribute__((always_inline))
#define PORT_COLD static __attribute__((noinline, unused))
#else
#define PORT_INLINE static inline
#define PORT_COLD static
#endif
#define PORT_CONST static const
#define PORT_IN(T) const T *
#define PORT_OUT(T) T *
#define PORT_INOUT(T) T *
#define PORT_DEREF(x) (*(x))
#define PORT_REF(x) (&(x))
#define PORT_ARRAY_OUT /* an array parameter the function writes: C passes its address anyway */
#define PORT_INT(x) ((int32_t)(x))
#define PORT_UINT(x) ((uint32_t)(x))
#define PORT_FLOAT(x) ((float)(x))
#define PORT_DOUBLE(x) ((double)(x))
#define PORT_INDEX(x) ((size_t)(x))
/* A struct type: C's typedef after its definition (PNanoVDB's idiom). */
#define PORT_TYPEDEF(T) typedef struct T T;
#define PORT_UNUSED(x) (void)(x)
#define PORT_NO_UNROLL

#else /* GLSL */

#define PORT_INLINE
#define PORT_COLD
#define PORT_CONST const
#define PORT_IN(T) T
#define PORT_OUT(T) out T
#define PORT_INOUT(T) inout T
#define PORT_DEREF(x) x
#define PORT_REF(x) x
#define PORT_ARRAY_OUT out
#define PORT_INT(x) int(x)
#define PORT_UINT(x) uint(x)
#define PORT_FLOAT(x) float(x)
#define PORT_DOUBLE(x) double(x)
#define PORT_INDEX(x) uint(x)
#define PORT_TYPEDEF(T)
#define PORT_UNUSED(x)
#define PORT_NO_UNROLL [[dont_unroll]]

#define int32_t int
#define uint32_t uint
#define size_t uint

#define INFINITY uintBitsToFloat(0x7F800000u)
#define NAN uintBitsToFloat(0x7FC00000u)

#define fabsf(x) abs(x)
#define fabs(x) abs(x)
#define sqrtf(x) sqrt(x)
#define floorf(x) floor(x)
#define ceilf(x) ceil(x)

float copysignf(float a, float b)
{
    return uintBitsToFloat((floatBitsToUint(a) & 0x7FFFFFFFu) | (floatBitsToUint(b) & 0x80000000u));
}

double copysign(double a, double b)
{
    const uvec2 ua = unpackDouble2x32(a), ub = unpackDouble2x32(b);
    return packDouble2x32(uvec2(ua.x, (ua.y & 0x7FFFFFFFu) | (ub.y & 0x80000000u)));
}

bool isfinite(float x) { return !isinf(x) && !isnan(x); }

/* The float next to x towards y, as C's. */
float nextafterf(float x, float y)
{
    if (isnan(x) || isnan(y))
        return x + y;
    if (x == y)
        return y;
    if (x == 0.0f)
        return y > 0.0f ? uintBitsToFloat(1u) : uintBitsToFloat(0x80000001u);
    const uint u = floatBitsToUint(x);
    return uintBitsToFloat((x < y) == (x > 0.0f) ? u + 1u : u - 1u);
}

/* sdftrace/vec3.h, operation for operation. */
#define sdft_vec3 vec3
float sdft_minf(float a, float b) { return a < b ? a : b; }
float sdft_maxf(float a, float b) { return a > b ? a : b; }
vec3 sdft_v3(float x, float y, float z) { return vec3(x, y, z); }
vec3 sdft_add(vec3 a, vec3 b) { return vec3(a.x + b.x, a.y + b.y, a.z + b.z); }
vec3 sdft_sub(vec3 a, vec3 b) { return vec3(a.x - b.x, a.y - b.y, a.z - b.z); }
vec3 sdft_mul(vec3 a, vec3 b) { return vec3(a.x * b.x, a.y * b.y, a.z * b.z); }
vec3 sdft_scale(vec3 a, float s) { return vec3(a.x * s, a.y * s, a.z * s); }
vec3 sdft_madd(vec3 o, vec3 d, float t) { return vec3(o.x + d.x * t, o.y + d.y * t, o.z + d.z * t); }
float sdft_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
vec3 sdft_cross(vec3 a, vec3 b) { return vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
float sdft_length(vec3 a) { return sqrt(sdft_dot(a, a)); }
vec3 sdft_normalize(vec3 a)
{
    float len = sdft_length(a);
    return len > 0.0f ? sdft_scale(a, 1.0f / len) : a;
}
vec3 sdft_min_v(vec3 a, vec3 b) { return vec3(sdft_minf(a.x, b.x), sdft_minf(a.y, b.y), sdft_minf(a.z, b.z)); }
vec3 sdft_max_v(vec3 a, vec3 b) { return vec3(sdft_maxf(a.x, b.x), sdft_maxf(a.y, b.y), sdft_maxf(a.z, b.z)); }
bool sdft_isfinite3(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

/* sdftrace/trace.h's plain data, member for member. */
#define SDFT_SPHERE 0
#define SDFT_RELAXED 1
#define SDFT_ENHANCED 2
#define SDFT_AUTO 3
#define SDFT_RELAXED_BV 4
#define SDFT_HIT 0
#define SDFT_MISS 1
#define SDFT_NOT_CONVERGED 2
#define SDFT_INVALID 3

struct sdft_ray {
    vec3 org;
    float tnear;
    vec3 dir;
    float tfar;
};

struct sdft_trace_params {
    int method;
    float omega;
    float beta;
    float eps;
    float pixel_radius;
    uint max_steps;
    int exact_root;
};

struct sdft_hit {
    float t;
    float distance;
    int status;
    uint steps;
    uint fallbacks;
    vec3 normal;
};

struct sdft_aabb {
    vec3 lo, hi;
};

struct sdft_slab {
    vec3 n;
    float lo, hi;
};

#endif

#endif
