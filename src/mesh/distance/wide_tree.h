// sdftrace — exact distances from arbitrary points to a triangle mesh: a
// bounding volume hierarchy eight children wide, whose children's boxes a
// point (or a packet of nearby points) tests eight at a time, as Embree's
// point queries do, and where a child is a flat patch askew to the axes,
// its disc (disc.h) too; over triangles stored four to a leaf for one
// vector evaluation. Built in parallel. Used by the point queries and the
// training samples (samples/query.h); the dense grids keep their own
// voxel-packet search (nearest_triangle.h). No OpenVDB here.
#ifndef SDFT_MESH_DISTANCE_WIDE_TREE_H
#define SDFT_MESH_DISTANCE_WIDE_TREE_H

#include "geometry/triangle_mesh.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace meshsdf
{

class WideTree
{
  public:
    /// Children per node, and triangles per leaf.
    static constexpr int kWidth = 8;
    static constexpr int kLeafSize = 4;
    /// Points per packet (nearestPacket).
    static constexpr int kPacketSize = 8;
    static constexpr uint32_t kNone = ~uint32_t(0);

    /// Copies the mesh's triangles (reordered); the mesh may be freed after.
    /// `simd`: test boxes and triangles with AVX2 where the processor has
    /// it; the scalar code computes the same operations in the same order,
    /// so both give the same answers bit for bit. Runs in parallel (TBB).
    explicit WideTree(const TriangleMesh &mesh, bool simd = true);

    /// A squared distance and the triangle it was measured to (a position
    /// in the tree's order, or kNone).
    struct Nearest {
        double d2 = INFINITY;
        uint32_t triangle = kNone;
    };

    /// The nearest triangle to p (3 finite doubles): d2 is the smallest of
    /// `start.d2` and the squared distance to every triangle, each computed
    /// by preparedDistance2 (distance/packet_rows.h): the same value
    /// whatever the start, the order or the vector width. The nearer
    /// `start` (seed()'s answer for a triangle near p), the less is
    /// searched. Thread-safe (read-only).
    Nearest nearest(const double *p, Nearest start) const;
    Nearest nearest(const double *p) const;

    /// nearest() for `count` (at most kPacketSize) points p[i] (3 doubles
    /// each, finite) at once, each starting from and returning in io[i]:
    /// the same answers, bit for bit, as one call each. The tree is walked
    /// once for the packet, so the points should be near each other (the
    /// box around them small against their distances).
    void nearestPacket(const double *const *p, int count, Nearest *io) const;

    /// nearest() for `count` points p[i] (3 finite doubles each) along a
    /// space-filling curve, so that neighbours are near each other, into
    /// out[i]: groups of kPacketSize whose box is small against their
    /// distances walk the tree together (nearestPacket), the rest one at a
    /// time, each starting from the nearest triangle of the point before.
    /// `*near`: in, a triangle near p[0] (or kNone); out, the last point's
    /// nearest, for the next run. The same answers as nearest() each.
    void nearestAlong(const double *const *p, size_t count, Nearest *out, uint32_t *near) const;

    /// The squared distance from p to one triangle (a position in the
    /// tree's order, or kNone: none), as nearest() measures it: a start.
    Nearest seed(const double *p, uint32_t triangle) const;

    /// The position in the tree's order of the mesh's triangle t.
    uint32_t position(uint32_t t) const { return mPosition[t]; }

    size_t triangleCount() const { return mPosition.size(); }

    /// A node: its children's boxes axis by axis (the exact float bounds of
    /// their triangles' corners; an absent child's is empty) and discs
    /// (disc.h), and each child's node index, or for a leaf its group.
    /// (Every row of lanes starts on 32 bytes, for the vector loads.)
    struct alignas(64) Node {
        double centre[3][kWidth], normal[3][kWidth], thickness[kWidth], radius[kWidth];
        float lo[3][kWidth], hi[3][kWidth];
        uint32_t child[kWidth];
        uint8_t valid, leaf, flat; // bit k: child k exists; is a leaf; is flat
    };
    /// A leaf's triangles, prepared as packet_rows.h's PreparedTriangle,
    /// lane by lane; lanes past the leaf's last triangle repeat its first.
    /// The corners are the mesh's floats, and the edges are not stored:
    /// both are computed as prepareTriangle computes them.
    struct alignas(32) Group {
        double normal[3][kLeafSize], inverse[3][kLeafSize], inward[3][3][kLeafSize];
        float corner[3][3][kLeafSize];
    };

  private:
    struct Box;
    struct Builder;
    struct Seeker;
    template <class Lanes> Nearest search(const double *p, Nearest best) const;
    template <class Lanes> void searchPacket(const double *const *p, int count, Nearest *io) const;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    Nearest searchAvx2(const double *p, Nearest best) const;
    void searchPacketAvx2(const double *const *p, int count, Nearest *io) const;
#endif
    double slack(const double *p) const;

    std::vector<Node> mNodes;                   // the root first, then depth first
    std::vector<Group> mGroups;                 // leaf g: triangles [4 g, 4 g + 4) of the order
    std::vector<uint32_t> mPosition;            // the mesh's triangle -> its position
    double mCentre[3] = {0, 0, 0}, mRadius = 0; // a sphere around every corner
    bool mVectorized;
};

static_assert(offsetof(WideTree::Node, lo) % 32 == 0 && offsetof(WideTree::Group, corner) % 16 == 0,
              "the vector loads' alignment");

inline WideTree::Nearest WideTree::nearest(const double *p) const { return nearest(p, Nearest{}); }

} // namespace meshsdf

#endif
