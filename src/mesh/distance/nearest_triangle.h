// sdftrace — the exact distance from voxel centres to a triangle mesh, for
// dense grids: a bounding volume hierarchy whose nodes bound their triangles
// twice, by a box and by a disc around their mean plane, searched once for a
// packet of 4^3 neighbouring centres, each starting from a triangle the
// caller already knows is near (a neighbouring voxel's nearest). No OpenVDB
// here.
#ifndef SDFT_MESH_DISTANCE_NEAREST_TRIANGLE_H
#define SDFT_MESH_DISTANCE_NEAREST_TRIANGLE_H

#include "distance/packet_rows.h"
#include "geometry/triangle_mesh.h"

#include <cstdint>
#include <vector>

namespace meshsdf
{

class NearestTriangle
{
  public:
    /// Copies the mesh's triangles (reordered); the mesh may be freed after.
    /// `vectorized`: search four voxels at a time with AVX2 where the
    /// processor has it, and `wide`: a triangle's distances to eight voxels
    /// at a time with AVX-512 where it has that (false: lane by lane; the
    /// answers agree to rounding).
    explicit NearestTriangle(const TriangleMesh &mesh, bool vectorized = true, bool wide = true);

    static constexpr uint32_t kNone = ~uint32_t(0);

    /// A packet: the kPacketDim^3 voxel centres corner + (i, j, k) * spacing,
    /// numbered (i * kPacketDim + j) * kPacketDim + k.
    static constexpr int kPacketDim = 4;
    static constexpr int kPacketSize = kPacketDim * kPacketDim * kPacketDim;

    /// Squared distances in world units from each centre of the packet at
    /// `corner` (3 doubles) to the mesh, in one search for the whole packet.
    /// `best` (kPacketSize): on entry an upper bound per centre (INFINITY if
    /// none; 0 for a centre the caller does not want); on return the smaller
    /// of that and the exact squared distance. `nearest` (kPacketSize): on
    /// entry a triangle to start each centre from (a neighbour's nearest) or
    /// kNone; on return the nearest triangle where one lowered `best`, else
    /// kNone. Thread-safe (read-only).
    void packetDistance2(const double *corner, double spacing, double *best, uint32_t *nearest) const;

  private:
    struct Node {
        float lo[3], hi[3];           // box of the triangles
        double centre[3], normal[3];  // disc: area-weighted centre, unit mean normal
        double thickness, radius;     // vertices lie within these of centre along / across normal
        uint32_t first, count, right; // leaf: triangles [first, first + count); inner: count 0,
                                      // children at this node + 1 and right
    };
    uint32_t build(uint32_t first, uint32_t count, std::vector<uint32_t> &order,
                   const std::vector<std::array<double, 3>> &centroids, const TriangleMesh &mesh);
    double packetLowerBound2(const Node &node, const double *lo, const double *hi, const double *centre, double radius,
                             double worst) const;
    template <class Rows> void search(const double *corner, double spacing, double *best, uint32_t *nearest) const;
#ifdef SDFT_MESH_ROWS_AVX2
    void searchAvx2(const double *corner, double spacing, double *best, uint32_t *nearest) const;
    void searchAvx512(const double *corner, double spacing, double *best, uint32_t *nearest) const;
#endif

    std::vector<PreparedTriangle> mTriangles; // in hierarchy order (packet_rows.h)
    std::vector<Node> mNodes;
    bool mVectorized, mVectorized512;
};

} // namespace meshsdf

#endif
