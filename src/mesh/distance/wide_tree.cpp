// sdftrace — exact point-to-mesh distances through a wide bounding volume
// hierarchy (see wide_tree.h).
//
// Why the answer is exact, and the same whatever the search's path. The answer
// is the smallest of the start's d2 and preparedDistance2(t, p) over every
// triangle t (call that value D(t)). The search skips a child only when no
// triangle in it can lower the best d2 found so far (best), so the minimum
// over the triangles it evaluates is the minimum over all: the same number for
// one point or a packet, a seed or none, AVX2 or scalar lanes (which compute
// the same operations in the same order on the same data).
//
// The skip. A child's box is the exact float bounds of its triangles' corners
// (the triangles' doubles are those floats), so every point of its triangles
// lies in it, and the true squared distance from p to a triangle t in it is at
// least dist2(p, box). D(t) is not the true distance: for a triangle of width
// down to kThin times its longest edge (packet_rows.h) the unit normal carries
// a relative error of about 3.3e-8 (kThin's comment), and the height above the
// plane an absolute one of that times |p - corner|, so D(t) >= true^2 - 7e-8
// R^2 with R = |p - c| + 2 r (c, r a sphere around every corner: R bounds |p -
// corner| and every edge); the edges' terms carry a few ulps of R^2. slack(p)
// = 2^-22 R^2 (2.4e-7 R^2) covers both twice. The box's distance is computed
// in float from p rounded outwards to floats (below for the low side, above
// for the high side, so each gap is at most the true gap) by five roundings of
// relative error at most 2^-24 each, so box2 <= (1 + 2^-19) dist2(p, box).
// Hence a child with box2 > limit = (best + slack) (1 + 2^-19), rounded up to
// a float, has D(t) >= box2 / (1 + 2^-19) - slack > best for each of its
// triangles: none can lower best. A limit beyond the floats is +inf, and a
// child is skipped only when box2 > limit, so +inf skips nothing. A packet
// tests the box around its points against its largest limit: every point's
// distance to a child is at least the packet box's. A child is also skipped
// when its disc (disc.h: a lower bound on the true distance, its rounding
// covered) bounds the squared distance by at least (best + slack) (1 + 2^-50),
// so that D(t) >= bound - slack > best: a node tests the discs of its flat
// children (a disc much thinner than the box, where the box is the poor
// bound), and a packet's points test them at the leaves they reach. Near a
// point on the surface the slack opens the leaves within about 5e-4 R of it;
// elsewhere it is far below the distances and costs nothing.
//
// The tree: children are split at the median centroid along the longest
// axis of their centroids' bounds, the largest range first, until a node
// has eight children or every child holds at most four triangles (a leaf,
// one group of lanes). Split positions are multiples of four and depend on
// the counts alone, so the shape, and so the nodes' positions (depth
// first), are known before any triangle is looked at: subtrees are built in
// parallel into their own slots, the same tree on any thread count.
#include "distance/wide_tree.h"

#include "distance/disc.h"
#include "distance/packet_rows.h"
#include "geometry/median_split.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cstring>
#include <limits>
#include <numeric>
#include <unordered_map>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SDFT_WIDE_AVX2 1
#endif

