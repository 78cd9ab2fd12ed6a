/* sdftrace — 3-vectors: a plain struct and the few inline operations the
 * tracer, the SDF toolkit and the renderer share. World units throughout;
 * everything is by value, nothing is allocated. */
#ifndef SDFTRACE_VEC3_H
#define SDFTRACE_VEC3_H

#include <math.h>

typedef struct sdft_vec3 {
    float x, y, z;
} sdft_vec3;

/* min and max as plain compares: they compile to one instruction, where
 * fminf/fmaxf become libm calls (their NaN rules) unless fast-math is on. */
static inline float sdft_minf(float a, float b) { return a < b ? a : b; }
static inline float sdft_maxf(float a, float b) { return a > b ? a : b; }

/* Written out rather than as a compound literal, so that the header is
 * also C++. */
static inline sdft_vec3 sdft_v3(float x, float y, float z)
{
    sdft_vec3 v;
    v.x = x, v.y = y, v.z = z;
    return v;
}
static inline sdft_vec3 sdft_add(sdft_vec3 a, sdft_vec3 b) { return sdft_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline sdft_vec3 sdft_sub(sdft_vec3 a, sdft_vec3 b) { return sdft_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline sdft_vec3 sdft_mul(sdft_vec3 a, sdft_vec3 b) { return sdft_v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline sdft_vec3 sdft_scale(sdft_vec3 a, float s) { return sdft_v3(a.x * s, a.y * s, a.z * s); }
static inline sdft_vec3 sdft_madd(sdft_vec3 o, sdft_vec3 d, float t)
{
    return sdft_v3(o.x + d.x * t, o.y + d.y * t, o.z + d.z * t);
}
static inline float sdft_dot(sdft_vec3 a, sdft_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline float sdft_length(sdft_vec3 a) { return sqrtf(sdft_dot(a, a)); }
static inline sdft_vec3 sdft_cross(sdft_vec3 a, sdft_vec3 b)
{
    return sdft_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline sdft_vec3 sdft_normalize(sdft_vec3 a)
{
    float len = sdft_length(a);
    return len > 0.0f ? sdft_scale(a, 1.0f / len) : a;
}
static inline sdft_vec3 sdft_abs3(sdft_vec3 a) { return sdft_v3(fabsf(a.x), fabsf(a.y), fabsf(a.z)); }
static inline sdft_vec3 sdft_max3(sdft_vec3 a, float s)
{
    return sdft_v3(sdft_maxf(a.x, s), sdft_maxf(a.y, s), sdft_maxf(a.z, s));
}
static inline sdft_vec3 sdft_min_v(sdft_vec3 a, sdft_vec3 b)
{
    return sdft_v3(sdft_minf(a.x, b.x), sdft_minf(a.y, b.y), sdft_minf(a.z, b.z));
}
static inline sdft_vec3 sdft_max_v(sdft_vec3 a, sdft_vec3 b)
{
    return sdft_v3(sdft_maxf(a.x, b.x), sdft_maxf(a.y, b.y), sdft_maxf(a.z, b.z));
}
static inline float sdft_maxcomp(sdft_vec3 a) { return sdft_maxf(a.x, sdft_maxf(a.y, a.z)); }
static inline int sdft_isfinite3(sdft_vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

#endif
