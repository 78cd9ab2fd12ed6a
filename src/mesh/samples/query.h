// sdftrace — the signed distance at arbitrary points, the converter's own
// at every point: the exact distance to the nearest triangle (WideTree)
// and the sign of the fast winding number (> 0.5 inside) of the oriented
// mesh, never read from a grid. Used by sdft_mesh_signed_distance and by
// the training samples (samples.h).
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
    /// `simd` as WideTree's and FastWinding's.
    PointQuery(const TriangleMesh &mesh, bool simd);

    /// The signed distance at p (3 finite doubles): negative where the
    /// winding number, stored in *winding, exceeds 0.5. `*near`: a triangle
    /// near p (the nearest of the point evaluated just before, in Morton
    /// order) or WideTree::kNone; on return p's nearest, for the next point.
    /// It only shortens the search: the answer is the same without it.
    double signedDistance(const double *p, uint32_t *near, double *winding) const
    {
        const double w = (*mWinding)({p[0], p[1], p[2]});
        const WideTree::Nearest nearest = mDistance->nearest(p, mDistance->seed(p, *near));
        *near = nearest.triangle;
        *winding = w;
        const double d = std::sqrt(nearest.d2);
        return w > 0.5 ? -d : d;
    }

    /// The winding number at p alone (3 doubles), without the distance.
    double winding(const double *p) const { return (*mWinding)({p[0], p[1], p[2]}); }

  private:
    std::unique_ptr<WideTree> mDistance;
    std::unique_ptr<FastWinding> mWinding;
};

/// The indices of the points `xyz` (3 doubles each) in Morton order in the
/// cube centre ± radius of `cube` (points outside it on its faces, NaN
/// ones at its low corner):
/// neighbours in this order are near in space, so that evaluating them in
/// it finds the hierarchies' nodes in cache. Runs in parallel.
std::vector<size_t> mortonOrder(const std::vector<double> &xyz, const MeshSphere &cube);

} // namespace meshsdf

#endif
