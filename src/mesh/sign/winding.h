// sdftrace — the generalized winding number of a triangle soup (Jacobson et
// al. 2013), evaluated hierarchically as in Barill et al. 2018, "Fast Winding
// Numbers for Soups and Clouds": a bounding volume hierarchy over the
// triangles, a far-field expansion (order 1 dipole + order 2 term) per node
// used when the query point is farther than beta * radius from the node's
// centre, and the exact solid angle (Van Oosterom–Strackee) of near triangles.
// No OpenVDB here: this file compiles fast and is tested on its own.
#ifndef SDFT_MESH_SIGN_WINDING_H
#define SDFT_MESH_SIGN_WINDING_H

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace meshsdf
{

using Vec3 = std::array<double, 3>;

/// Solid angle of triangle (a, b, c) seen from q, divided by 4π (so a closed,
/// outward-oriented surface sums to 1 at an inside point). Van Oosterom and
/// Strackee (1983), "The solid angle of a plane triangle".
double triangleWinding(const Vec3 &a, const Vec3 &b, const Vec3 &c, const Vec3 &q);

/// A BVH over a triangle soup that answers winding-number queries. Holds its
/// own copy of the triangles (reordered); the inputs may be freed afterwards.
class FastWinding
{
  public:
    /// points: xyz per vertex; tris: three vertex indices per triangle, all
    /// valid. beta: accuracy (Barill et al. use 2; larger is more exact).
    /// simd: the exact near field's solid angles four at a time with AVX2
    /// where the processor has it (solid_angles.h).
    FastWinding(const std::vector<std::array<float, 3>> &points, const std::vector<std::array<uint32_t, 3>> &tris,
                double beta = 2.0, bool simd = true);

    /// Winding number at q: ~1 inside a closed outward-facing surface, ~0
    /// outside, fractional near holes. Thread-safe (read-only).
    double operator()(const Vec3 &q) const;

    /// Exact sum over every triangle, for checks (O(triangles) per query).
    double bruteForce(const Vec3 &q) const;

    /// Unsigned distance from q to the nearest triangle (exact, through the
    /// same hierarchy's bounding boxes). `bound`, if known, is a distance no
    /// smaller than the answer (it prunes the search); it is returned when no
    /// triangle is nearer.
    /// `nearest`, if given, receives the nearest triangle's index in the
    /// input (unchanged when none is nearer than `bound`).
    double distance(const Vec3 &q, double bound = INFINITY, uint32_t *nearest = nullptr) const;

    size_t triangleCount() const { return mTris.size() / 3; }

  private:
    struct Node {
        float lo[3], hi[3];    // bounds of the node's triangles
        double centre[3];      // area-weighted centroid of the triangles
        double radius2;        // (beta * radius)^2 for the far-field test
        double dipole[3];      // sum of area vectors (order 1)
        double second[9];      // sum of area vector (x) centroid offset (order 2)
        uint32_t first, count; // leaf: triangle range; inner: count == 0
        uint32_t left, right;  // inner: children
        uint32_t groups;       // leaf: its triangles' offset in mLeafGroups
    };
    uint32_t build(uint32_t first, uint32_t count, std::vector<uint32_t> &order, const std::vector<Vec3> &centroids);
    void summarize(Node &n) const;

    std::vector<double> mTris;       // 9 doubles per triangle, in BVH order
    std::vector<double> mLeafGroups; // each leaf's triangles, four to a group (solid_angles.h)
    std::vector<uint32_t> mOrder;    // BVH order -> input index
    std::vector<Node> mNodes;
    double mBeta2;
    bool mVectorized;
};

} // namespace meshsdf

#endif
