// sdftrace — the sign of every voxel by the generalized winding number,
// evaluated at as few points as a proven bound on its change allows: voxel
// by voxel in the band's 8^3 blocks (distance/band.h), and whole cubes of voxels off
// the band. No OpenVDB here.
#ifndef SDFT_MESH_SIGN_WINDING_SIGN_H
#define SDFT_MESH_SIGN_WINDING_SIGN_H

#include "geometry/triangle_mesh.h"
#include "sign/winding.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

namespace meshsdf
{

/// Edges whose triangles' boundaries do not cancel (see winding_sign.cpp),
/// each directed along its net current.
struct OpenEdge {
    double a[3], b[3];   // endpoints, world units; the current flows a -> b
    double lo[3], hi[3]; // bounding box
    double length;
    double current; // |k - l|: net number of triangle boundaries along it
};

/// Bounds on |grad w|, the winding number's gradient, from a mesh's open
/// edges (winding_sign.cpp proves them): edge by edge up close, and for a
/// group of edges far from a region, by the group's net current and size
/// (a closed loop's field falls off as a dipole's, not as its length's).
class EdgeField
{
  public:
    explicit EdgeField(const TriangleMesh &mesh);

    const std::vector<OpenEdge> &edges() const { return mEdges; }

    /// A bound on |grad w| at every point off the mesh within `inflate` of
    /// the box [lo, hi] (world units; lo == hi for a point) that is at least
    /// `floor` from every open edge.
    double overBox(const double lo[3], const double hi[3], double inflate, double floor = 0) const;

    /// The exact field at p (grad w up to its sign: the Biot-Savart field of
    /// the open edges), in 1 / world units.
    void field(const double p[3], double B[3]) const;

    /// A bound on the second derivative of the field along any line, at
    /// every point off the mesh within `inflate` of p.
    double curvature(const double p[3], double inflate) const;

    /// overBox's bound split in two: the sum over groups and edges farther
    /// than `nearDistance` from the inflated box is returned; edges nearer
    /// go to `near`, for the caller to bound point by point.
    double farPart(const double lo[3], const double hi[3], double inflate, double nearDistance,
                   std::vector<const OpenEdge *> &near) const;

  private:
    struct Group {
        double centre[3];
        double radius;        // every edge of the group lies within it of the centre
        double chord;         // |sum of current * (b - a)|, rounded up
        double mass;          // sum of current * length
        uint32_t left, right; // children; left == right: a leaf, edge `left`
    };
    uint32_t build(std::vector<uint32_t> &order, size_t first, size_t count);
    template <typename Leaf>
    double walk(uint32_t node, const double lo[3], const double hi[3], double inflate, Leaf &&leaf) const;

    std::vector<OpenEdge> mEdges;
    std::vector<Group> mGroups;
};

class WindingSign
{
  public:
    /// `field` is the mesh's open edges (EdgeField(mesh), built apart so
    /// that it can be built beside the winding tree); `winding` is the
    /// mesh's winding tree and must outlive this object; voxel (i, j, k)
    /// has its centre at origin + (i, j, k) * voxelSize. `halfWidth` is the
    /// exact band's (distance/band.h), in voxels: every voxel off the band is at
    /// least that far from the mesh. `simd`: the near field four voxels at
    /// a time with AVX2 where the processor has it. `counted`: the box of
    /// voxels [0, counted) whose voxels off the band count in
    /// ambiguousVoxels (a grid with a distance in every voxel of its box);
    /// band voxels always count.
    WindingSign(EdgeField field, const FastWinding &winding, const std::array<double, 3> &origin, double voxelSize,
                double halfWidth, bool simd = true, const std::array<int, 3> &counted = {0, 0, 0});

    /// Signs every voxel of the block at `origin` (distance/band.h's layout) by
    /// whether the winding number exceeds 1/2 there: band voxels (finite
    /// entries, exact unsigned distances) are negated, voxels off the band
    /// (+inf) become -inf. Thread-safe (read-only).
    void signBlock(const std::array<int, 3> &origin, float *distance) const;

    /// The side of the cube of size^3 voxels from `origin`, none of which is
    /// in the band: -1 when the winding number exceeds 1/2 at all its voxels,
    /// +1 when it is below at all of them, 0 when the bound cannot tell (split
    /// the cube). Thread-safe (read-only).
    int cubeSide(const std::array<int, 3> &origin, int size) const;

    /// How many voxels signBlock and cubeSide have signed from a winding
    /// number between 1/2 - kAmbiguous and 1/2 + kAmbiguous (0.25 to 0.75):
    /// near holes, or where a patch has no clear outside. Only band voxels
    /// and those off the band in the `counted` box count: the voxels a
    /// grid stores (a narrow band's are its band's).
    uint64_t ambiguousVoxels() const { return mAmbiguous.load(); }

  private:
    // The voxels of the cube of size^3 from `origin` within mCounted's box.
    uint64_t countedOffBand(const std::array<int, 3> &origin, int size) const;

    void countAmbiguous(uint64_t voxels) const
    {
        if (voxels)
            mAmbiguous.fetch_add(voxels, std::memory_order_relaxed);
    }

    mutable std::atomic<uint64_t> mAmbiguous{0};
    const FastWinding &mWinding;
    std::array<double, 3> mOrigin;
    double mVoxelSize;
    double mOffBand; // world distance that every voxel off the band keeps from the mesh
    EdgeField mField;
    bool mVectorized;
    std::array<int, 3> mCounted;
};

} // namespace meshsdf

#endif
