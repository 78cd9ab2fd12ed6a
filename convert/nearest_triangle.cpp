// mesh2sdf — exact nearest-triangle queries for packets of voxel centres
// (see nearest_triangle.h).
//
// Why every centre's answer is exact. The search keeps, per centre v, best(v):
// the smallest squared distance from v to a triangle evaluated so far (or
// the caller's bound). It skips a set of triangles only on a lower bound on
// their distance from v that is at least best(v), so no skipped triangle is
// nearer than v's final best, and the answer, a minimum of triangleDistance2
// over evaluated triangles, is the minimum over all of them. The skips:
//  - a node, for the whole packet, when its lower bound over the packet's
//    box is at least `worst`, the largest best(v): every v lies in that box,
//    so each of the node's triangles is at least worst >= best(v) from v;
//  - a node, for the whole packet, when for every centre v its own lower
//    bound is at least best(v) (CentreBounds::anyReaches);
//  - a leaf's triangles, for one centre v, when v's own lower bound on the
//    leaf is at least best(v);
//  - one triangle, for one centre v, when v's distance to the triangle's
//    plane (less the plane's slack, trianglePlane) is at least sqrt(best(v)).
// Bests only fall, so a skip stays justified to the end.
//
// The lower bounds of a node, both true because each triangle is the convex
// hull of its corners and both shapes are convex and hold every corner: the
// distance to the node's box, and the distance to its disc, the cylinder of
// points within `thickness` of the mean plane through `centre` and within
// `radius` of `centre` across it. For q at height a above that plane and
// lateral distance l from the centre, that distance is
// sqrt(max(|a| - thickness, 0)^2 + max(l - radius, 0)^2). Over a packet:
// the distance between the node's box and the packet's box, and the disc's
// distance from the packet's centre less the packet's half-diagonal (a
// distance to a convex set changes by at most the distance moved). Far from
// a nearly flat patch the box is a poor bound: a sphere around q that just
// reaches the surface passes within a box's thickness of the surface over a
// wide cap, and every box it touches must be opened; the disc of a flat
// patch is thin, and only the patches under the sphere's contact are
// opened. All are computed in double precision and shrunk by a relative
// 1e-12, far above their rounding error, except where the disc's terms
// cancel, which kCancel covers.
//
// Why packets: neighbouring centres open nearly the same nodes, so one
// descent serves kPacketSize centres; each centre then pays only its own
// bounds at the nodes the packet opens (from per-axis terms, CentreBounds)
// and the triangles no bound excludes. Each centre starts from a
// neighbour's nearest triangle, so the bests are near their answers from
// the first node on, and nearer children are searched first.
#include "nearest_triangle.h"

#include "median_split.h"
#include "triangle_distance.h"

#include <algorithm>
#include <cmath>

namespace mesh2sdf
{

namespace
{

constexpr uint32_t kLeafSize = 2;
constexpr double kShrink = 1 - 1e-12;

// The disc's terms cancel: the lateral offset comes from |q - centre|^2 -
// a^2, and a and |q - centre|^2 carry rounding errors of a few ulps of
// |q - centre| and its square. Every disc bound gives away kCancel *
// |q - centre|^2 for them (an error of 1e-16 there moves a lateral offset
// near zero by 1e-8 |q - centre|, far beyond a relative shrink), and the
// disc itself is grown by as much when it is built.
constexpr double kCancel = 1e-14;

// A triangle's plane for a cheap lower bound on its distance: unit normal
// n, offset n . a and slack, the farthest any corner lies from the plane as
// computed plus a margin far above the rounding of n . q - offset; so
// |n . q - offset| - slack never exceeds the distance from q to the
// triangle, a convex hull of its corners.
void trianglePlane(const double *t, double *plane)
{
    const double e1[3] = {t[3] - t[0], t[4] - t[1], t[5] - t[2]}, e2[3] = {t[6] - t[0], t[7] - t[1], t[8] - t[2]};
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(length > 0)) { // no plane: a bound of 0
        std::fill(plane, plane + 5, 0.0);
        plane[4] = INFINITY;
        return;
    }
    double scale = 0;
    for (int k = 0; k < 3; ++k) {
        n[k] /= length;
        scale = std::max({scale, std::abs(t[k]), std::abs(t[3 + k]), std::abs(t[6 + k])});
    }
    const double offset = n[0] * t[0] + n[1] * t[1] + n[2] * t[2];
    double slack = 0;
    for (int v = 0; v < 3; ++v)
        slack = std::max(slack, std::abs(n[0] * t[3 * v] + n[1] * t[3 * v + 1] + n[2] * t[3 * v + 2] - offset));
    plane[0] = n[0];
    plane[1] = n[1];
    plane[2] = n[2];
    plane[3] = offset;
    plane[4] = slack + 1e-9 * scale;
}

} // namespace

