// mesh2sdf — the sign of band voxels by the generalized winding number,
// evaluated at as few voxels as a proven bound on its change allows. Works
// on the band's 8^3 blocks (band.h); no OpenVDB here.
#ifndef MESH2SDF_WINDING_SIGN_H
#define MESH2SDF_WINDING_SIGN_H

#include "mesh.h"
#include "winding.h"

#include <array>
#include <vector>

namespace mesh2sdf
{

class WindingSign
{
  public:
    /// `winding` is the mesh's winding tree and must outlive this object;
    /// voxel (i, j, k) has its centre at origin + (i, j, k) * voxelSize.
    WindingSign(const TriangleMesh &mesh, const FastWinding &winding, const std::array<double, 3> &origin,
                double voxelSize);

    /// Negates the band voxels (finite entries, exact unsigned distances) of
    /// the block at `origin` (band.h's layout) where the winding number
    /// exceeds 1/2. Thread-safe (read-only).
    void signBlock(const std::array<int, 3> &origin, float *distance) const;

    /// Edges whose triangles' boundaries do not cancel (see winding_sign.cpp).
    struct OpenEdge {
        double a[3], b[3];   // endpoints, world units
        double lo[3], hi[3]; // bounding box
        double length;
        double current; // |k - l|: net number of triangle boundaries along it
    };

  private:
    const FastWinding &mWinding;
    std::array<double, 3> mOrigin;
    double mVoxelSize;
    std::vector<OpenEdge> mEdges;
};

} // namespace mesh2sdf

#endif
