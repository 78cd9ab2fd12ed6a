// sdftrace — the signed distance at arbitrary points, the converter's own
// at every point: the exact distance to the nearest triangle
// (NearestTriangle::pointDistance2) and the sign of the fast winding number
// (> 0.5 inside) of the oriented mesh, never read from a grid. Used by
// sdft_mesh_signed_distance and by the training samples (samples.h).
// Where only the sign is wanted it comes from FastWinding::side, which
// agrees with the winding number's value at less cost.
#ifndef SDFT_MESH_SAMPLES_QUERY_H
#define SDFT_MESH_SAMPLES_QUERY_H

#include "distance/nearest_triangle.h"
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
    /// `simd`, `wide` as NearestTriangle's and FastWinding's; `accuracy`
    /// the winding numbers'.
    PointQuery(const TriangleMesh &mesh, bool simd, bool wide, WindingAccuracy accuracy = WindingAccuracy::Fast);

    /// The signed distance at p (3 doubles): negative where the winding
    /// number (its side, FastWinding::side) exceeds 0.5. `bound2`: a
    /// squared distance from p to some point of the mesh, or INFINITY.
    double signedDistance(const double *p, double bound2) const
    {
        const double w = mWinding->side({p[0], p[1], p[2]}, mAccuracy).w;
        const double d = std::sqrt(mNearest->pointDistance2(p, bound2));
        return w > 0.5 ? -d : d;
    }

    /// The same, signed by the winding number's value, stored in *winding.
    double signedDistance(const double *p, double bound2, double *winding) const
    {
        const double w = this->winding(p);
        const double d = std::sqrt(mNearest->pointDistance2(p, bound2));
        *winding = w;
        return w > 0.5 ? -d : d;
    }

    /// The winding number at p alone (3 doubles), without the distance.
    double winding(const double *p) const { return (*mWinding)({p[0], p[1], p[2]}, mAccuracy); }

  private:
    std::unique_ptr<NearestTriangle> mNearest;
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
