// sdftrace — the per-row work of the packet search (nearest_triangle.cpp):
// for one row of four voxel centres (i, j, 0..3), which differ only in z,
// a node's two lower bounds and a triangle's squared distances (also the
// exact band's rows, band.cpp). Written
// twice, lane by lane in plain C++ (ScalarRows) and four lanes at once with
// AVX2 and FMA (Avx2Rows, for a caller compiled for those: see
// NearestTriangle::searchAvx2); both compute the same formulas, to rounding.
// Avx512Rows (the dense search only) does a group of two rows, eight lanes,
// in one AVX-512 vector, lane by lane Avx2Rows's operations.
// No OpenVDB here.
//
// Why the distance is exact (PreparedTriangle, rowDistances). Let q be the
// point of triangle T nearest to p, and h the height of p above T's plane.
// If p's projection onto the plane lies inside T, q is that projection and
// |p - q|^2 = h^2. Otherwise q lies on T's boundary (a point inside T's
// relative interior is not a local minimum of the distance unless it is the
// projection), the union of three segments; the squared distance to the
// segment from v along e is |w - t e|^2 with w = p - v and t = (w . e /
// |e|^2) clamped to [0, 1]. The projection is inside T when its offset from
// each edge along that edge's inward normal in the plane (normal x edge,
// with the corners counter-clockwise about the normal) is positive. Where
// that test errs by rounding, the projection lies within rounding of an
// edge, and the two answers differ by rounding. A triangle of no area
// (a segment or a point), or so thin that its normal would be unreliable
// (kThin), is the union of its three edges: its normal and inward normals
// are 0, the inside test always fails, and the minimum over the edges is
// exact for a degenerate triangle and within half its width otherwise.
#ifndef SDFT_MESH_DISTANCE_PACKET_ROWS_H
#define SDFT_MESH_DISTANCE_PACKET_ROWS_H

#include <algorithm>
#include <cmath>
#include <cstdint>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SDFT_MESH_ROWS_AVX2 1
#endif

namespace meshsdf
{

/// Whether this processor runs Avx2Rows (AVX2 and FMA).
inline bool rowsVectorizable()
{
#ifdef SDFT_MESH_ROWS_AVX2
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    return false;
#endif
}

/// A triangle prepared for many distance queries (see above).
struct PreparedTriangle {
    double corner[3][3]; // a, b, c
    double edge[3][3];   // b - a, c - b, a - c: edge k runs from corner k
    double inverse[3];   // 1 / |edge k|^2, or 0 for an edge of length 0
    double normal[3];    // unit normal (b - a) x (c - a), or 0 (no area, or thin)
    double inward[3][3]; // normal x edge k, or 0
};

/// A triangle thinner than kThin times its longest edge (twice its area over
/// that edge) counts as its three edges: its unit normal, from a cross
/// product whose rounding is a few ulps of |edge|^2, would carry a relative
/// error of about 1e-16 / kThin, and the edges' answer is off by at most
/// half the width, kThin / 2 times the edge.
constexpr double kThin = 1e-8;

inline PreparedTriangle prepareTriangle(const double *a, const double *b, const double *c)
{
    PreparedTriangle t{};
    const double *corners[3] = {a, b, c};
    double longest2 = 0;
    for (int k = 0; k < 3; ++k) {
        const double *from = corners[k], *to = corners[(k + 1) % 3];
        double length2 = 0;
        for (int x = 0; x < 3; ++x) {
            t.corner[k][x] = from[x];
            t.edge[k][x] = to[x] - from[x];
            length2 += t.edge[k][x] * t.edge[k][x];
        }
        t.inverse[k] = length2 > 0 ? 1 / length2 : 0;
        longest2 = std::max(longest2, length2);
    }
    const double *e0 = t.edge[0], *e2 = t.edge[2]; // (b - a) x (c - a) = e0 x -e2
    const double n[3] = {e2[1] * e0[2] - e2[2] * e0[1], e2[2] * e0[0] - e2[0] * e0[2], e2[0] * e0[1] - e2[1] * e0[0]};
    const double twiceArea = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(twiceArea > kThin * longest2)) // width twiceArea / longest <= kThin * longest
        return t;
    for (int x = 0; x < 3; ++x)
        t.normal[x] = n[x] / twiceArea;
    for (int k = 0; k < 3; ++k) {
        const double *m = t.normal, *e = t.edge[k];
        t.inward[k][0] = m[1] * e[2] - m[2] * e[1];
        t.inward[k][1] = m[2] * e[0] - m[0] * e[2];
        t.inward[k][2] = m[0] * e[1] - m[1] * e[0];
    }
    return t;
}