namespace meshsdf
{

namespace
{

// The float after f towards +inf (f finite or -inf), as std::nextafter,
// without its call.
inline float floatUp(float f)
{
    if (f == 0)
        return std::numeric_limits<float>::denorm_min();
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    bits = f > 0 ? bits + 1 : bits - 1;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

// Floats next to x: at most x, at least x (infinite beyond the floats).
inline float floatAbove(double x)
{
    if (!(x <= FLT_MAX))
        return INFINITY;
    const float f = float(std::max(x, double(-FLT_MAX)));
    return double(f) < x ? floatUp(f) : f;
}
inline float floatBelow(double x) { return -floatAbove(-x); }

// The largest box distance that may hold a triangle nearer than best (see
// the head of the file).
inline float limitFor(double best, double slack) { return floatAbove((best + slack) * (1 + 0x1p-19)); }

// Subtrees over fewer triangles than this are built on one thread.
constexpr uint32_t kSerialBuild = 4096;

// The deepest stack a search needs: at most kWidth - 1 entries a level
// below the root, and a tree over 2^32 triangles is 11 levels deep.
constexpr int kStack = 128;

// A packet is coherent when the squared diagonal of the box around its
// points is below kCoherent times the squared distance of its first point
// from the nearest triangle of the point before: then the points share most
// of the nodes they open.
constexpr double kCoherent = 1.0 / 16;

} // namespace

// ---------------------------------------------------------------- lanes

// The two ways of testing a node's children and a leaf's triangles, each
// operation the same in both (no fused multiply-add: the file is compiled
// without contraction, and the AVX2 code asks for none), so that their
// answers agree bit for bit.
struct ScalarLanes {
    using Node = WideTree::Node;
    using Group = WideTree::Group;

    // Bit k set for each child k whose box's squared distance from the box
    // [lo, hi] is at most limit; the distances in d2.
    static unsigned boxes(const Node &n, const float *lo, const float *hi, float limit, float *d2)
    {
        unsigned mask = 0;
        for (int k = 0; k < WideTree::kWidth; ++k) {
            float g[3];
            for (int a = 0; a < 3; ++a) {
                const float below = n.lo[a][k] - hi[a], above = lo[a] - n.hi[a][k];
                const float gap = below > above ? below : above;
                g[a] = gap > 0.0f ? gap : 0.0f;
            }
            d2[k] = (g[0] * g[0] + g[1] * g[1]) + g[2] * g[2];
            mask |= unsigned(d2[k] <= limit) << k;
        }
        return mask & n.valid;
    }

    // Bit k set for each child whose disc's lower bound on the squared
    // distance from p (disc.h) is below limit2.
    static unsigned discs(const Node &n, const double *p, double limit2)
    {
        unsigned mask = 0;
        for (int k = 0; k < WideTree::kWidth; ++k) {
            const double dx = p[0] - n.centre[0][k], dy = p[1] - n.centre[1][k], dz = p[2] - n.centre[2][k];
            const double a = dx * n.normal[0][k] + dy * n.normal[1][k] + dz * n.normal[2][k];
            const double d2 = dx * dx + dy * dy + dz * dz, cancel = kDiscCancel * d2;
            const double lateral2 = d2 - a * a - cancel;
            const double height = (a < 0 ? -a : a) - n.thickness[k];
            const double across = height > 0 ? height : 0.0;
            const double root = std::sqrt(lateral2 > 0 ? lateral2 : 0.0) - n.radius[k];
            const double along = root > 0 ? root : 0.0;
            const double bound = (across * across + along * along - cancel) * kDiscShrink;
            mask |= unsigned(bound < limit2) << k;
        }
        return mask;
    }

    // preparedDistance2 (packet_rows.h) of lane l's triangle, operation by
    // operation.
    static double lane(const Group &t, int l, const double *p)
    {
        double edges = INFINITY, height = 0;
        bool inside = true;
        for (int k = 0; k < 3; ++k) {
            const int next = k == 2 ? 0 : k + 1;
            double corner[3], e[3], m[3];
            for (int x = 0; x < 3; ++x) {
                corner[x] = t.corner[k][x][l];
                e[x] = double(t.corner[next][x][l]) - corner[x];
                m[x] = t.inward[k][x][l];
            }
            const double w[3] = {p[0] - corner[0], p[1] - corner[1], p[2] - corner[2]};
            const double s = std::clamp((w[0] * e[0] + w[1] * e[1] + w[2] * e[2]) * t.inverse[k][l], 0.0, 1.0);
            const double r[3] = {w[0] - s * e[0], w[1] - s * e[1], w[2] - s * e[2]};
            edges = std::min(edges, r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            inside = inside && w[0] * m[0] + w[1] * m[1] + w[2] * m[2] > 0;
            if (k == 0)
                height = w[0] * t.normal[0][l] + w[1] * t.normal[1][l] + w[2] * t.normal[2][l];
        }
        return inside ? height * height : edges;
    }

    // The squared distances from p to the group's four lanes.
    static void triangles(const Group &t, const double *p, double *d2)
    {
        for (int l = 0; l < WideTree::kLeafSize; ++l)
            d2[l] = lane(t, l, p);
    }
};

#ifdef SDFT_WIDE_AVX2
#define SDFT_WIDE_AVX2_INLINE __attribute__((target("avx2"))) inline
struct Avx2Lanes {
    using Node = WideTree::Node;
    using Group = WideTree::Group;

