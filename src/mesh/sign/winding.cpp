// sdftrace — hierarchical generalized winding number (see winding.h).
#include "sign/winding.h"

#include "geometry/median_split.h"
#include "geometry/triangle_distance.h"
#include "sign/solid_angles.h"

#include <algorithm>
#include <cmath>

namespace meshsdf
{

namespace
{

constexpr double kInv4Pi = 0.07957747154594767; // 1 / (4π)
constexpr uint32_t kLeafSize = 8;

inline Vec3 sub(const double *a, const Vec3 &b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const Vec3 &a, const Vec3 &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm(const Vec3 &a) { return std::sqrt(dot(a, a)); }
inline Vec3 cross(const Vec3 &a, const Vec3 &b)
{
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Van Oosterom–Strackee on the corner vectors a, b, c (corners minus q).
inline double solidAngleOver4Pi(const Vec3 &a, const Vec3 &b, const Vec3 &c)
{
    return meshsdf::solidAngleOver4Pi(a.data(), b.data(), c.data());
}

inline double triangleAt(const double *t, const Vec3 &q)
{
    return solidAngleOver4Pi(sub(t, q), sub(t + 3, q), sub(t + 6, q));
}

} // namespace

double triangleWinding(const Vec3 &a, const Vec3 &b, const Vec3 &c, const Vec3 &q)
{
    return solidAngleOver4Pi(sub(a.data(), q), sub(b.data(), q), sub(c.data(), q));
}

FastWinding::FastWinding(const std::vector<std::array<float, 3>> &points,
                         const std::vector<std::array<uint32_t, 3>> &tris, double beta, bool simd)
    : mBeta2(beta * beta), mVectorized(simd && solidAnglesVectorized())
{
    const uint32_t n = static_cast<uint32_t>(tris.size());
    std::vector<Vec3> centroids(n);
    for (uint32_t t = 0; t < n; ++t)
        for (int k = 0; k < 3; ++k)
            centroids[t][k] = (double(points[tris[t][0]][k]) + points[tris[t][1]][k] + points[tris[t][2]][k]) / 3.0;
    std::vector<uint32_t> order(n);
    for (uint32_t t = 0; t < n; ++t)
        order[t] = t;
    mNodes.reserve(n / kLeafSize * 2 + 2);
    if (n > 0)
        build(0, n, order, centroids);

    mTris.resize(size_t(n) * 9);
    for (uint32_t i = 0; i < n; ++i)
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k)
                mTris[size_t(i) * 9 + v * 3 + k] = points[tris[order[i]][v]][k];
    for (Node &node : mNodes)
        summarize(node);
    // Each leaf's triangles again, four to a group (solid_angles.h); lanes
    // past the last repeat its first triangle.
    for (Node &node : mNodes) {
        if (node.count > kLeafSize)
            continue;
        node.groups = uint32_t(mLeafGroups.size());
        const uint32_t lanes = (node.count + kSolidAngleLanes - 1) / kSolidAngleLanes * kSolidAngleLanes;
        mLeafGroups.resize(mLeafGroups.size() + size_t(lanes) * 9);
        double *groups = &mLeafGroups[node.groups];
        for (uint32_t i = 0; i < lanes; ++i) {
            const double *t = &mTris[size_t(node.first + (i < node.count ? i : 0)) * 9];
            for (int k = 0; k < 9; ++k)
                groups[(i / kSolidAngleLanes) * kSolidAngleGroup + k * kSolidAngleLanes + i % kSolidAngleLanes] = t[k];
        }
    }
    mOrder = std::move(order);
}

// Splits [first, first + count) of `order` at the median (median_split.h).
// Returns the node's index.
uint32_t FastWinding::build(uint32_t first, uint32_t count, std::vector<uint32_t> &order,
                            const std::vector<Vec3> &centroids)
{
    const uint32_t index = static_cast<uint32_t>(mNodes.size());
    mNodes.push_back(Node{});
    mNodes[index].first = first;
    mNodes[index].count = count;
    if (count <= kLeafSize)
        return index;

    const uint32_t half = splitAtMedian(order, first, count, centroids);
    const uint32_t left = build(first, half, order, centroids);
    const uint32_t right = build(first + half, count - half, order, centroids);
    mNodes[index].left = left;
    mNodes[index].right = right;
    return index;
}

// Far-field data of a node from its triangles: area-weighted centre, the sum
// of area vectors (order 1), the second-order moment and the radius.
void FastWinding::summarize(Node &node) const
{
    double area = 0, centre[3] = {0, 0, 0};
    std::vector<std::pair<Vec3, Vec3>> moments; // (area vector, centroid)
    moments.reserve(node.count);
    for (int k = 0; k < 3; ++k) {
        node.lo[k] = INFINITY;
        node.hi[k] = -INFINITY;
    }
    for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const double *t = &mTris[size_t(i) * 9];
        const Vec3 a{t[0], t[1], t[2]};
        const Vec3 e1 = sub(t + 3, a), e2 = sub(t + 6, a);
        Vec3 av = cross(e1, e2);
        for (double &x : av)
            x *= 0.5;
        const double ta = norm(av);
        Vec3 c;
        for (int k = 0; k < 3; ++k) {
            c[k] = (t[k] + t[3 + k] + t[6 + k]) / 3.0;
            centre[k] += ta * c[k];
            for (int v = 0; v < 3; ++v) {
                node.lo[k] = std::min(node.lo[k], float(t[v * 3 + k]));
                node.hi[k] = std::max(node.hi[k], float(t[v * 3 + k]));
            }
        }
        area += ta;
        moments.emplace_back(av, c);
    }
    for (int k = 0; k < 3; ++k)
        node.centre[k] = area > 0 ? centre[k] / area : 0.5 * (double(node.lo[k]) + node.hi[k]);
    std::fill(node.dipole, node.dipole + 3, 0.0);
    std::fill(node.second, node.second + 9, 0.0);
    for (const auto &m : moments)
        for (int i = 0; i < 3; ++i) {
            node.dipole[i] += m.first[i];
            for (int j = 0; j < 3; ++j)
                node.second[i * 3 + j] += m.first[i] * (m.second[j] - node.centre[j]);
        }
    double r2 = 0;
    for (uint32_t i = node.first; i < node.first + node.count; ++i)
        for (int v = 0; v < 3; ++v) {
            const double *p = &mTris[size_t(i) * 9 + v * 3];
            const double dx = p[0] - node.centre[0], dy = p[1] - node.centre[1], dz = p[2] - node.centre[2];
            r2 = std::max(r2, dx * dx + dy * dy + dz * dz);
        }
    node.radius2 = mBeta2 * r2;
}

double FastWinding::operator()(const Vec3 &q) const
{
    if (mNodes.empty())
        return 0.0;
    double w = 0.0;
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node &node = mNodes[stack[--top]];
        const double rx = node.centre[0] - q[0], ry = node.centre[1] - q[1], rz = node.centre[2] - q[2];
        const double d2 = rx * rx + ry * ry + rz * rz;
        if (d2 > node.radius2) {
            // Far field: dipole A·r/|r|^3 plus the order-2 term
            // tr(M)/|r|^3 - 3 rᵀMr/|r|^5 (Barill et al. 2018, eq. 9-10).
            const double inv = 1.0 / std::sqrt(d2), inv3 = inv * inv * inv, inv5 = inv3 * inv * inv;
            const double *m = node.second;
            const double r[3] = {rx, ry, rz};
            double rMr = 0;
            for (int i = 0; i < 3; ++i)
                rMr += r[i] * (m[i * 3] * r[0] + m[i * 3 + 1] * r[1] + m[i * 3 + 2] * r[2]);
            const double order1 = (node.dipole[0] * rx + node.dipole[1] * ry + node.dipole[2] * rz) * inv3;
            const double order2 = (m[0] + m[4] + m[8]) * inv3 - 3.0 * rMr * inv5;
            w += (order1 + order2) * kInv4Pi;
        } else if (node.count <= kLeafSize) {
            w += solidAnglesOver4Pi(&mLeafGroups[node.groups], int(node.count), q.data(), mVectorized);
        } else {
            stack[top++] = node.left;
            stack[top++] = node.right;
        }
    }
    return w;
}