/// Squared distance from p (3 doubles) to the triangle (see above).
inline double preparedDistance2(const PreparedTriangle &t, const double *p)
{
    double edges = INFINITY, height = 0;
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
        const double w[3] = {p[0] - t.corner[k][0], p[1] - t.corner[k][1], p[2] - t.corner[k][2]};
        const double *e = t.edge[k], *m = t.inward[k];
        const double s = std::clamp((w[0] * e[0] + w[1] * e[1] + w[2] * e[2]) * t.inverse[k], 0.0, 1.0);
        const double r[3] = {w[0] - s * e[0], w[1] - s * e[1], w[2] - s * e[2]};
        edges = std::min(edges, r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        inside = inside && w[0] * m[0] + w[1] * m[1] + w[2] * m[2] > 0;
        if (k == 0)
            height = w[0] * t.normal[0] + w[1] * t.normal[1] + w[2] * t.normal[2];
    }
    return inside ? height * height : edges;
}

/// A node's per-axis terms for a packet (terms(), then groupReaches() per group of rows): for
/// axis k and coordinate index i, the squared gap to the node's box, the
/// height above its disc's centre along the disc's normal, and the squared
/// offset from that centre; with the disc's thickness and radius.
struct RowTerms {
    alignas(32) double gap[3][4], height[3][4], square[3][4];
    double thickness, radius;
};

/// The cancellation allowance and shrink of nearest_triangle.cpp's bounds.
struct RowRounding {
    double cancel, shrink;
};

struct ScalarRows {
    /// Rows per group (groupDistances, lowerGroup): one.
    static constexpr int kRows = 1;

    /// The terms of the node with box [lo, hi] and disc (centre, normal,
    /// thickness, radius) for the packet whose centres have coordinates
    /// axis[k][0..3] along axis k.
    static RowTerms terms(const double (*axis)[4], const float *lo, const float *hi, const double *centre,
                          const double *normal, double thickness, double radius)
    {
        RowTerms t;
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 4; ++i) {
                const double gap = std::max({double(lo[k]) - axis[k][i], 0.0, axis[k][i] - double(hi[k])});
                const double offset = axis[k][i] - centre[k];
                t.gap[k][i] = gap * gap;
                t.height[k][i] = offset * normal[k];
                t.square[k][i] = offset * offset;
            }
        t.thickness = thickness;
        t.radius = radius;
        return t;
    }

    /// best[l] = min(best[l], d2[l]); bit l set where d2[l] was smaller.
    static unsigned lower(const double *d2, double *best)
    {
        unsigned mask = 0;
        for (int l = 0; l < 4; ++l)
            if (d2[l] < best[l]) {
                best[l] = d2[l];
                mask |= 1u << l;
            }
        return mask;
    }

    /// Bit l set for each centre (i, j, l) whose lower bound on the node is
    /// below best[l] (nearest_triangle.cpp gives the bound): the group of
    /// kRows rows from (i, j) is this one row.
    static unsigned groupReaches(const RowTerms &n, RowRounding r, int i, int j, const double *best)
    {
        const double gap = n.gap[0][i] + n.gap[1][j], height = n.height[0][i] + n.height[1][j];
        const double square = n.square[0][i] + n.square[1][j];
        unsigned mask = 0;
        for (int l = 0; l < 4; ++l) {
            const double a = height + n.height[2][l];
            const double offset2 = square + n.square[2][l], lateral2 = offset2 - a * a - r.cancel * offset2;
            const double across = std::max(std::abs(a) - n.thickness, 0.0);
            const double along = std::sqrt(std::max(lateral2, n.radius * n.radius)) - n.radius;
            const double disc = across * across + along * along - r.cancel * offset2;
            const double bound = std::max(n.gap[2][l] + gap, disc) * r.shrink;
            mask |= unsigned(bound < best[l]) << l;
        }
        return mask;
    }

    /// Squared distances from (x, y, z[l]), l < 4, to the triangle.
    static void distances(const PreparedTriangle &t, double x, double y, const double *z, double *d2)
    {
        for (int l = 0; l < 4; ++l) {
            const double p[3] = {x, y, z[l]};
            d2[l] = preparedDistance2(t, p);
        }
    }

    /// A group of kRows rows, (x, y[r], z[l]) in lane 4 r + l: one row here.
    static void groupDistances(const PreparedTriangle &t, double x, const double *y, const double *z, double *d2)
    {
        distances(t, x, y[0], z, d2);
    }
    static unsigned lowerGroup(const double *d2, double *best) { return lower(d2, best); }
};