    SDFT_WIDE_AVX2_INLINE static unsigned boxes(const Node &n, const float *lo, const float *hi, float limit, float *d2)
    {
        const __m256 zero = _mm256_setzero_ps();
        __m256 g[3];
        for (int a = 0; a < 3; ++a) {
            const __m256 below = _mm256_sub_ps(_mm256_load_ps(n.lo[a]), _mm256_set1_ps(hi[a]));
            const __m256 above = _mm256_sub_ps(_mm256_set1_ps(lo[a]), _mm256_load_ps(n.hi[a]));
            g[a] = _mm256_max_ps(_mm256_max_ps(below, above), zero);
        }
        const __m256 sum = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(g[0], g[0]), _mm256_mul_ps(g[1], g[1])),
                                         _mm256_mul_ps(g[2], g[2]));
        _mm256_storeu_ps(d2, sum);
        return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(sum, _mm256_set1_ps(limit), _CMP_LE_OQ))) & n.valid;
    }

    SDFT_WIDE_AVX2_INLINE static __m256d corner(const Group &t, int k, int x)
    {
        return _mm256_cvtps_pd(_mm_load_ps(t.corner[k][x]));
    }

    // ScalarLanes::discs, four children at a time: max(x, 0) is
    // _mm256_max_pd(x, zero) (x > 0 ? x : 0), |a| the sign bit cleared.
    SDFT_WIDE_AVX2_INLINE static unsigned discs(const Node &n, const double *p, double limit2)
    {
        const __m256d zero = _mm256_setzero_pd(), sign = _mm256_set1_pd(-0.0);
        unsigned mask = 0;
        for (int half = 0; half < WideTree::kWidth; half += 4) {
            const __m256d dx = _mm256_sub_pd(_mm256_set1_pd(p[0]), _mm256_load_pd(n.centre[0] + half));
            const __m256d dy = _mm256_sub_pd(_mm256_set1_pd(p[1]), _mm256_load_pd(n.centre[1] + half));
            const __m256d dz = _mm256_sub_pd(_mm256_set1_pd(p[2]), _mm256_load_pd(n.centre[2] + half));
            const __m256d a = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, _mm256_load_pd(n.normal[0] + half)),
                                                          _mm256_mul_pd(dy, _mm256_load_pd(n.normal[1] + half))),
                                            _mm256_mul_pd(dz, _mm256_load_pd(n.normal[2] + half)));
            const __m256d d2 =
                _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
            const __m256d cancel = _mm256_mul_pd(_mm256_set1_pd(kDiscCancel), d2);
            const __m256d lateral2 = _mm256_sub_pd(_mm256_sub_pd(d2, _mm256_mul_pd(a, a)), cancel);
            const __m256d across =
                _mm256_max_pd(_mm256_sub_pd(_mm256_andnot_pd(sign, a), _mm256_load_pd(n.thickness + half)), zero);
            const __m256d along = _mm256_max_pd(
                _mm256_sub_pd(_mm256_sqrt_pd(_mm256_max_pd(lateral2, zero)), _mm256_load_pd(n.radius + half)), zero);
            const __m256d bound = _mm256_mul_pd(
                _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(across, across), _mm256_mul_pd(along, along)), cancel),
                _mm256_set1_pd(kDiscShrink));
            mask |= unsigned(_mm256_movemask_pd(_mm256_cmp_pd(bound, _mm256_set1_pd(limit2), _CMP_LT_OQ))) << half;
        }
        return mask;
    }

    // ScalarLanes::lane on four lanes: std::clamp(v, 0, 1) is max(0, min(1,
    // v)) with the instructions' operand order (NaN passes through both),
    // std::min(edges, r2) is min(r2, edges).
    SDFT_WIDE_AVX2_INLINE static void triangles(const Group &t, const double *p, double *d2)
    {
        const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
        __m256d edges = _mm256_set1_pd(INFINITY), inside = _mm256_castsi256_pd(_mm256_set1_epi64x(-1)), height = zero;
        __m256d c[3][3];
        for (int k = 0; k < 3; ++k)
            for (int x = 0; x < 3; ++x)
                c[k][x] = corner(t, k, x);
        for (int k = 0; k < 3; ++k) {
            const int next = k == 2 ? 0 : k + 1;
            const __m256d wx = _mm256_sub_pd(_mm256_set1_pd(p[0]), c[k][0]);
            const __m256d wy = _mm256_sub_pd(_mm256_set1_pd(p[1]), c[k][1]);
            const __m256d wz = _mm256_sub_pd(_mm256_set1_pd(p[2]), c[k][2]);
            const __m256d ex = _mm256_sub_pd(c[next][0], c[k][0]), ey = _mm256_sub_pd(c[next][1], c[k][1]),
                          ez = _mm256_sub_pd(c[next][2], c[k][2]);
            const __m256d along =
                _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(wx, ex), _mm256_mul_pd(wy, ey)), _mm256_mul_pd(wz, ez));
            const __m256d s =
                _mm256_max_pd(zero, _mm256_min_pd(one, _mm256_mul_pd(along, _mm256_load_pd(t.inverse[k]))));
            const __m256d rx = _mm256_sub_pd(wx, _mm256_mul_pd(s, ex));
            const __m256d ry = _mm256_sub_pd(wy, _mm256_mul_pd(s, ey));
            const __m256d rz = _mm256_sub_pd(wz, _mm256_mul_pd(s, ez));
            const __m256d r2 =
                _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(rx, rx), _mm256_mul_pd(ry, ry)), _mm256_mul_pd(rz, rz));
            edges = _mm256_min_pd(r2, edges);
            const __m256d side = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(wx, _mm256_load_pd(t.inward[k][0])),
                                                             _mm256_mul_pd(wy, _mm256_load_pd(t.inward[k][1]))),
                                               _mm256_mul_pd(wz, _mm256_load_pd(t.inward[k][2])));
            inside = _mm256_and_pd(inside, _mm256_cmp_pd(side, zero, _CMP_GT_OQ));
            if (k == 0)
                height = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(wx, _mm256_load_pd(t.normal[0])),
                                                     _mm256_mul_pd(wy, _mm256_load_pd(t.normal[1]))),
                                       _mm256_mul_pd(wz, _mm256_load_pd(t.normal[2])));
        }
        _mm256_storeu_pd(d2, _mm256_blendv_pd(edges, _mm256_mul_pd(height, height), inside));
    }
};
#undef SDFT_WIDE_AVX2_INLINE
#endif

