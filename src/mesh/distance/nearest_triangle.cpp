// sdftrace — exact nearest-triangle queries for packets of voxel centres
// (see nearest_triangle.h).
//
// Why every centre's answer is exact. The search keeps, per centre v, best(v):
// the smallest squared distance from v to a triangle evaluated so far (or
// the caller's bound). It skips a set of triangles only on a lower bound on
// their distance from v that is at least best(v), so no skipped triangle is
// nearer than v's final best, and the answer, a minimum of preparedDistance2
// over evaluated triangles, is the minimum over all of them. The skips:
//  - a node, for the whole packet, when its lower bound over the packet's
//    box is at least `worst`, the largest best(v): every v lies in that box,
//    so each of the node's triangles is at least worst >= best(v) from v;
//  - a node, for the whole packet, when for every centre v its own lower
//    bound is at least best(v) (Rows::groupReaches, packet_rows.h, a group
//    of rows at a time);
//  - a leaf's triangles, for a group of rows (one row of four centres
//    (i, j, 0..3), or two, (i, j..j + 1, 0..3), with AVX-512), when each
//    centre's own lower bound on the leaf is at least its best.
// A group's centres all take the distances of every triangle evaluated for
// the group, and each keeps the smaller: a true distance to a triangle only
// ever lowers best(v) towards its answer, so it breaks no skip.
// Bests only fall, so a skip stays justified to the end.
//
// The lower bounds of a node, both true because each triangle is the convex
// hull of its corners and both shapes are convex and hold every corner: the
// distance to the node's box, and the distance to its disc (disc.h, which
// gives why, and why far from a nearly flat patch the box is the poorer).
// Over a packet: the distance between the node's box and the packet's box,
// and the disc's distance from the packet's centre less the packet's
// half-diagonal (a distance to a convex set changes by at most the distance
// moved). All are computed in double precision and shrunk by a relative
// 1e-12, far above their rounding error, except where the disc's terms
// cancel, which kCancel covers.
//
// Why packets: neighbouring centres open nearly the same nodes, so one
// descent serves kPacketSize centres; each centre then pays only its own
// bounds at the nodes the packet opens (from per-axis terms, RowTerms) and
// the triangles no bound excludes, a row of four centres at a time
// (packet_rows.h, with AVX2 where the processor has it; two rows, eight
// centres, with AVX-512). Each centre starts from a
// neighbour's nearest triangle, so the bests are near their answers from
// the first node on, and nearer children are searched first.
#include "distance/nearest_triangle.h"

// GCC 12 flags its own AVX-512 intrinsics (_mm512_max_pd and others pass an
// _mm512_undefined_pd() as the unused merge source) as maybe-uninitialized
// once they are inlined into searchAvx512; a false positive in its headers,
// silenced for this file only.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "distance/disc.h"
#include "geometry/median_split.h"

#include <algorithm>
#include <cmath>

namespace meshsdf
{

namespace
{

constexpr uint32_t kLeafSize = 4;
constexpr double kShrink = kDiscShrink;
constexpr double kCancel = kDiscCancel; // disc.h

// A node on a search's stack, with its lower bound.
struct Entry {
    uint32_t node;
    double bound;
};

// Pushes both children, the nearer last so that it is searched first.
inline void pushChildren(Entry *stack, int &top, Entry left, Entry right)
{
    const bool leftFirst = left.bound < right.bound;
    stack[top++] = leftFirst ? right : left;
    stack[top++] = leftFirst ? left : right;
}

} // namespace

NearestTriangle::NearestTriangle(const TriangleMesh &mesh, bool vectorized, bool wide)
{
    mVectorized = vectorized && rowsVectorizable();
    mVectorized512 = mVectorized && wide && rowsVectorizable512();
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
    mTriangles.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
        double corner[3][3];
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k)
                corner[v][k] = mesh.points[mesh.triangles[order[i]][v]][k];
        mTriangles[i] = prepareTriangle(corner[0], corner[1], corner[2]);
    }
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
    auto corner = [&](uint32_t i, int v) -> const std::array<float, 3> & {
        return mesh.points[mesh.triangles[order[i]][v]];
    };
    for (int k = 0; k < 3; ++k) {
        node.lo[k] = INFINITY;
        node.hi[k] = -INFINITY;
    }
    for (uint32_t i = first; i < first + count; ++i)
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k) {
                node.lo[k] = std::min(node.lo[k], corner(i, v)[k]);
                node.hi[k] = std::max(node.hi[k], corner(i, v)[k]);
            }
    const Disc disc = discAround(
        first, count, corner, [&](uint32_t i) { return centroids[order[i]].data(); }, node.lo, node.hi);
    for (int k = 0; k < 3; ++k) {
        node.centre[k] = disc.centre[k];
        node.normal[k] = disc.normal[k];
    }
    node.thickness = disc.thickness;
    node.radius = disc.radius;
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