#ifdef SDFT_MESH_ROWS_AVX2
#define MESH2SDF_AVX2_INLINE __attribute__((target("avx2,fma"))) inline
struct Avx2Rows {
    static constexpr int kRows = 1;

    MESH2SDF_AVX2_INLINE static RowTerms terms(const double (*axis)[4], const float *lo, const float *hi,
                                               const double *centre, const double *normal, double thickness,
                                               double radius)
    {
        RowTerms t;
        const __m256d zero = _mm256_setzero_pd();
        for (int k = 0; k < 3; ++k) {
            const __m256d x = _mm256_load_pd(axis[k]);
            const __m256d gap = _mm256_max_pd(_mm256_max_pd(_mm256_sub_pd(_mm256_set1_pd(lo[k]), x), zero),
                                              _mm256_sub_pd(x, _mm256_set1_pd(hi[k])));
            const __m256d offset = _mm256_sub_pd(x, _mm256_set1_pd(centre[k]));
            _mm256_store_pd(t.gap[k], _mm256_mul_pd(gap, gap));
            _mm256_store_pd(t.height[k], _mm256_mul_pd(offset, _mm256_set1_pd(normal[k])));
            _mm256_store_pd(t.square[k], _mm256_mul_pd(offset, offset));
        }
        t.thickness = thickness;
        t.radius = radius;
        return t;
    }

    MESH2SDF_AVX2_INLINE static unsigned lower(const double *d2, double *best)
    {
        const __m256d d = _mm256_loadu_pd(d2), b = _mm256_loadu_pd(best);
        const unsigned mask = unsigned(_mm256_movemask_pd(_mm256_cmp_pd(d, b, _CMP_LT_OQ)));
        if (mask)
            _mm256_storeu_pd(best, _mm256_min_pd(d, b));
        return mask;
    }

    MESH2SDF_AVX2_INLINE static unsigned groupReaches(const RowTerms &n, RowRounding r, int i, int j,
                                                      const double *best)
    {
        const __m256d gap = _mm256_add_pd(_mm256_set1_pd(n.gap[0][i] + n.gap[1][j]), _mm256_load_pd(n.gap[2]));
        const __m256d a = _mm256_add_pd(_mm256_set1_pd(n.height[0][i] + n.height[1][j]), _mm256_load_pd(n.height[2]));
        const __m256d offset2 =
            _mm256_add_pd(_mm256_set1_pd(n.square[0][i] + n.square[1][j]), _mm256_load_pd(n.square[2]));
        const __m256d cancel = _mm256_mul_pd(_mm256_set1_pd(r.cancel), offset2);
        const __m256d lateral2 = _mm256_sub_pd(_mm256_fnmadd_pd(a, a, offset2), cancel);
        const __m256d zero = _mm256_setzero_pd(), radius = _mm256_set1_pd(n.radius);
        const __m256d absA = _mm256_andnot_pd(_mm256_set1_pd(-0.0), a);
        const __m256d across = _mm256_max_pd(_mm256_sub_pd(absA, _mm256_set1_pd(n.thickness)), zero);
        const __m256d along =
            _mm256_sub_pd(_mm256_sqrt_pd(_mm256_max_pd(lateral2, _mm256_mul_pd(radius, radius))), radius);
        const __m256d disc = _mm256_sub_pd(_mm256_fmadd_pd(across, across, _mm256_mul_pd(along, along)), cancel);
        const __m256d bound = _mm256_mul_pd(_mm256_max_pd(gap, disc), _mm256_set1_pd(r.shrink));
        return unsigned(_mm256_movemask_pd(_mm256_cmp_pd(bound, _mm256_loadu_pd(best), _CMP_LT_OQ)));
    }