// ---------------------------------------------------------------- build

struct WideTree::Box {
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    void grow(const Box &b)
    {
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], b.lo[k]);
            hi[k] = std::max(hi[k], b.hi[k]);
        }
    }
};

struct WideTree::Builder {
    const TriangleMesh &mesh;
    std::vector<std::array<double, 3>> centroid;
    std::vector<uint32_t> order;
    std::vector<Node> &nodes;

    // A node's children over `count` triangles: ranges split at positions
    // that are multiples of kLeafSize, the largest range first (the first
    // of equals), until there are kWidth or none holds more than a leaf.
    // Fills counts[] with the children's triangle counts in order, calling
    // split(i, left) just before range i is cut after its first `left`
    // triangles; returns the number of children.
    template <class Split> static int plan(uint32_t count, uint32_t *counts, Split split)
    {
        int n = 1;
        counts[0] = count;
        while (n < kWidth) {
            int widest = 0;
            for (int i = 1; i < n; ++i)
                if (counts[i] > counts[widest])
                    widest = i;
            if (counts[widest] <= uint32_t(kLeafSize))
                break;
            const uint32_t groups = (counts[widest] + kLeafSize - 1) / kLeafSize;
            const uint32_t left = (groups + 1) / 2 * kLeafSize;
            split(widest, left);
            std::copy_backward(counts + widest + 1, counts + n, counts + n + 1);
            counts[widest + 1] = counts[widest] - left;
            counts[widest] = left;
            ++n;
        }
        return n;
    }

