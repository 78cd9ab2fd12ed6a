// mesh2sdf — the signed distance at arbitrary points, the converter's own
// at every point: the exact distance to the nearest triangle
// (NearestTriangle::pointDistance2) and the sign of the fast winding number
// (> 0.5 inside) of the oriented mesh, never read from a grid. Used by
// --query (its points from a .npy file) and by --samples (samples.h).
#ifndef MESH2SDF_QUERY_H
#define MESH2SDF_QUERY_H

#include "mesh.h"
#include "nearest_triangle.h"
#include "options.h"
#include "output.h"
#include "text.h"
#include "unit_sphere.h"
#include "winding.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace mesh2sdf
{

class PointQuery
{
  public:
    /// Both hierarchies over `mesh` (oriented already), built side by side;
    /// `simd`, `wide` as NearestTriangle's and FastWinding's.
    PointQuery(const TriangleMesh &mesh, bool simd, bool wide);

    /// The signed distance at p (3 doubles): negative where the winding
    /// number, stored in *winding, exceeds 0.5. `bound2`: a squared
    /// distance from p to some point of the mesh, or INFINITY.
    double signedDistance(const double *p, double bound2, double *winding) const
    {
        const double w = (*mWinding)({p[0], p[1], p[2]});
        const double d = std::sqrt(mNearest->pointDistance2(p, bound2));
        *winding = w;
        return w > 0.5 ? -d : d;
    }

    /// The winding number at p alone (3 doubles), without the distance.
    double winding(const double *p) const { return (*mWinding)({p[0], p[1], p[2]}); }

  private:
    std::unique_ptr<NearestTriangle> mNearest;
    std::unique_ptr<FastWinding> mWinding;
};

/// The indices of the points `xyz` (3 doubles each) in Morton order in the
/// cube centre ± radius of `cube` (points outside it on its faces):
/// neighbours in this order are near in space, so that evaluating them in
/// it finds the hierarchies' nodes in cache. Runs in parallel.
std::vector<size_t> mortonOrder(const std::vector<double> &xyz, const MeshSphere &cube);

/// The mesh of --samples and --query: read, its sphere taken, mapped into
/// the unit sphere with --normalize, oriented as --orient says. `sphere` is
/// in the file's units either way; `orientSeconds` what orienting took.
bool loadPointMesh(const Options &opt, TriangleMesh &mesh, MeshSphere &sphere, double &orientSeconds,
                   std::string &error);

/// OUT.npy and OUT.json of --samples and --query: reserved before any work
/// (output.h), written and renamed into place at the end, or removed.
struct PointFiles {
    PendingFile array, sidecar;
    bool reserve(const std::string &npy, std::string &error);
    /// The float32 array of `shape` ("(n, 4)") and the sidecar: `fields`
    /// (its own lines, each ending in ",\n"), then the frame: whether the
    /// points are normalized, the sphere, how to map a point and a distance
    /// back, the sign and the source mesh. On failure, removes both.
    bool write(const std::string &shape, const std::vector<float> &values, const std::string &fields,
               const Options &opt, const MeshSphere &sphere, std::string &error);
    /// Removes both temporary files; returns false.
    bool discard();
};

/// The sidecar's "array" line: the file name of `path`.
std::string arrayField(const std::string &path);

/// mesh2sdf MESH --query POINTS.npy OUT.npy [--winding] [--normalize]:
/// reads, evaluates every point in parallel, writes OUT.npy and OUT.json
/// (each through a temporary file) and the summary line or --json object.
bool runQuery(const Options &opt, std::string &error);

} // namespace mesh2sdf

#endif