NearestTriangle::NearestTriangle(const TriangleMesh &mesh)
{
    const uint32_t n = uint32_t(mesh.triangles.size());
    std::vector<std::array<double, 3>> centroids(n);
    std::vector<uint32_t> order(n);
    for (uint32_t t = 0; t < n; ++t) {
        order[t] = t;
        for (int k = 0; k < 3; ++k)
            centroids[t][k] = (double(mesh.points[mesh.triangles[t][0]][k]) + mesh.points[mesh.triangles[t][1]][k] +
                               mesh.points[mesh.triangles[t][2]][k]) /
                              3.0;
    }
    mNodes.reserve(2 * (n / kLeafSize + 1));
    if (n > 0)
        build(0, n, order, centroids, mesh);
    mTriangles.resize(size_t(n) * 9);
    for (uint32_t i = 0; i < n; ++i)
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k)
                mTriangles[size_t(i) * 9 + v * 3 + k] = mesh.points[mesh.triangles[order[i]][v]][k];
    mPlanes.resize(size_t(n) * 5);
    for (uint32_t i = 0; i < n; ++i)
        trianglePlane(&mTriangles[size_t(i) * 9], &mPlanes[size_t(i) * 5]);
}

// Median splits (median_split.h), depth first, so a node's left child
// follows it. Returns the node's index.
uint32_t NearestTriangle::build(uint32_t first, uint32_t count, std::vector<uint32_t> &order,
                                const std::vector<std::array<double, 3>> &centroids, const TriangleMesh &mesh)
{
    const uint32_t index = uint32_t(mNodes.size());
    mNodes.push_back(Node{});
    Node node{};
    node.first = first;
    node.count = count;
    auto corner = [&](uint32_t i, int v) { return mesh.points[mesh.triangles[order[i]][v]]; };
    // Box; area-weighted centre and mean normal, each triangle's normal
    // turned to agree with the sum so far (orientation does not matter here).
    double area = 0, sum[3] = {0, 0, 0}, centre[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        node.lo[k] = INFINITY;
        node.hi[k] = -INFINITY;
    }
    for (uint32_t i = first; i < first + count; ++i) {
        const auto a = corner(i, 0), b = corner(i, 1), c = corner(i, 2);
        double e1[3], e2[3];
        for (int k = 0; k < 3; ++k) {
            e1[k] = double(b[k]) - a[k];
            e2[k] = double(c[k]) - a[k];
            node.lo[k] = std::min({node.lo[k], a[k], b[k], c[k]});
            node.hi[k] = std::max({node.hi[k], a[k], b[k], c[k]});
        }
        const double cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                 e1[0] * e2[1] - e1[1] * e2[0]};
        const double twice = std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
        const double turn = cross[0] * sum[0] + cross[1] * sum[1] + cross[2] * sum[2] < 0 ? -1.0 : 1.0;
        for (int k = 0; k < 3; ++k) {
            sum[k] += turn * cross[k];
            centre[k] += twice * centroids[order[i]][k];
        }
        area += twice;
    }
    const double length = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    for (int k = 0; k < 3; ++k) {
        node.normal[k] = length > 0 ? sum[k] / length : (k == 2 ? 1.0 : 0.0);
        node.centre[k] = area > 0 ? centre[k] / area : 0.5 * (double(node.lo[k]) + node.hi[k]);
    }
    for (uint32_t i = first; i < first + count; ++i)
        for (int v = 0; v < 3; ++v) {
            const auto p = corner(i, v);
            double d[3], a = 0, d2 = 0;
            for (int k = 0; k < 3; ++k) {
                d[k] = double(p[k]) - node.centre[k];
                a += d[k] * node.normal[k];
                d2 += d[k] * d[k];
            }
            // Grown by the rounding of a and of d2 - a^2 (see kCancel).
            node.thickness = std::max(node.thickness, std::abs(a) + kCancel * std::sqrt(d2));
            node.radius = std::max(node.radius, std::sqrt(std::max(d2 - a * a + kCancel * d2, 0.0)));
        }
    if (count > kLeafSize) {
        const uint32_t half = splitAtMedian(order, first, count, centroids);
        build(first, half, order, centroids, mesh);
        node.right = build(first + half, count - half, order, centroids, mesh);
        node.count = 0;
    }
    mNodes[index] = node;
    return index;
}