    // Nodes in the subtree over each count of triangles that occurs (none
    // for a leaf): a count's subtree is the same wherever it occurs, so
    // few counts occur, and the table is filled before the build reads it
    // from its threads.
    std::unordered_map<uint32_t, uint32_t> subtree;

    uint32_t nodesFor(uint32_t count)
    {
        if (count <= uint32_t(kLeafSize))
            return 0;
        const auto known = subtree.find(count);
        if (known != subtree.end())
            return known->second;
        uint32_t counts[kWidth], total = 1;
        const int n = plan(count, counts, [](int, uint32_t) {});
        for (int i = 0; i < n; ++i)
            total += nodesFor(counts[i]);
        subtree[count] = total;
        return total;
    }

    uint32_t nodesKnown(uint32_t count) const { return count <= uint32_t(kLeafSize) ? 0 : subtree.at(count); }

    Box leafBox(uint32_t first, uint32_t count) const
    {
        Box b;
        for (uint32_t i = first; i < first + count; ++i)
            for (int v = 0; v < 3; ++v) {
                const auto &q = mesh.points[mesh.triangles[order[i]][v]];
                for (int k = 0; k < 3; ++k) {
                    b.lo[k] = std::min(b.lo[k], q[k]);
                    b.hi[k] = std::max(b.hi[k], q[k]);
                }
            }
        return b;
    }

    // Builds node `index` over order[first, first + count) and its subtree
    // in the slots after it; returns the box of its triangles.
    Box build(uint32_t index, uint32_t first, uint32_t count)
    {
        uint32_t counts[kWidth], starts[kWidth] = {first};
        const int n = plan(count, counts, [&](int i, uint32_t left) {
            const uint32_t start = starts[i], size = counts[i];
            splitAt(order, start, size, left, centroid);
            std::copy_backward(starts + i + 1, starts + kWidth - 1, starts + kWidth);
            starts[i + 1] = start + left;
        });
        Node node{};
        uint32_t slots[kWidth], next = index + 1;
        for (int i = 0; i < n; ++i) {
            slots[i] = next;
            next += nodesKnown(counts[i]);
        }
        Box boxes[kWidth];
        Disc discs[kWidth];
        auto child = [&](int i) {
            if (counts[i] <= uint32_t(kLeafSize)) {
                boxes[i] = leafBox(starts[i], counts[i]);
            } else {
                boxes[i] = build(slots[i], starts[i], counts[i]);
            }
            discs[i] = discAround(
                starts[i], counts[i],
                [&](uint32_t t, int v) -> const std::array<float, 3> & {
                    return mesh.points[mesh.triangles[order[t]][v]];
                },
                [&](uint32_t t) { return centroid[order[t]].data(); }, boxes[i].lo, boxes[i].hi);
        };
        if (count > kSerialBuild)
            tbb::parallel_for(0, n, child);
        else
            for (int i = 0; i < n; ++i)
                child(i);
        Box all;
        for (int k = 0; k < kWidth; ++k) {
            const bool used = k < n;
            for (int a = 0; a < 3; ++a) {
                node.lo[a][k] = used ? boxes[k].lo[a] : INFINITY;
                node.hi[a][k] = used ? boxes[k].hi[a] : -INFINITY;
            }
            if (!used)
                continue;
            all.grow(boxes[k]);
            for (int a = 0; a < 3; ++a) {
                node.centre[a][k] = discs[k].centre[a];
                node.normal[a][k] = discs[k].normal[a];
            }
            node.thickness[k] = discs[k].thickness;
            node.radius[k] = discs[k].radius;
            // A disc is worth its test where it is much thinner than the
            // box: a flat patch not aligned with the axes.
            float thinnest = INFINITY;
            for (int a = 0; a < 3; ++a)
                thinnest = std::min(thinnest, boxes[k].hi[a] - boxes[k].lo[a]);
            node.flat |= uint8_t(unsigned(4 * discs[k].thickness < thinnest) << k);
            node.valid |= uint8_t(1u << k);
            const bool leaf = counts[k] <= uint32_t(kLeafSize);
            node.leaf |= uint8_t(unsigned(leaf) << k);
            node.child[k] = leaf ? starts[k] / kLeafSize : slots[k];
        }
        nodes[index] = node;
        return all;
    }
};