double FastWinding::bruteForce(const Vec3 &q) const
{
    double w = 0.0;
    for (size_t i = 0; i < mTris.size(); i += 9)
        w += triangleAt(&mTris[i], q);
    return w;
}

double FastWinding::distance(const Vec3 &q, double bound, uint32_t *nearest) const
{
    if (mNodes.empty())
        return bound;
    auto boxDistance2 = [&](const Node &n) {
        double d2 = 0;
        for (int k = 0; k < 3; ++k) {
            const double d = std::max({double(n.lo[k]) - q[k], 0.0, q[k] - double(n.hi[k])});
            d2 += d * d;
        }
        return d2;
    };
    double best = bound * bound;
    // Each entry carries its box's squared distance, computed once when its
    // parent ordered the children.
    struct Entry {
        uint32_t node;
        double d2;
    };
    Entry stack[64];
    int top = 0;
    stack[top++] = {0, boxDistance2(mNodes[0])};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.d2 >= best)
            continue;
        const Node &node = mNodes[e.node];
        if (node.count <= kLeafSize) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                const double d2 = triangleDistance2(&mTris[size_t(i) * 9], q.data());
                if (d2 < best) {
                    best = d2;
                    if (nearest)
                        *nearest = mOrder[i];
                }
            }
        } else {
            // Push the farther child first so the nearer one is searched first.
            const double dl = boxDistance2(mNodes[node.left]), dr = boxDistance2(mNodes[node.right]);
            if (dl < dr) {
                stack[top++] = {node.right, dr};
                stack[top++] = {node.left, dl};
            } else {
                stack[top++] = {node.left, dl};
                stack[top++] = {node.right, dr};
            }
        }
    }
    return std::sqrt(best);
}

} // namespace meshsdf