// A lower bound on the squared distance from every point of the packet's box
// [lo, hi] (centre `centre`, half-diagonal `radius`) to the node's triangles:
// the larger of the boxes' distance and the disc's distance from the centre
// less the radius (shrunk for rounding); the disc is not computed when the
// boxes already reach `worst`.
double NearestTriangle::packetLowerBound2(const Node &node, const double *lo, const double *hi, const double *centre,
                                          double radius, double worst) const
{
    double box = 0;
    for (int k = 0; k < 3; ++k) {
        const double d = std::max({double(node.lo[k]) - hi[k], 0.0, lo[k] - double(node.hi[k])});
        box += d * d;
    }
    box *= kShrink;
    if (box >= worst)
        return box;
    double d[3], a = 0, d2 = 0;
    for (int k = 0; k < 3; ++k) {
        d[k] = centre[k] - node.centre[k];
        a += d[k] * node.normal[k];
        d2 += d[k] * d[k];
    }
    const double across = std::max(std::abs(a) - node.thickness, 0.0);
    const double along = std::max(std::sqrt(std::max(d2 - a * a - kCancel * d2, 0.0)) - node.radius, 0.0);
    const double disc =
        std::max(std::sqrt(std::max(across * across + along * along - kCancel * d2, 0.0)) - radius, 0.0);
    return std::max(box, disc * disc * kShrink);
}

// A node's two lower bounds (box and disc) for each centre of a packet, from
// terms that each depend on one axis: the squared gap to the
// box, the height above the disc's centre along its normal, and the squared
// offset from the disc's centre.
class CentreBounds
{
  public:
    static constexpr int n = NearestTriangle::kPacketDim;

    CentreBounds(const double (*axis)[n], const float *lo, const float *hi, const double *centre, const double *normal,
                 double thickness, double radius)
        : mThickness(thickness), mRadius(radius)
    {
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < n; ++i) {
                const double gap = std::max({double(lo[k]) - axis[k][i], 0.0, axis[k][i] - double(hi[k])});
                const double offset = axis[k][i] - centre[k];
                mGap[k][i] = gap * gap;
                mHeight[k][i] = offset * normal[k];
                mSquare[k][i] = offset * offset;
            }
    }

    /// Bit l set for each centre (i, j, l) of the row that may lie nearer
    /// than its best (`best`: the row's kPacketDim squared distances) to the
    /// node's triangles. Without branches, so that the row is computed
    /// side by side.
    unsigned rowReaches(int i, int j, const double *best) const
    {
        const double gap = mGap[0][i] + mGap[1][j], height = mHeight[0][i] + mHeight[1][j];
        const double square = mSquare[0][i] + mSquare[1][j];
        unsigned mask = 0;
        for (int l = 0; l < n; ++l) {
            const double a = height + mHeight[2][l];
            const double offset2 = square + mSquare[2][l], lateral2 = offset2 - a * a - kCancel * offset2;
            const double across = std::max(std::abs(a) - mThickness, 0.0);
            const double along = std::sqrt(std::max(lateral2, mRadius * mRadius)) - mRadius;
            const double disc = across * across + along * along - kCancel * offset2;
            const double bound = std::max(gap + mGap[2][l], disc) * kShrink;
            mask |= unsigned(bound < best[l]) << l;
        }
        return mask;
    }

    /// Whether any centre may lie nearer than its best to the node.
    bool anyReaches(const double *best) const
    {
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                if (rowReaches(i, j, best + (i * n + j) * n))
                    return true;
        return false;
    }

  private:
    double mGap[3][n], mHeight[3][n], mSquare[3][n];
    double mThickness, mRadius;
};