WideTree::WideTree(const TriangleMesh &mesh, bool simd)
{
#ifdef SDFT_WIDE_AVX2
    mVectorized = simd && __builtin_cpu_supports("avx2");
#else
    (void)simd;
    mVectorized = false;
#endif
    const uint32_t n = uint32_t(mesh.triangles.size());
    mPosition.resize(n);
    if (n == 0)
        return;
    Builder b{mesh, std::vector<std::array<double, 3>>(n), std::vector<uint32_t>(n), mNodes, {}};
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 4096), [&](const tbb::blocked_range<uint32_t> &r) {
        for (uint32_t t = r.begin(); t != r.end(); ++t) {
            b.order[t] = t;
            for (int k = 0; k < 3; ++k)
                b.centroid[t][k] = (double(mesh.points[mesh.triangles[t][0]][k]) +
                                    mesh.points[mesh.triangles[t][1]][k] + mesh.points[mesh.triangles[t][2]][k]) /
                                   3.0;
        }
    });
    // The root is a node even over a single leaf.
    mNodes.resize(std::max<uint32_t>(1, b.nodesFor(n)));
    const Box all = b.build(0, 0, n);
    double diagonal2 = 0;
    for (int k = 0; k < 3; ++k) {
        mCentre[k] = 0.5 * (double(all.lo[k]) + all.hi[k]);
        diagonal2 += (double(all.hi[k]) - all.lo[k]) * (double(all.hi[k]) - all.lo[k]);
    }
    mRadius = 0.5 * std::sqrt(diagonal2) * (1 + 1e-9);

    const uint32_t groups = (n + kLeafSize - 1) / kLeafSize;
    mGroups.resize(groups);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, groups, 256), [&](const tbb::blocked_range<uint32_t> &r) {
        for (uint32_t g = r.begin(); g != r.end(); ++g) {
            Group &group = mGroups[g];
            for (int l = 0; l < kLeafSize; ++l) {
                const uint32_t at = g * kLeafSize + l < n ? g * kLeafSize + l : g * kLeafSize;
                const auto &tri = mesh.triangles[b.order[at]];
                double corner[3][3];
                for (int v = 0; v < 3; ++v)
                    for (int k = 0; k < 3; ++k)
                        corner[v][k] = mesh.points[tri[v]][k];
                const PreparedTriangle t = prepareTriangle(corner[0], corner[1], corner[2]);
                for (int k = 0; k < 3; ++k) {
                    for (int x = 0; x < 3; ++x) {
                        group.corner[k][x][l] = mesh.points[tri[k]][x];
                        group.inward[k][x][l] = t.inward[k][x];
                    }
                    group.inverse[k][l] = t.inverse[k];
                    group.normal[k][l] = t.normal[k];
                }
                if (g * kLeafSize + l < n)
                    mPosition[b.order[at]] = g * kLeafSize + l;
            }
        }
    });
}

// ---------------------------------------------------------------- search

double WideTree::slack(const double *p) const
{
    const double dx = p[0] - mCentre[0], dy = p[1] - mCentre[1], dz = p[2] - mCentre[2];
    const double reach = std::sqrt(dx * dx + dy * dy + dz * dz) + 2 * mRadius;
    return 0x1p-22 * reach * reach;
}

