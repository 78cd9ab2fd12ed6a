// sdftrace — the signed distance at arbitrary points, the converter's own
// at every point: the exact distance to the nearest triangle (WideTree)
// and the sign of the fast winding number (> 0.5 inside) of the oriented
// mesh, never read from a grid. Used by sdft_mesh_signed_distance and by
// the training samples (samples.h). Where only the sign is wanted it comes
// from FastWinding::side, which agrees with the winding number's value at
// less cost.
#ifndef SDFT_MESH_SAMPLES_QUERY_H
#define SDFT_MESH_SAMPLES_QUERY_H

#include "distance/wide_tree.h"
#include "geometry/triangle_mesh.h"
#include "geometry/unit_sphere.h"
#include "sign/winding.h"

#include <cmath>
#include <memory>
#include <vector>

namespace meshsdf
{

class PointQuery
{
  public:
    /// Both hierarchies over `mesh` (oriented already), built side by side;
    /// `simd` as WideTree's and FastWinding's; `accuracy` the winding
    /// numbers'.
    PointQuery(const TriangleMesh &mesh, bool simd, WindingAccuracy accuracy = WindingAccuracy::Fast);

    /// What evaluate() computes: the distance (with the winding number's
    /// sign), the winding number as a value, or both.
    struct Wanted {
        bool distance = true, winding = true;
    };

    /// At the points xyz + 3 i for i = order[j], j in [first, last), in an
    /// order along a space-filling curve (mortonOrder), calls emit(i, d, w):
    /// if wanted.distance, the signed distance d (negative where the
    /// winding number exceeds 0.5), else NaN; w the winding number, or,
    /// unless wanted.winding, a number on its side of 0.5 (side()); both
    /// NaN at a point with a coordinate that is not finite. The distances
    /// are searched along the curve (WideTree::nearestAlong), but each
    /// point's values are the same in any order and any grouping.
    template <class Emit>
    void evaluate(const double *xyz, const size_t *order, size_t first, size_t last, Wanted wanted, Emit emit) const
    {
        constexpr size_t kBlock = 256;
        const double *p[kBlock];
        size_t index[kBlock];
        WideTree::Nearest nearest[kBlock];
        uint32_t near = WideTree::kNone;
        for (size_t j = first; j < last;) {
            size_t n = 0;
            for (; j < last && n < kBlock; ++j) {
                const size_t i = order[j];
                const double *q = xyz + 3 * i;
                if (std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2])) {
                    p[n] = q;
                    index[n++] = i;
                } else {
                    emit(i, double(NAN), double(NAN));
                }
            }
            if (wanted.distance)
                mDistance->nearestAlong(p, n, nearest, &near);
            for (size_t k = 0; k < n; ++k) {
                const double w = wanted.winding ? winding(p[k]) : side(p[k]);
                const double d = wanted.distance ? std::sqrt(nearest[k].d2) : double(NAN);
                emit(index[k], w > 0.5 ? -d : d, w);
            }
        }
    }

    /// A number on the winding number's side of 0.5 at p, where only the
    /// side is wanted (a sign): FastWinding::side's.
    double side(const double *p) const { return mWinding->side({p[0], p[1], p[2]}, mAccuracy).w; }

    /// The winding number at p alone (3 doubles), without the distance.
    double winding(const double *p) const { return (*mWinding)({p[0], p[1], p[2]}, mAccuracy); }

  private:
    std::unique_ptr<WideTree> mDistance;
    std::unique_ptr<FastWinding> mWinding;
    WindingAccuracy mAccuracy;
};

/// The indices of the points `xyz` (3 doubles each) in Morton order in the
/// cube centre ± radius of `cube` (points outside it on its faces, NaN
/// ones at its low corner):
/// neighbours in this order are near in space, so that evaluating them in
/// it finds the hierarchies' nodes in cache. Runs in parallel.
std::vector<size_t> mortonOrder(const std::vector<double> &xyz, const MeshSphere &cube);

} // namespace meshsdf

#endif
