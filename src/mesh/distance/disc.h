// sdftrace — a disc around a set of triangles: the lower bound on their
// distance that stays tight where a box's does not. Far from a nearly flat
// patch, a sphere around a point that just reaches the surface passes
// within a box's thickness of the surface over a wide cap, and every box it
// touches must be opened; the disc of a flat patch is thin, and only the
// patches under the sphere's contact are. Both searches use it: the dense
// grids' (nearest_triangle.cpp) and the points' (wide_tree.cpp).
//
// Why it is a bound. The disc is the cylinder of points within `thickness`
// of the plane through `centre` normal to `normal` and within `radius` of
// `centre` across it; it holds every corner of the triangles, and so, each
// triangle being the convex hull of its corners, all of them. For q at
// height a above that plane and lateral distance l from the centre, the
// distance from q to the cylinder is sqrt(max(|a| - thickness, 0)^2 +
// max(l - radius, 0)^2), and no triangle inside it is nearer. Computed in
// double: the lateral offset comes from |q - centre|^2 - a^2, whose terms
// carry rounding errors of a few ulps of |q - centre|^2, so every bound
// gives away kDiscCancel |q - centre|^2 for them (an error of 1e-16 there
// moves a lateral offset near zero by 1e-8 |q - centre|, far beyond a
// relative shrink), and the disc itself is grown by as much when it is
// made; the rest is covered by shrinking the result by kDiscShrink.
// No OpenVDB here.
#ifndef SDFT_MESH_DISTANCE_DISC_H
#define SDFT_MESH_DISTANCE_DISC_H

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace meshsdf
{

constexpr double kDiscCancel = 1e-14;
constexpr double kDiscShrink = 1 - 1e-12;

struct Disc {
    double centre[3] = {0, 0, 0}; // area-weighted centre of the triangles
    double normal[3] = {0, 0, 1}; // unit mean normal
    double thickness = 0;         // every corner lies within it of the plane
    double radius = 0;            // and within it of the centre across the normal
};

/// The disc around triangles first .. first + count - 1: corner(i, v) is
/// corner v of triangle i (3 floats), centroid(i) its centroid (3 doubles);
/// the centre is the box's [lo, hi] where the triangles have no area. Each
/// triangle's normal is turned to agree with the sum so far: orientation
/// does not matter here.
template <class Corner, class Centroid>
Disc discAround(uint32_t first, uint32_t count, Corner corner, Centroid centroid, const float *lo, const float *hi)
{
    Disc disc;
    double area = 0, sum[3] = {0, 0, 0}, centre[3] = {0, 0, 0};
    for (uint32_t i = first; i < first + count; ++i) {
        const auto &a = corner(i, 0), &b = corner(i, 1), &c = corner(i, 2);
        double e1[3], e2[3];
        for (int k = 0; k < 3; ++k) {
            e1[k] = double(b[k]) - a[k];
            e2[k] = double(c[k]) - a[k];
        }
        const double cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                 e1[0] * e2[1] - e1[1] * e2[0]};
        const double twice = std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
        const double turn = cross[0] * sum[0] + cross[1] * sum[1] + cross[2] * sum[2] < 0 ? -1.0 : 1.0;
        const double *mid = centroid(i);
        for (int k = 0; k < 3; ++k) {
            sum[k] += turn * cross[k];
            centre[k] += twice * mid[k];
        }
        area += twice;
    }
    const double length = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    for (int k = 0; k < 3; ++k) {
        disc.normal[k] = length > 0 ? sum[k] / length : (k == 2 ? 1.0 : 0.0);
        disc.centre[k] = area > 0 ? centre[k] / area : 0.5 * (double(lo[k]) + hi[k]);
    }
    for (uint32_t i = first; i < first + count; ++i)
        for (int v = 0; v < 3; ++v) {
            const auto &p = corner(i, v);
            double d[3], a = 0, d2 = 0;
            for (int k = 0; k < 3; ++k) {
                d[k] = double(p[k]) - disc.centre[k];
                a += d[k] * disc.normal[k];
                d2 += d[k] * d[k];
            }
            // Grown by the rounding of a and of d2 - a^2 (kDiscCancel).
            disc.thickness = std::max(disc.thickness, std::abs(a) + kDiscCancel * std::sqrt(d2));
            disc.radius = std::max(disc.radius, std::sqrt(std::max(d2 - a * a + kDiscCancel * d2, 0.0)));
        }
    return disc;
}

} // namespace meshsdf

#endif