    MESH2SDF_AVX2_INLINE static void distances(const PreparedTriangle &t, double x, double y, const double *z,
                                               double *d2)
    {
        const __m256d zs = _mm256_loadu_pd(z), zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
        __m256d edges = _mm256_set1_pd(INFINITY), side = _mm256_set1_pd(INFINITY), height = zero;
        for (int k = 0; k < 3; ++k) {
            const double *e = t.edge[k], *m = t.inward[k];
            const double wx = x - t.corner[k][0], wy = y - t.corner[k][1];
            const __m256d wz = _mm256_sub_pd(zs, _mm256_set1_pd(t.corner[k][2]));
            const __m256d along = _mm256_fmadd_pd(wz, _mm256_set1_pd(e[2]), _mm256_set1_pd(wx * e[0] + wy * e[1]));
            const __m256d s =
                _mm256_min_pd(_mm256_max_pd(_mm256_mul_pd(along, _mm256_set1_pd(t.inverse[k])), zero), one);
            const __m256d rx = _mm256_fnmadd_pd(s, _mm256_set1_pd(e[0]), _mm256_set1_pd(wx));
            const __m256d ry = _mm256_fnmadd_pd(s, _mm256_set1_pd(e[1]), _mm256_set1_pd(wy));
            const __m256d rz = _mm256_fnmadd_pd(s, _mm256_set1_pd(e[2]), wz);
            const __m256d r2 = _mm256_fmadd_pd(rz, rz, _mm256_fmadd_pd(ry, ry, _mm256_mul_pd(rx, rx)));
            edges = _mm256_min_pd(edges, r2);
            side =
                _mm256_min_pd(side, _mm256_fmadd_pd(wz, _mm256_set1_pd(m[2]), _mm256_set1_pd(wx * m[0] + wy * m[1])));
            if (k == 0)
                height = _mm256_fmadd_pd(wz, _mm256_set1_pd(t.normal[2]),
                                         _mm256_set1_pd(wx * t.normal[0] + wy * t.normal[1]));
        }
        const __m256d inside = _mm256_cmp_pd(side, zero, _CMP_GT_OQ);
        _mm256_storeu_pd(d2, _mm256_blendv_pd(edges, _mm256_mul_pd(height, height), inside));
    }

    MESH2SDF_AVX2_INLINE static void groupDistances(const PreparedTriangle &t, double x, const double *y,
                                                    const double *z, double *d2)
    {
        distances(t, x, y[0], z, d2);
    }
    MESH2SDF_AVX2_INLINE static unsigned lowerGroup(const double *d2, double *best) { return lower(d2, best); }
};
#undef MESH2SDF_AVX2_INLINE

/// Whether this processor runs Avx512Rows (AVX-512 F besides AVX2 and FMA).
inline bool rowsVectorizable512() { return rowsVectorizable() && __builtin_cpu_supports("avx512f"); }

#define MESH2SDF_AVX512_INLINE __attribute__((target("avx512f,avx2,fma"))) inline
/// Avx2Rows with its triangle distances two rows at a time: rows (x, y[0],
/// z[0..3]) and (x, y[1], z[0..3]) in the eight lanes of one AVX-512
/// vector, lane by lane the same operations as Avx2Rows::distances. Where
/// the processor has full-width AVX-512 units, that is twice the lanes per
/// instruction for the search's costliest step.
struct Avx512Rows : Avx2Rows {
    static constexpr int kRows = 2;