void NearestTriangle::packetDistance2(const double *corner, double spacing, double *best, uint32_t *nearest) const
{
    if (mNodes.empty())
        return;
#ifdef SDFT_MESH_ROWS_AVX2
    if (mVectorized512)
        return searchAvx512(corner, spacing, best, nearest);
    if (mVectorized)
        return searchAvx2(corner, spacing, best, nearest);
#endif
    search<ScalarRows>(corner, spacing, best, nearest);
}

#ifdef SDFT_MESH_ROWS_AVX2
// The search compiled for AVX2 and FMA, everything it calls inlined
// (flatten), so that Avx2Rows's intrinsics run in its body.
__attribute__((target("avx2,fma"), flatten)) void NearestTriangle::searchAvx2(const double *corner, double spacing,
                                                                              double *best, uint32_t *nearest) const
{
    search<Avx2Rows>(corner, spacing, best, nearest);
}

// The same with AVX-512 for the triangle distances, two rows at a time.
__attribute__((target("avx512f,avx2,fma"), flatten)) void
NearestTriangle::searchAvx512(const double *corner, double spacing, double *best, uint32_t *nearest) const
{
    search<Avx512Rows>(corner, spacing, best, nearest);
}
#endif

// The packet search (the file's head gives why its answers are exact), a
// row of four centres at a time through `Rows`.
template <class Rows>
void NearestTriangle::search(const double *corner, double spacing, double *best, uint32_t *nearest) const
{
    constexpr int n = kPacketDim;
    static_assert(n == 4, "a row is four lanes (packet_rows.h)");
    constexpr RowRounding rounding{kCancel, kShrink};
    alignas(32) double axis[3][n];
    double lo[3], hi[3], centre[3];
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < n; ++i)
            axis[k][i] = corner[k] + i * spacing;
        lo[k] = axis[k][0];
        hi[k] = axis[k][n - 1];
        centre[k] = 0.5 * (lo[k] + hi[k]);
    }
    // The seeds, each evaluated once for its whole group of rows (neighbours
    // mostly share one): a true distance only lowers a best.
    uint32_t seeds[kPacketSize];
    std::copy(nearest, nearest + kPacketSize, seeds);
    std::fill(nearest, nearest + kPacketSize, kNone);
    for (int row = 0; row < n * n; row += Rows::kRows) {
        const uint32_t *groupSeeds = seeds + row * n;
        for (int l = 0; l < n * Rows::kRows; ++l) {
            const uint32_t t = groupSeeds[l];
            if (t == kNone || std::find(groupSeeds, groupSeeds + l, t) != groupSeeds + l)
                continue;
            double d2[n * Rows::kRows];
            Rows::groupDistances(mTriangles[t], axis[0][row / n], &axis[1][row % n], axis[2], d2);
            for (unsigned lowered = Rows::lowerGroup(d2, best + row * n); lowered; lowered &= lowered - 1)
                nearest[row * n + __builtin_ctz(lowered)] = t;
        }
    }
    const double radius = 0.5 * std::sqrt(3.0) * (n - 1) * spacing * (1 + 1e-12);
    double worst = *std::max_element(best, best + kPacketSize);
    Entry stack[64];
    int top = 0;
    stack[top++] = {0, packetLowerBound2(mNodes[0], lo, hi, centre, radius, worst)};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.bound >= worst)
            continue;
        const Node &node = mNodes[e.node];
        const RowTerms terms =
            Rows::terms(axis, node.lo, node.hi, node.centre, node.normal, node.thickness, node.radius);
        if (node.count > 0) {
            // Rows::kRows rows (i, j..j + kRows - 1) at a time, skipped when
            // none of them reaches the leaf.
            static_assert(n % Rows::kRows == 0, "a group of rows stays in one i");
            bool lowered = false;
            for (int row = 0; row < n * n; row += Rows::kRows) {
                double *rowBest = best + row * n;
                if (!Rows::groupReaches(terms, rounding, row / n, row % n, rowBest))
                    continue;
                for (uint32_t t = node.first; t < node.first + node.count; ++t) {
                    double d2[n * Rows::kRows];
                    Rows::groupDistances(mTriangles[t], axis[0][row / n], &axis[1][row % n], axis[2], d2);
                    const unsigned lanes = Rows::lowerGroup(d2, rowBest);
                    lowered = lowered || lanes != 0;
                    for (unsigned lane = lanes; lane; lane &= lane - 1)
                        nearest[row * n + __builtin_ctz(lane)] = t;
                }
            }
            if (lowered)
                worst = *std::max_element(best, best + kPacketSize);
            continue;
        }
        bool any = false;
        for (int row = 0; row < n * n && !any; row += Rows::kRows)
            any = Rows::groupReaches(terms, rounding, row / n, row % n, best + row * n) != 0;
        if (!any)
            continue;
        // The nearer child is searched first: pushed last.
        const uint32_t left = e.node + 1, right = node.right;
        pushChildren(stack, top, {left, packetLowerBound2(mNodes[left], lo, hi, centre, radius, worst)},
                     {right, packetLowerBound2(mNodes[right], lo, hi, centre, radius, worst)});
    }
}

} // namespace meshsdf