void NearestTriangle::packetDistance2(const double *corner, double spacing, double *best, uint32_t *nearest) const
{
    if (mNodes.empty())
        return;
    double axis[3][kPacketDim], lo[3], hi[3], centre[3];
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < kPacketDim; ++i)
            axis[k][i] = corner[k] + i * spacing;
        lo[k] = axis[k][0];
        hi[k] = axis[k][kPacketDim - 1];
        centre[k] = 0.5 * (lo[k] + hi[k]);
    }
    for (int i = 0, v = 0; i < kPacketDim; ++i)
        for (int j = 0; j < kPacketDim; ++j)
            for (int l = 0; l < kPacketDim; ++l, ++v)
                if (nearest[v] != kNone) {
                    const double q[3] = {axis[0][i], axis[1][j], axis[2][l]};
                    const double d2 = triangleDistance2(&mTriangles[size_t(nearest[v]) * 9], q);
                    if (d2 < best[v])
                        best[v] = d2;
                    else
                        nearest[v] = kNone;
                }
    const double radius = 0.5 * std::sqrt(3.0) * (kPacketDim - 1) * spacing * (1 + 1e-12);
    double worst = *std::max_element(best, best + kPacketSize);
    struct Entry {
        uint32_t node;
        double bound;
    };
    Entry stack[64];
    int top = 0;
    stack[top++] = {0, packetLowerBound2(mNodes[0], lo, hi, centre, radius, worst)};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.bound >= worst)
            continue;
        const Node &node = mNodes[e.node];
        const CentreBounds bounds(axis, node.lo, node.hi, node.centre, node.normal, node.thickness, node.radius);
        if (node.count > 0) {
            for (int i = 0; i < kPacketDim; ++i)
                for (int j = 0; j < kPacketDim; ++j)
                    for (unsigned mask = bounds.rowReaches(i, j, best + (i * kPacketDim + j) * kPacketDim); mask;
                         mask &= mask - 1) {
                        const int l = __builtin_ctz(mask), v = (i * kPacketDim + j) * kPacketDim + l;
                        const double q[3] = {axis[0][i], axis[1][j], axis[2][l]};
                        for (uint32_t t = node.first; t < node.first + node.count; ++t) {
                            const double *plane = &mPlanes[size_t(t) * 5];
                            const double height =
                                std::abs(plane[0] * q[0] + plane[1] * q[1] + plane[2] * q[2] - plane[3]) - plane[4];
                            if (height > 0 && height * height >= best[v])
                                continue;
                            const double d2 = triangleDistance2(&mTriangles[size_t(t) * 9], q);
                            if (d2 < best[v]) {
                                best[v] = d2;
                                nearest[v] = t;
                            }
                        }
                    }
            worst = *std::max_element(best, best + kPacketSize);
            continue;
        }
        if (!bounds.anyReaches(best))
            continue;
        // The nearer child is searched first: pushed last.
        const uint32_t left = e.node + 1, right = node.right;
        const double bl = packetLowerBound2(mNodes[left], lo, hi, centre, radius, worst);
        const double br = packetLowerBound2(mNodes[right], lo, hi, centre, radius, worst);
        if (bl < br) {
            stack[top++] = {right, br};
            stack[top++] = {left, bl};
        } else {
            stack[top++] = {left, bl};
            stack[top++] = {right, br};
        }
    }
}

} // namespace mesh2sdf