WideTree::Nearest WideTree::seed(const double *p, uint32_t triangle) const
{
    if (triangle == kNone)
        return Nearest{};
    return {ScalarLanes::lane(mGroups[triangle / kLeafSize], int(triangle % kLeafSize), p), triangle};
}

WideTree::Nearest WideTree::nearest(const double *p, Nearest start) const
{
    if (mNodes.empty())
        return start;
#ifdef SDFT_WIDE_AVX2
    if (mVectorized)
        return searchAvx2(p, start);
#endif
    return search<ScalarLanes>(p, start);
}

void WideTree::nearestPacket(const double *const *p, int count, Nearest *io) const
{
    if (mNodes.empty())
        return;
#ifdef SDFT_WIDE_AVX2
    if (mVectorized)
        return searchPacketAvx2(p, count, io);
#endif
    searchPacket<ScalarLanes>(p, count, io);
}

void WideTree::nearestAlong(const double *const *p, size_t count, Nearest *out, uint32_t *near) const
{
    for (size_t i = 0; i < count;) {
        const int n = int(std::min<size_t>(kPacketSize, count - i));
        const Nearest start = seed(p[i], *near);
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, diagonal2 = 0;
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], p[i + j][k]);
                hi[k] = std::max(hi[k], p[i + j][k]);
            }
        for (int k = 0; k < 3; ++k)
            diagonal2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
        if (n > 1 && diagonal2 < kCoherent * start.d2) {
            out[i] = start;
            for (int j = 1; j < n; ++j)
                out[i + j] = seed(p[i + j], *near);
            nearestPacket(p + i, n, out + i);
            *near = out[i + n - 1].triangle;
            i += size_t(n);
        } else {
            out[i] = nearest(p[i], start);
            *near = out[i].triangle;
            ++i;
        }
    }
}

#ifdef SDFT_WIDE_AVX2
__attribute__((target("avx2"), flatten)) WideTree::Nearest WideTree::searchAvx2(const double *p, Nearest best) const
{
    return search<Avx2Lanes>(p, best);
}

__attribute__((target("avx2"), flatten)) void WideTree::searchPacketAvx2(const double *const *p, int count,
                                                                         Nearest *io) const
{
    searchPacket<Avx2Lanes>(p, count, io);
}
#endif

namespace
{

// The child of `mask` (not empty) nearest by d2, the first of equals.
inline int nearestOf(unsigned mask, const float *d2)
{
    int best = __builtin_ctz(mask);
    for (mask &= mask - 1; mask; mask &= mask - 1) {
        const int k = __builtin_ctz(mask);
        if (d2[k] < d2[best])
            best = k;
    }
    return best;
}

struct Entry {
    uint32_t node;
    float d2;
};

} // namespace

// One point's search: where it is (rounded outwards to floats for the box
// tests), its best so far, and the limits that follow from it (see the
// head of the file).
struct WideTree::Seeker {
    const double *p = nullptr;
    Nearest best;
    double slack = 0, discLimit = 0;
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, limit = 0;

    Seeker() = default;
    Seeker(const WideTree &tree, const double *at, Nearest start) : p(at), best(start), slack(tree.slack(at))
    {
        for (int k = 0; k < 3; ++k) {
            lo[k] = floatBelow(p[k]);
            hi[k] = floatAbove(p[k]);
        }
        limits();
    }

    // A child whose disc bound is at least discLimit >= best + slack holds
    // no triangle that can lower best (disc.h; the head of the file).
    void limits()
    {
        limit = limitFor(best.d2, slack);
        discLimit = (best.d2 + slack) * (1 + 0x1p-50);
    }

    // Lowers best by the triangles of group g.
    template <class Lanes> void leaf(const WideTree &tree, uint32_t g)
    {
        double t[kLeafSize];
        Lanes::triangles(tree.mGroups[g], p, t);
        bool lowered = false;
        for (int l = 0; l < kLeafSize; ++l)
            if (t[l] < best.d2) {
                best = {t[l], g * kLeafSize + l};
                lowered = true;
            }
        if (lowered)
            limits();
    }
};

