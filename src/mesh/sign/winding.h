// sdftrace — the generalized winding number of a triangle soup (Jacobson et
// al. 2013), evaluated hierarchically as in Barill et al. 2018, "Fast Winding
// Numbers for Soups and Clouds": a bounding volume hierarchy over the
// triangles, four children to a node, a far-field expansion per child (the
// dipole and the next two Taylor terms of its triangles' solid angles)
// where the child is far enough from the query point, and the exact solid
// angle (Van Oosterom–Strackee) of the triangles of leaves too near.
// winding.cpp proves a bound on each expansion's error, which the exact
// evaluation sums. No OpenVDB here: this file compiles fast and is tested
// on its own.
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

/// A winding number with a proven bound on its error.
struct WindingValue {
    double w;     // the winding number
    double bound; // |w - exact| <= bound, the exact sum over every triangle
};

/// How exactly a winding number is evaluated (sdftrace/mesh.h's
/// sdft_mesh_accuracy). The bounds are measured against brute force on
/// the test meshes (tests/test_mesh_winding.cpp), open and closed.
enum class WindingAccuracy {
    Fast, // within 5e-3 of the exact sum
    Exact // within 1e-5, and on the side of 1/2 that the exact sum is (proven)
};

/// A BVH over a triangle soup that answers winding-number queries. Holds its
/// own copy of the triangles (reordered); the inputs may be freed afterwards.
/// Built in parallel (TBB); the same tree for any thread count.
class FastWinding
{
  public:
    /// points: xyz per vertex; tris: three vertex indices per triangle, all
    /// valid. simd: four children at a time with AVX2 where the processor
    /// has it (the same answers to the bit), and the leaves' solid angles
    /// four at a time (solid_angles.h).
    FastWinding(const std::vector<std::array<float, 3>> &points, const std::vector<std::array<uint32_t, 3>> &tris,
                bool simd = true);

    /// Winding number at q: ~1 inside a closed outward-facing surface, ~0
    /// outside, fractional near holes. Within 5e-3 of the exact sum.
    /// Thread-safe (read-only).
    double operator()(const Vec3 &q) const;

    /// Winding number at q within 1e-5 of the exact sum, with a proven
    /// bound on its error (winding.cpp) that keeps it on the exact sum's
    /// side of 1/2: where the bound does not, the expansions whose bounds
    /// are largest are replaced by their children's, down to exact solid
    /// angles, until it does (a point exactly at 1/2 costs a brute-force
    /// sum). Thread-safe.
    WindingValue exact(const Vec3 &q) const;

    /// operator() or exact(q).w.
    double operator()(const Vec3 &q, WindingAccuracy accuracy) const
    {
        return accuracy == WindingAccuracy::Exact ? exact(q).w : (*this)(q);
    }

    /// The error margins that side() reports (winding.cpp measures them).
    static constexpr double kSideMargin = 0.1, kFastMargin = 0.01;

    /// Which side of 1/2 the winding number at q is on, at less cost than
    /// its value. Fast: a coarser pass (within kSideMargin) where that is
    /// clear of 1/2 by more than its margin, else operator() (within
    /// kFastMargin); w > 1/2 as operator() has it wherever the margins
    /// hold. Exact: the coarser pass's expansions with their proven bounds,
    /// the largest opened as in exact(q) until they keep w on one side of
    /// 1/2 (not within 1e-5: only the side is proven); w > 1/2 exactly
    /// where the exact sum is, wherever |w - 1/2| > bound. Returns the
    /// evaluation and its margin. Thread-safe.
    WindingValue side(const Vec3 &q, WindingAccuracy accuracy = WindingAccuracy::Fast) const;

    /// Exact sum over every triangle, for checks (O(triangles) per query).
    double bruteForce(const Vec3 &q) const;

    /// Unsigned distance from q to the nearest triangle (exact, through the
    /// same hierarchy's bounding boxes). `bound`, if known, is a distance no
    /// smaller than the answer (it prunes the search); it is returned when no
    /// triangle is nearer.
    /// `nearest`, if given, receives the nearest triangle's index in the
    /// input (unchanged when none is nearer than `bound`).
    double distance(const Vec3 &q, double bound = INFINITY, uint32_t *nearest = nullptr) const;

    size_t triangleCount() const { return mTris.size() / 9; }

  private:
    /// A node's four children, structure of arrays, so that one AVX2
    /// instruction tests or expands all four (winding.cpp).
    static constexpr int kTerms = 23; // coefficients of an expansion (winding.cpp)
    struct Node4 {
        double centre[3][4]; // area-weighted centroid of each child's triangles
        double radius2[4];   // radius^2 (infinite: no child)
        double radius[4];    // every vertex of the child lies within it of its centre
        double area[4];      // of the child's triangles
        double terms[kTerms][4];
        uint32_t child[4];        // an inner child's Node4, a leaf's Leaf
        uint32_t leaves;          // bit l: child l is a leaf
        uint32_t inner;           // bit l: child l is an inner node (neither: no child)
        float lo[3][4], hi[3][4]; // each child's bounds
    };
    struct Leaf {
        uint32_t first, count; // its triangles in BVH order
        uint32_t groups;       // their offset in mLeafGroups
    };

    double fastAt(const Vec3 &q, double beta) const;
    template <class Lanes> double fast(const Vec3 &q, double beta2) const;
    WindingValue boundedAt(const Vec3 &q, double ratio, double term) const;
    template <class Lanes> WindingValue bounded(const Vec3 &q, double ratio, double term) const;
    double fastAvx2(const Vec3 &q, double beta2) const;
    WindingValue boundedAvx2(const Vec3 &q, double ratio, double term) const;
    double leafExact(uint32_t leaf, const Vec3 &q) const;

    std::vector<double> mTris;       // 9 doubles per triangle, in BVH order
    std::vector<double> mLeafGroups; // each leaf's triangles, four to a group (solid_angles.h)
    std::vector<uint32_t> mOrder;    // BVH order -> input index
    std::vector<Node4> mNodes;       // the root first
    std::vector<Leaf> mLeaves;
    bool mVectorized;
};

} // namespace meshsdf

#endif
