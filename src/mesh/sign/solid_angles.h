// sdftrace — the solid angles of a few triangles seen from one point, four
// at a time with AVX2 where the processor has it (chosen at run time, so the
// build runs on any x86-64), for the exact near field of the winding number
// (winding.h). No OpenVDB here.
#ifndef SDFT_MESH_SIGN_SOLID_ANGLES_H
#define SDFT_MESH_SIGN_SOLID_ANGLES_H

#include <cstddef>

namespace meshsdf
{

/// Solid angle of the triangle with corners a, b, c (3 doubles each,
/// relative to the point it is seen from), divided by 4π: Van Oosterom and
/// Strackee (1983), "The solid angle of a plane triangle".
double solidAngleOver4Pi(const double *a, const double *b, const double *c);

/// Triangles stored four to a group, component by component: group g holds
/// 36 doubles, corner a's x of its four triangles, then a's y, a's z, b's x,
/// ..., c's z. Lanes past the last triangle may hold anything finite.
constexpr int kSolidAngleLanes = 4;
constexpr int kSolidAngleGroup = 9 * kSolidAngleLanes;

/// Whether solidAnglesOver4Pi runs four lanes at once on this processor.
bool solidAnglesVectorized();

/// Sum over the first `count` triangles of `groups` of the solid angle seen
/// from q (3 doubles), divided by 4π, as solidAngleOver4Pi gives it (to
/// rounding); four lanes at once where `vectorized` (and the processor
/// has them).
double solidAnglesOver4Pi(const double *groups, int count, const double *q, bool vectorized = true);

} // namespace meshsdf

#endif