// One point (the head of the file gives why its answer is exact): at each
// node, the leaves the point reaches evaluated at once, the nearest first,
// and the inner children pushed so that the nearest is searched next.
template <class Lanes> WideTree::Nearest WideTree::search(const double *p, Nearest start) const
{
    Seeker q(*this, p, start);
    Entry stack[kStack];
    int top = 0;
    stack[top++] = {0, 0.0f};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.d2 > q.limit)
            continue;
        const Node &node = mNodes[e.node];
        alignas(32) float d2[kWidth];
        unsigned mask = Lanes::boxes(node, q.lo, q.hi, q.limit, d2);
        if (mask & node.flat)
            mask &= Lanes::discs(node, p, q.discLimit) | ~unsigned(node.flat);
        unsigned leaves = mask & node.leaf, inner = mask & ~unsigned(node.leaf);
        if (leaves) {
            const int first = nearestOf(leaves, d2);
            q.leaf<Lanes>(*this, node.child[first]);
            for (leaves &= ~(1u << first); leaves; leaves &= leaves - 1) {
                const int k = __builtin_ctz(leaves);
                if (d2[k] <= q.limit)
                    q.leaf<Lanes>(*this, node.child[k]);
            }
        }
        if (inner) {
            const int first = nearestOf(inner, d2);
            for (unsigned rest = inner & ~(1u << first); rest; rest &= rest - 1) {
                const int k = __builtin_ctz(rest);
                stack[top++] = {node.child[k], d2[k]};
            }
            stack[top++] = {node.child[first], d2[first]};
        }
    }
    return q.best;
}

// A packet: the tree walked once with the box around the points against
// the largest of their limits; at a node whose leaves that box reaches,
// each point tests the node's children itself and evaluates the leaves it
// reaches, so each point's answer is its own search's.
template <class Lanes> void WideTree::searchPacket(const double *const *p, int count, Nearest *io) const
{
    Seeker q[kPacketSize];
    float all[2][3] = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}}, worst = 0;
    for (int i = 0; i < count; ++i) {
        q[i] = Seeker(*this, p[i], io[i]);
        for (int k = 0; k < 3; ++k) {
            all[0][k] = std::min(all[0][k], q[i].lo[k]);
            all[1][k] = std::max(all[1][k], q[i].hi[k]);
        }
        worst = std::max(worst, q[i].limit);
    }
    Entry stack[kStack];
    int top = 0;
    stack[top++] = {0, 0.0f};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.d2 > worst)
            continue;
        const Node &node = mNodes[e.node];
        alignas(32) float d2[kWidth];
        const unsigned mask = Lanes::boxes(node, all[0], all[1], worst, d2);
        if (mask & node.leaf) {
            worst = 0;
            for (int i = 0; i < count; ++i) {
                alignas(32) float own[kWidth];
                unsigned leaves = Lanes::boxes(node, q[i].lo, q[i].hi, q[i].limit, own) & mask & node.leaf;
                if (leaves & node.flat)
                    leaves &= Lanes::discs(node, p[i], q[i].discLimit) | ~unsigned(node.flat);
                if (leaves) {
                    const int first = nearestOf(leaves, own);
                    q[i].leaf<Lanes>(*this, node.child[first]);
                    for (leaves &= ~(1u << first); leaves; leaves &= leaves - 1) {
                        const int k = __builtin_ctz(leaves);
                        if (own[k] <= q[i].limit)
                            q[i].leaf<Lanes>(*this, node.child[k]);
                    }
                }
                worst = std::max(worst, q[i].limit);
            }
        }
        if (const unsigned inner = mask & ~unsigned(node.leaf)) {
            const int first = nearestOf(inner, d2);
            for (unsigned rest = inner & ~(1u << first); rest; rest &= rest - 1) {
                const int k = __builtin_ctz(rest);
                stack[top++] = {node.child[k], d2[k]};
            }
            stack[top++] = {node.child[first], d2[first]};
        }
    }
    for (int i = 0; i < count; ++i)
        io[i] = q[i].best;
}

} // namespace meshsdf
