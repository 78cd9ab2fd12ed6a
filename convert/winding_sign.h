// mesh2sdf — the sign of every voxel by the generalized winding number,
// evaluated at as few points as a proven bound on its change allows: voxel
// by voxel in the band's 8^3 blocks (band.h), and whole cubes of voxels off
// the band. No OpenVDB here.
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
    /// `halfWidth` is the exact band's (band.h), in voxels: every voxel off
    /// the band is at least that far from the mesh.
    WindingSign(const TriangleMesh &mesh, const FastWinding &winding, const std::array<double, 3> &origin,
                double voxelSize, double halfWidth);

    /// Signs every voxel of the block at `origin` (band.h's layout) by
    /// whether the winding number exceeds 1/2 there: band voxels (finite
    /// entries, exact unsigned distances) are negated, voxels off the band
    /// (+inf) become -inf. Thread-safe (read-only).
    void signBlock(const std::array<int, 3> &origin, float *distance) const;

    /// The side of the cube of size^3 voxels from `origin`, none of which is
    /// in the band: -1 when the winding number exceeds 1/2 at all its voxels,
    /// +1 when it is below at all of them, 0 when the bound cannot tell (split
    /// the cube). Thread-safe (read-only).
    int cubeSide(const std::array<int, 3> &origin, int size) const;

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
    double mOffBand; // world distance that every voxel off the band keeps from the mesh
    std::vector<OpenEdge> mEdges;
};

} // namespace mesh2sdf

#endif