    /// A vector whose low four lanes are a and high four are b.
    MESH2SDF_AVX512_INLINE static __m512d halves(double a, double b)
    {
        return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_set1_pd(a)), _mm256_set1_pd(b), 1);
    }

    MESH2SDF_AVX512_INLINE static void groupDistances(const PreparedTriangle &t, double x, const double *y,
                                                      const double *z, double *d2)
    {
        const __m512d zs = _mm512_broadcast_f64x4(_mm256_loadu_pd(z)), zero = _mm512_setzero_pd();
        const __m512d one = _mm512_set1_pd(1.0);
        __m512d edges = _mm512_set1_pd(INFINITY), side = _mm512_set1_pd(INFINITY), height = zero;
        for (int k = 0; k < 3; ++k) {
            const double *e = t.edge[k], *m = t.inward[k];
            const double wx = x - t.corner[k][0], wy0 = y[0] - t.corner[k][1], wy1 = y[1] - t.corner[k][1];
            const __m512d wz = _mm512_sub_pd(zs, _mm512_set1_pd(t.corner[k][2]));
            const __m512d along =
                _mm512_fmadd_pd(wz, _mm512_set1_pd(e[2]), halves(wx * e[0] + wy0 * e[1], wx * e[0] + wy1 * e[1]));
            const __m512d s =
                _mm512_min_pd(_mm512_max_pd(_mm512_mul_pd(along, _mm512_set1_pd(t.inverse[k])), zero), one);
            const __m512d rx = _mm512_fnmadd_pd(s, _mm512_set1_pd(e[0]), _mm512_set1_pd(wx));
            const __m512d ry = _mm512_fnmadd_pd(s, _mm512_set1_pd(e[1]), halves(wy0, wy1));
            const __m512d rz = _mm512_fnmadd_pd(s, _mm512_set1_pd(e[2]), wz);
            const __m512d r2 = _mm512_fmadd_pd(rz, rz, _mm512_fmadd_pd(ry, ry, _mm512_mul_pd(rx, rx)));
            edges = _mm512_min_pd(edges, r2);
            side = _mm512_min_pd(side, _mm512_fmadd_pd(wz, _mm512_set1_pd(m[2]),
                                                       halves(wx * m[0] + wy0 * m[1], wx * m[0] + wy1 * m[1])));
            if (k == 0)
                height =
                    _mm512_fmadd_pd(wz, _mm512_set1_pd(t.normal[2]),
                                    halves(wx * t.normal[0] + wy0 * t.normal[1], wx * t.normal[0] + wy1 * t.normal[1]));
        }
        const __mmask8 inside = _mm512_cmp_pd_mask(side, zero, _CMP_GT_OQ);
        _mm512_storeu_pd(d2, _mm512_mask_blend_pd(inside, edges, _mm512_mul_pd(height, height)));
    }

    /// Avx2Rows::groupReaches for rows (i, j) and (i, j + 1) at once: bit 4 r + l
    /// for centre (i, j + r, l).
    MESH2SDF_AVX512_INLINE static unsigned groupReaches(const RowTerms &n, RowRounding r, int i, int j,
                                                        const double *best)
    {
        const __m512d gap = _mm512_add_pd(halves(n.gap[0][i] + n.gap[1][j], n.gap[0][i] + n.gap[1][j + 1]),
                                          _mm512_broadcast_f64x4(_mm256_load_pd(n.gap[2])));
        const __m512d a = _mm512_add_pd(halves(n.height[0][i] + n.height[1][j], n.height[0][i] + n.height[1][j + 1]),
                                        _mm512_broadcast_f64x4(_mm256_load_pd(n.height[2])));
        const __m512d offset2 =
            _mm512_add_pd(halves(n.square[0][i] + n.square[1][j], n.square[0][i] + n.square[1][j + 1]),
                          _mm512_broadcast_f64x4(_mm256_load_pd(n.square[2])));
        const __m512d cancel = _mm512_mul_pd(_mm512_set1_pd(r.cancel), offset2);
        const __m512d lateral2 = _mm512_sub_pd(_mm512_fnmadd_pd(a, a, offset2), cancel);
        const __m512d zero = _mm512_setzero_pd(), radius = _mm512_set1_pd(n.radius);
        const __m512d absA = _mm512_abs_pd(a);
        const __m512d across = _mm512_max_pd(_mm512_sub_pd(absA, _mm512_set1_pd(n.thickness)), zero);
        const __m512d along =
            _mm512_sub_pd(_mm512_sqrt_pd(_mm512_max_pd(lateral2, _mm512_mul_pd(radius, radius))), radius);
        const __m512d disc = _mm512_sub_pd(_mm512_fmadd_pd(across, across, _mm512_mul_pd(along, along)), cancel);
        const __m512d bound = _mm512_mul_pd(_mm512_max_pd(gap, disc), _mm512_set1_pd(r.shrink));
        return _mm512_cmp_pd_mask(bound, _mm512_loadu_pd(best), _CMP_LT_OQ);
    }

    /// best[l] = min(best[l], d2[l]) for eight lanes; bit l set where d2[l]
    /// was smaller.
    MESH2SDF_AVX512_INLINE static unsigned lowerGroup(const double *d2, double *best)
    {
        const __m512d d = _mm512_loadu_pd(d2), b = _mm512_loadu_pd(best);
        const unsigned mask = _mm512_cmp_pd_mask(d, b, _CMP_LT_OQ);
        if (mask)
            _mm512_storeu_pd(best, _mm512_min_pd(d, b));
        return mask;
    }
};
#undef MESH2SDF_AVX512_INLINE
#endif

} // namespace meshsdf

#endif
