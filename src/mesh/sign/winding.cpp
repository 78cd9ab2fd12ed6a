// sdftrace — hierarchical generalized winding number (see winding.h).
//
// THE EXPANSION. Over a node's triangles (outward normal n, area element
// dA), the winding number at q is int n . f(x) dA / (4 pi) with
// f(x) = (x - q) / |x - q|^3 = -grad_x G(x), G(x) = 1 / |x - q|. About the
// node's centre c (its area-weighted centroid), with r = c - q, d = x - c,
// the Taylor series of f integrated term by term is (Barill et al. 2018,
// eq. 9-12, there one term shorter by default)
//   N . r / |r|^3                                      (order 1: the dipole)
// + tr M / |r|^3 - 3 r^T M r / |r|^5                    (order 2)
// + 15/2 H[r, r, r] / |r|^7 - 3/2 t . r / |r|^5          (order 3)
// with the moments N_i = int n_i, M_ij = int n_i d_j, H_ijk = int n_i d_j
// d_k (dA), t_k = 2 sum_i H_iik + sum_j H_kjj. Only the symmetric parts of M
// and H enter, so a node keeps kTerms = 23 numbers. A triangle's own
// moments are exact: int d = A (centroid - c), int d d^T = A/12 (sum_v d_v
// d_v^T + s s^T), d_v its corners less c, s their sum. A node's moments are
// its children's moved to its centre: with d = d' + e (e the child's centre
// less the node's), M_ij = M'_ij + N'_i e_j and H_ijk = H'_ijk + M'_ij e_k +
// M'_ik e_j + N'_i e_j e_k.
//
// THE BOUND. Let every vertex of the node lie within R of c and D = |r| > R.
// For |d| < D, G(c + d) = sum_n h_n(d) with h_n(d) = |d|^n P_n(cos g) /
// D^(n+1) (g the angle between d and q - c), h_n a homogeneous harmonic
// polynomial of degree n in d: the groups of the Taylor series by degree.
// Keeping orders 1-3 keeps h_1..h_3 of n . grad G, so the error is
// |sum_{n>3} n . grad h_n| integrated. In spherical coordinates about the
// axis q - c, |grad h_n|^2 = |d|^(2n-2) / D^(2n+2) (n^2 P_n^2 + (dP_n/dg)^2),
// and P_n(cos g) is a cosine polynomial of degree n bounded by 1, so by the
// inequality of van der Corput and Schaake (T^2 + T'^2 / n^2 <= max T^2 for
// a real trigonometric polynomial T of degree n), |grad h_n| <= n |d|^(n-1)
// / D^(n+1). With |d| <= R = x D on the node's triangles (they are the
// convex hulls of their vertices) and A their total area,
//   |error| <= A / (4 pi D^2) sum_{n>=4} n x^(n-1)
//            = A / (4 pi D^2) x^3 (4 - 3x) / (1 - x)^2             (expansionBound).
// Measured against brute force this is 10 (a cap seen from inside) to 500
// (points near a surface) times the error: it proves, but too loosely to
// choose where to expand. So the fast evaluation takes a child's
// expansion where D > kBeta R, a threshold measured to keep the error
// below 5e-3 (tests/test_mesh_winding.cpp), and the exact one sums the
// bound: it expands where x < kExactRatio and the bound is below
// kExactTerm (measured to keep the error below 1e-5), and where the sum of
// the bounds does not keep w on one side of 1/2 it opens the expansions
// with the largest bounds, children for parents, leaves summed exactly,
// until it does: then w > 1/2 exactly when the exact sum is. An exactly
// summed triangle adds kTriangleError to the bound (fastAtan2's 1e-9 rad,
// solid_angles.cpp).
#include "sign/winding.h"

#include "geometry/median_split.h"
#include "geometry/triangle_distance.h"
#include "sign/solid_angles.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SDFT_WINDING_AVX2 1
#endif

namespace meshsdf
{

namespace
{

constexpr double kInv4Pi = 0.07957747154594767; // 1 / (4π)
constexpr uint32_t kLeafSize = 4;
// Subtrees with more triangles than this are built in parallel.
constexpr uint32_t kParallelBuild = 4096;
// The fast evaluation: a child's expansion where D > kBeta R; the side
// pass's where D > kSideBeta R (see FastWinding::side).
constexpr double kBeta = 3.5;
constexpr double kSideBeta = 2.0;
// The exact one: where R < kExactRatio D and its bound is below kExactTerm.
constexpr double kExactRatio = 0.5;
constexpr double kExactTerm = 2e-6;
// Error of one triangle's solid angle over 4 pi: fastAtan2's 1e-9 rad
// doubled (solid_angles.cpp), with room for rounding.
constexpr double kTriangleError = 2e-10;
// Deep enough for any tree of 2^32 triangles: three children wait per level.
constexpr int kStack = 128;

inline Vec3 sub(const double *a, const Vec3 &b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const Vec3 &a, const Vec3 &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm(const Vec3 &a) { return std::sqrt(dot(a, a)); }
inline Vec3 cross(const Vec3 &a, const Vec3 &b)
{
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

inline double triangleAt(const double *t, const Vec3 &q)
{
    const Vec3 a = sub(t, q), b = sub(t + 3, q), c = sub(t + 6, q);
    return solidAngleOver4Pi(a.data(), b.data(), c.data());
}

// The build's node of the binary tree (median splits), with its moments
// about its centre (see THE EXPANSION).
struct BinaryNode {
    uint32_t first, count, right; // triangles; the right child (the left one is next)
    double centre[3], radius, area;
    float lo[3], hi[3];
    double centroidSum[3];    // area-weighted
    double N[3], M[9], H[18]; // H_ijk at i * 6 + sym(j, k)
};

inline bool isLeaf(const BinaryNode &b) { return b.count <= kLeafSize; }

// Index of the symmetric pair (j, k) among xx yy zz xy xz yz.
inline int pairIndex(int j, int k)
{
    static const int table[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
    return table[j][k];
}

// Index of the monomial r_i r_j r_k among xxx yyy zzz xxy xxz xyy yyz xzz yzz xyz.
int cubicIndex(int i, int j, int k)
{
    int c[3] = {0, 0, 0};
    ++c[i];
    ++c[j];
    ++c[k];
    if (c[0] == 3)
        return 0;
    if (c[1] == 3)
        return 1;
    if (c[2] == 3)
        return 2;
    if (c[0] == 2)
        return c[1] ? 3 : 4;
    if (c[1] == 2)
        return c[0] ? 5 : 6;
    if (c[2] == 2)
        return c[0] ? 7 : 8;
    return 9;
}

// How many of `count` triangles (more than a leaf's) go left: half,
// rounded to whole groups of the leaves' solid angles (solid_angles.h), so
// that leaves fill their groups.
uint32_t leftCount(uint32_t count)
{
    const uint32_t lanes = kSolidAngleLanes;
    return std::min(std::max(lanes, (count / 2 + lanes / 2) / lanes * lanes), count - 1);
}

// Nodes of the binary subtree over `count` triangles: the shape depends on
// the count alone.
uint32_t subtreeNodes(uint32_t count)
{
    return count <= kLeafSize ? 1 : 1 + subtreeNodes(leftCount(count)) + subtreeNodes(count - leftCount(count));
}

// The 23 terms of a node's expansion (see THE EXPANSION): the dipole (0-2),
// tr M (3), M symmetrized as the coefficients of r^T M r (4-9: xx yy zz xy
// xz yz), t (10-12) and H symmetrized as the coefficients of H[r, r, r]
// (13-22).
void expansionTerms(const BinaryNode &b, double *terms)
{
    for (int i = 0; i < 3; ++i)
        terms[i] = b.N[i];
    const double *M = b.M;
    terms[3] = M[0] + M[4] + M[8];
    terms[4] = M[0];
    terms[5] = M[4];
    terms[6] = M[8];
    terms[7] = M[1] + M[3];
    terms[8] = M[2] + M[6];
    terms[9] = M[5] + M[7];
    auto H = [&](int i, int j, int k) { return b.H[i * 6 + pairIndex(j, k)]; };
    for (int k = 0; k < 3; ++k) {
        terms[10 + k] = 0;
        for (int i = 0; i < 3; ++i)
            terms[10 + k] += 2 * H(i, i, k) + H(k, i, i);
    }
    std::fill(terms + 13, terms + 23, 0.0);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                terms[13 + cubicIndex(i, j, k)] += H(i, j, k);
}

// Four lanes of doubles, element by element in IEEE arithmetic whatever the
// instructions: the same answers with AVX2 or without. (GCC warns that
// passing them by value without AVX differs from the ABI with it: these
// functions are all inline in this file.)
#pragma GCC diagnostic ignored "-Wpsabi"
typedef double V4 __attribute__((vector_size(32)));
typedef long long M4 __attribute__((vector_size(32)));

inline V4 load(const double (&a)[4])
{
    V4 v;
    std::memcpy(&v, a, sizeof v);
    return v;
}
inline V4 splat(double x) { return V4{x, x, x, x}; }

// sqrt and the sign mask, without vector instructions (compiled for any
// x86-64: SSE2, two lanes at a time) or with AVX2.
struct PlainLanes {
    static V4 sqrt(const V4 &x) { return V4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])}; }
    static unsigned mask(const M4 &m) { return unsigned((m[0] & 1) | (m[1] & 2) | (m[2] & 4) | (m[3] & 8)); }
};
#ifdef SDFT_WINDING_AVX2
#define SDFT_WINDING_AVX2_INLINE __attribute__((target("avx2"))) inline
struct Avx2Lanes {
    SDFT_WINDING_AVX2_INLINE static V4 sqrt(const V4 &x) { return _mm256_sqrt_pd(x); }
    SDFT_WINDING_AVX2_INLINE static unsigned mask(const M4 &m) { return unsigned(_mm256_movemask_pd(__m256d(m))); }
};
#endif

// The expansions of a node's four children at r = centre - q (d2 = |r|^2),
// each over 4 pi (see THE EXPANSION).
template <class Lanes, class Node>
inline V4 farField(const Node &n, const V4 &rx, const V4 &ry, const V4 &rz, const V4 &d2)
{
    const V4 inv = splat(1.0) / Lanes::sqrt(d2), inv2 = inv * inv, inv3 = inv2 * inv;
    const V4 xx = rx * rx, yy = ry * ry, zz = rz * rz, xy = rx * ry, xz = rx * rz, yz = ry * rz;
    auto t = [&](int k) { return load(n.terms[k]); };
    const V4 order1 = t(0) * rx + t(1) * ry + t(2) * rz;
    const V4 rMr = t(4) * xx + t(5) * yy + t(6) * zz + t(7) * xy + t(8) * xz + t(9) * yz;
    const V4 tr = t(10) * rx + t(11) * ry + t(12) * rz;
    const V4 cube = rx * (t(13) * xx + t(16) * xy + t(17) * xz + t(18) * yy + t(22) * yz + t(20) * zz) +
                    ry * (t(14) * yy + t(19) * yz + t(21) * zz) + t(15) * zz * rz;
    const V4 order2 = t(3) - splat(3.0) * rMr * inv2;
    const V4 order3 = (splat(7.5) * cube * inv2 - splat(1.5) * tr) * inv2;
    return (order1 + order2 + order3) * inv3 * splat(kInv4Pi);
}

// The bound of THE BOUND at x = R / D < 1 for each lane, area A.
inline V4 expansionBound(const V4 &area, const V4 &x, const V4 &d2)
{
    const V4 one = splat(1.0), rest = one - x;
    return area * splat(kInv4Pi) / d2 * x * x * x * (splat(4.0) - splat(3.0) * x) / (rest * rest);
}

} // namespace

double triangleWinding(const Vec3 &a, const Vec3 &b, const Vec3 &c, const Vec3 &q)
{
    const Vec3 x = sub(a.data(), q), y = sub(b.data(), q), z = sub(c.data(), q);
    return solidAngleOver4Pi(x.data(), y.data(), z.data());
}

FastWinding::FastWinding(const std::vector<std::array<float, 3>> &points,
                         const std::vector<std::array<uint32_t, 3>> &tris, bool simd)
    : mVectorized(simd && solidAnglesVectorized())
{
    const uint32_t n = static_cast<uint32_t>(tris.size());
    if (n == 0)
        return;
    std::vector<Vec3> centroids(n);
    std::vector<uint32_t> order(n);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 4096), [&](const tbb::blocked_range<uint32_t> &r) {
        for (uint32_t t = r.begin(); t != r.end(); ++t) {
            order[t] = t;
            for (int k = 0; k < 3; ++k)
                centroids[t][k] = (double(points[tris[t][0]][k]) + points[tris[t][1]][k] + points[tris[t][2]][k]) / 3.0;
        }
    });
    // The binary tree: median splits, each subtree's nodes in preorder after
    // its root, so that both halves are built at once.
    std::vector<BinaryNode> bin(subtreeNodes(n));
    auto shape = [&](auto &&self, uint32_t index, uint32_t first, uint32_t count) -> void {
        BinaryNode &b = bin[index];
        b.first = first;
        b.count = count;
        b.right = 0;
        if (count <= kLeafSize)
            return;
        const uint32_t half = leftCount(count);
        splitAt(order, first, count, half, centroids);
        b.right = index + 1 + subtreeNodes(half);
        auto left = [&] { self(self, index + 1, first, half); };
        auto right = [&] { self(self, b.right, first + half, count - half); };
        if (count > kParallelBuild)
            tbb::parallel_invoke(left, right);
        else {
            left();
            right();
        }
    };
    shape(shape, 0, 0, n);

    mTris.resize(size_t(n) * 9);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 4096), [&](const tbb::blocked_range<uint32_t> &r) {
        for (uint32_t i = r.begin(); i != r.end(); ++i)
            for (int v = 0; v < 3; ++v)
                for (int k = 0; k < 3; ++k)
                    mTris[size_t(i) * 9 + v * 3 + k] = points[tris[order[i]][v]][k];
    });

    // Moments bottom-up (THE EXPANSION): a leaf's from its triangles, an
    // inner node's from its children's.
    auto leafMoments = [&](BinaryNode &b) {
        b.area = 0;
        for (int k = 0; k < 3; ++k) {
            b.centroidSum[k] = 0;
            b.lo[k] = INFINITY;
            b.hi[k] = -INFINITY;
        }
        for (uint32_t i = b.first; i < b.first + b.count; ++i) {
            const double *t = &mTris[size_t(i) * 9];
            const double ta = 0.5 * norm(cross(sub(t + 3, {t[0], t[1], t[2]}), sub(t + 6, {t[0], t[1], t[2]})));
            b.area += ta;
            for (int k = 0; k < 3; ++k) {
                b.centroidSum[k] += ta * (t[k] + t[3 + k] + t[6 + k]) / 3.0;
                for (int v = 0; v < 3; ++v) {
                    b.lo[k] = std::min(b.lo[k], float(t[v * 3 + k]));
                    b.hi[k] = std::max(b.hi[k], float(t[v * 3 + k]));
                }
            }
        }
        for (int k = 0; k < 3; ++k)
            b.centre[k] = b.area > 0 ? b.centroidSum[k] / b.area : 0.5 * (double(b.lo[k]) + b.hi[k]);
        std::fill(b.N, b.N + 3, 0.0);
        std::fill(b.M, b.M + 9, 0.0);
        std::fill(b.H, b.H + 18, 0.0);
        for (uint32_t i = b.first; i < b.first + b.count; ++i) {
            const double *t = &mTris[size_t(i) * 9];
            const Vec3 av = cross(sub(t + 3, {t[0], t[1], t[2]}), sub(t + 6, {t[0], t[1], t[2]}));
            double d[3][3], s[3] = {0, 0, 0};
            for (int v = 0; v < 3; ++v)
                for (int k = 0; k < 3; ++k) {
                    d[v][k] = t[v * 3 + k] - b.centre[k];
                    s[k] += d[v][k];
                }
            for (int i2 = 0; i2 < 3; ++i2) {
                const double Ni = 0.5 * av[i2]; // the area vector
                b.N[i2] += Ni;
                for (int j = 0; j < 3; ++j)
                    b.M[i2 * 3 + j] += Ni * s[j] / 3.0;
                for (int j = 0; j < 3; ++j)
                    for (int k = j; k < 3; ++k)
                        b.H[i2 * 6 + pairIndex(j, k)] +=
                            Ni * (d[0][j] * d[0][k] + d[1][j] * d[1][k] + d[2][j] * d[2][k] + s[j] * s[k]) / 12.0;
            }
        }
    };
    auto merge = [&](BinaryNode &b, const BinaryNode &l, const BinaryNode &r) {
        b.area = l.area + r.area;
        for (int k = 0; k < 3; ++k) {
            b.centroidSum[k] = l.centroidSum[k] + r.centroidSum[k];
            b.lo[k] = std::min(l.lo[k], r.lo[k]);
            b.hi[k] = std::max(l.hi[k], r.hi[k]);
            b.centre[k] = b.area > 0 ? b.centroidSum[k] / b.area : 0.5 * (double(b.lo[k]) + b.hi[k]);
        }
        std::fill(b.N, b.N + 3, 0.0);
        std::fill(b.M, b.M + 9, 0.0);
        std::fill(b.H, b.H + 18, 0.0);
        for (const BinaryNode *c : {&l, &r}) {
            double e[3];
            for (int k = 0; k < 3; ++k)
                e[k] = c->centre[k] - b.centre[k];
            for (int i = 0; i < 3; ++i) {
                b.N[i] += c->N[i];
                for (int j = 0; j < 3; ++j)
                    b.M[i * 3 + j] += c->M[i * 3 + j] + c->N[i] * e[j];
                for (int j = 0; j < 3; ++j)
                    for (int k = j; k < 3; ++k)
                        b.H[i * 6 + pairIndex(j, k)] += c->H[i * 6 + pairIndex(j, k)] + c->M[i * 3 + j] * e[k] +
                                                        c->M[i * 3 + k] * e[j] + c->N[i] * e[j] * e[k];
            }
        }
    };
    auto summarize = [&](auto &&self, uint32_t index) -> void {
        BinaryNode &b = bin[index];
        if (isLeaf(b)) {
            leafMoments(b);
            return;
        }
        if (b.count > kParallelBuild)
            tbb::parallel_invoke([&] { self(self, index + 1); }, [&] { self(self, b.right); });
        else {
            self(self, index + 1);
            self(self, b.right);
        }
        merge(b, bin[index + 1], bin[b.right]);
    };
    summarize(summarize, 0);
    // Each node's radius: the farthest of its vertices from its centre.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, bin.size(), 64), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t index = r.begin(); index != r.end(); ++index) {
            BinaryNode &b = bin[index];
            double r2 = 0;
            for (uint32_t i = b.first; i < b.first + b.count; ++i)
                for (int v = 0; v < 3; ++v) {
                    const double *p = &mTris[size_t(i) * 9 + v * 3];
                    const double dx = p[0] - b.centre[0], dy = p[1] - b.centre[1], dz = p[2] - b.centre[2];
                    r2 = std::max(r2, dx * dx + dy * dy + dz * dz);
                }
            b.radius = std::sqrt(r2) * (1 + 1e-12); // room for rounding
        }
    });

    // Four children to a node: a binary node's two, each inner one of them
    // replaced by its own two, the one with the most triangles first.
    auto collapse = [&](auto &&self, uint32_t root) -> uint32_t {
        uint32_t lanes[4];
        int count = 0;
        if (isLeaf(bin[root]))
            lanes[count++] = root;
        else {
            lanes[count++] = root + 1;
            lanes[count++] = bin[root].right;
        }
        while (count < 4) {
            int widest = -1;
            for (int l = 0; l < count; ++l)
                if (!isLeaf(bin[lanes[l]]) && (widest < 0 || bin[lanes[l]].count > bin[lanes[widest]].count))
                    widest = l;
            if (widest < 0)
                break;
            const uint32_t b = lanes[widest];
            for (int l = count; l > widest + 1; --l)
                lanes[l] = lanes[l - 1];
            lanes[widest] = b + 1;
            lanes[widest + 1] = bin[b].right;
            ++count;
        }
        const uint32_t index = uint32_t(mNodes.size());
        mNodes.emplace_back();
        {
            Node4 &node = mNodes[index];
            std::memset(&node, 0, sizeof node);
            for (int l = 0; l < 4; ++l) {
                node.radius2[l] = node.radius[l] = INFINITY; // no child: never expanded
                for (int k = 0; k < 3; ++k) {
                    node.lo[k][l] = INFINITY;
                    node.hi[k][l] = -INFINITY;
                }
            }
            for (int l = 0; l < count; ++l) {
                const BinaryNode &b = bin[lanes[l]];
                double terms[kTerms];
                expansionTerms(b, terms);
                for (int t = 0; t < kTerms; ++t)
                    node.terms[t][l] = terms[t];
                for (int k = 0; k < 3; ++k) {
                    node.centre[k][l] = b.centre[k];
                    node.lo[k][l] = b.lo[k];
                    node.hi[k][l] = b.hi[k];
                }
                node.radius[l] = b.radius;
                node.radius2[l] = b.radius * b.radius;
                node.area[l] = b.area;
                if (isLeaf(b)) {
                    node.leaves |= 1u << l;
                    node.child[l] = uint32_t(mLeaves.size());
                    mLeaves.push_back({b.first, b.count, 0});
                }
            }
        }
        for (int l = 0; l < count; ++l)
            if (!isLeaf(bin[lanes[l]])) {
                const uint32_t child = self(self, lanes[l]);
                mNodes[index].inner |= 1u << l;
                mNodes[index].child[l] = child;
            }
        return index;
    };
    mNodes.reserve(bin.size() / 2 + 1);
    collapse(collapse, 0);

    // Each leaf's triangles again, four to a group (solid_angles.h); lanes
    // past the last repeat its first triangle.
    size_t groupDoubles = 0;
    for (Leaf &leaf : mLeaves) {
        leaf.groups = uint32_t(groupDoubles);
        groupDoubles += size_t((leaf.count + kSolidAngleLanes - 1) / kSolidAngleLanes) * kSolidAngleGroup;
    }
    mLeafGroups.resize(groupDoubles);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, mLeaves.size(), 256), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t index = r.begin(); index != r.end(); ++index) {
            const Leaf &leaf = mLeaves[index];
            const uint32_t lanes = (leaf.count + kSolidAngleLanes - 1) / kSolidAngleLanes * kSolidAngleLanes;
            double *groups = &mLeafGroups[leaf.groups];
            for (uint32_t i = 0; i < lanes; ++i) {
                const double *t = &mTris[size_t(leaf.first + (i < leaf.count ? i : 0)) * 9];
                for (int k = 0; k < 9; ++k)
                    groups[(i / kSolidAngleLanes) * kSolidAngleGroup + k * kSolidAngleLanes + i % kSolidAngleLanes] =
                        t[k];
            }
        }
    });
    mOrder = std::move(order);
}

double FastWinding::leafExact(uint32_t leaf, const Vec3 &q) const
{
    const Leaf &l = mLeaves[leaf];
    return solidAnglesOver4Pi(&mLeafGroups[l.groups], int(l.count), q.data(), mVectorized);
}

// Depth first: each child's expansion where it is far enough (D > beta R,
// beta2 = beta^2), a near leaf's triangles exactly, a near inner child's
// children in turn. The expansions are summed lane by lane and the lanes at
// the end, in the same order with or without AVX2.
template <class Lanes> double FastWinding::fast(const Vec3 &q, double beta2) const
{
    const V4 qx = splat(q[0]), qy = splat(q[1]), qz = splat(q[2]);
    V4 far = splat(0.0);
    double exact = 0;
    uint32_t stack[kStack];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node4 &node = mNodes[stack[--top]];
        const V4 rx = load(node.centre[0]) - qx, ry = load(node.centre[1]) - qy, rz = load(node.centre[2]) - qz;
        const V4 d2 = rx * rx + ry * ry + rz * rz;
        const M4 expand = d2 > load(node.radius2) * splat(beta2);
        const unsigned expanded = Lanes::mask(expand);
        if (expanded)
            far += expand ? farField<Lanes>(node, rx, ry, rz, d2) : splat(0.0);
        for (unsigned near = node.leaves & ~expanded; near; near &= near - 1)
            exact += leafExact(node.child[__builtin_ctz(near)], q);
        for (unsigned inner = node.inner & ~expanded; inner; inner &= ~(1u << (31 - __builtin_clz(inner))))
            stack[top++] = node.child[31 - __builtin_clz(inner)]; // the last lane first, so the first is next
    }
    return exact + ((far[0] + far[1]) + (far[2] + far[3]));
}

#ifdef SDFT_WINDING_AVX2
__attribute__((target("avx2"), flatten)) double FastWinding::fastAvx2(const Vec3 &q, double beta2) const
{
    return fast<Avx2Lanes>(q, beta2);
}
__attribute__((target("avx2"), flatten)) WindingValue FastWinding::boundedAvx2(const Vec3 &q, double ratio,
                                                                               double term) const
{
    return bounded<Avx2Lanes>(q, ratio, term);
}
#else
double FastWinding::fastAvx2(const Vec3 &q, double beta2) const { return fast<PlainLanes>(q, beta2); }
WindingValue FastWinding::boundedAvx2(const Vec3 &q, double ratio, double term) const
{
    return bounded<PlainLanes>(q, ratio, term);
}
#endif

double FastWinding::fastAt(const Vec3 &q, double beta) const
{
    if (mNodes.empty())
        return 0.0;
    return mVectorized ? fastAvx2(q, beta * beta) : fast<PlainLanes>(q, beta * beta);
}

double FastWinding::operator()(const Vec3 &q) const { return fastAt(q, kBeta); }

WindingValue FastWinding::side(const Vec3 &q, WindingAccuracy accuracy) const
{
    if (accuracy == WindingAccuracy::Exact) // the coarse pass's expansions, proven
        return boundedAt(q, 1 / kSideBeta, INFINITY);
    const double w = fastAt(q, kSideBeta);
    if (std::abs(w - 0.5) > kSideMargin)
        return {w, kSideMargin};
    return {fastAt(q, kBeta), kFastMargin};
}

WindingValue FastWinding::exact(const Vec3 &q) const { return boundedAt(q, kExactRatio, kExactTerm); }

WindingValue FastWinding::boundedAt(const Vec3 &q, double ratio, double term) const
{
    if (mNodes.empty())
        return {0.0, 0.0};
    return mVectorized ? boundedAvx2(q, ratio, term) : bounded<PlainLanes>(q, ratio, term);
}

// The evaluation with a proven bound (see THE BOUND): first depth first, a
// child's expansion where x < ratio and its bound is below term (exact():
// kExactRatio, kExactTerm; side(): the coarse pass's ratio, any bound);
// then, while the bounds do not keep w on one side of 1/2, the expansion
// with the largest bound replaced by its children's (or its leaf's
// triangles).
template <class Lanes> WindingValue FastWinding::bounded(const Vec3 &q, double ratio, double term) const
{
    struct Entry {
        double bound, value;
        uint32_t node, lane;
        bool operator<(const Entry &o) const { return bound < o.bound; }
    };
    thread_local std::vector<Entry> frontier;
    frontier.clear();
    const V4 qx = splat(q[0]), qy = splat(q[1]), qz = splat(q[2]);
    double exact = 0, rounding = 0;
    uint32_t stack[kStack];
    int top = 0;
    auto sumLeaf = [&](uint32_t leaf) {
        exact += leafExact(leaf, q);
        rounding += mLeaves[leaf].count * kTriangleError;
    };
    // Expands node's children in `take` onto the frontier; the rest near
    // enough to need it: leaves summed, inner children onto the stack.
    auto visit = [&](uint32_t index, double ratio, double term) {
        const Node4 &node = mNodes[index];
        const V4 rx = load(node.centre[0]) - qx, ry = load(node.centre[1]) - qy, rz = load(node.centre[2]) - qz;
        const V4 d2 = rx * rx + ry * ry + rz * rz;
        const V4 radius = load(node.radius);
        unsigned take = Lanes::mask(d2 * splat(ratio * ratio) > radius * radius);
        if (take) {
            const V4 x = radius / Lanes::sqrt(d2);
            const V4 bound = expansionBound(load(node.area), x, d2);
            take &= Lanes::mask(bound <= splat(term));
            if (take) {
                const V4 value = farField<Lanes>(node, rx, ry, rz, d2);
                for (unsigned m = take; m; m &= m - 1) {
                    const int l = __builtin_ctz(m);
                    frontier.push_back({bound[l], value[l], index, uint32_t(l)});
                }
            }
        }
        for (unsigned near = node.leaves & ~take; near; near &= near - 1)
            sumLeaf(node.child[__builtin_ctz(near)]);
        for (int l = 3; l >= 0; --l)
            if ((node.inner & ~take) >> l & 1)
                stack[top++] = node.child[l];
    };
    stack[top++] = 0;
    while (top > 0)
        visit(stack[--top], ratio, term);
    double far = 0, bound = 0;
    for (const Entry &e : frontier) {
        far += e.value;
        bound += e.bound;
    }
    if (std::abs(exact + far - 0.5) > bound + rounding)
        return {exact + far, bound + rounding};
    // The largest bound first, any expansion that converges (x < 1) taken.
    std::make_heap(frontier.begin(), frontier.end());
    while (!frontier.empty() && !(std::abs(exact + far - 0.5) > bound + rounding)) {
        std::pop_heap(frontier.begin(), frontier.end());
        const Entry e = frontier.back();
        frontier.pop_back();
        far -= e.value;
        bound = std::max(bound - e.bound, 0.0);
        const Node4 &node = mNodes[e.node];
        if (node.leaves >> e.lane & 1) {
            sumLeaf(node.child[e.lane]);
            continue;
        }
        stack[top++] = node.child[e.lane];
        while (top > 0) {
            const size_t first = frontier.size();
            visit(stack[--top], 1.0, INFINITY);
            for (size_t i = first; i < frontier.size(); ++i) {
                far += frontier[i].value;
                bound += frontier[i].bound;
                std::push_heap(frontier.begin(), frontier.begin() + ptrdiff_t(i) + 1);
            }
        }
    }
    // The sums afresh: the running ones drift by rounding.
    far = bound = 0;
    for (const Entry &e : frontier) {
        far += e.value;
        bound += e.bound;
    }
    return {exact + far, bound + rounding};
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
    double best = bound * bound;
    // Each entry carries its box's squared distance, computed when its
    // parent was searched.
    struct Entry {
        uint32_t node;
        double d2;
    };
    Entry stack[kStack];
    int top = 0;
    stack[top++] = {0, 0.0};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.d2 >= best)
            continue;
        const Node4 &node = mNodes[e.node];
        double d2[4];
        for (int l = 0; l < 4; ++l) {
            d2[l] = 0;
            for (int k = 0; k < 3; ++k) {
                const double d = std::max({double(node.lo[k][l]) - q[k], 0.0, q[k] - double(node.hi[k][l])});
                d2[l] += d * d;
            }
        }
        for (unsigned m = node.leaves; m; m &= m - 1) {
            const int l = __builtin_ctz(m);
            if (d2[l] >= best)
                continue;
            const Leaf &leaf = mLeaves[node.child[l]];
            for (uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
                const double t2 = triangleDistance2(&mTris[size_t(i) * 9], q.data());
                if (t2 < best) {
                    best = t2;
                    if (nearest)
                        *nearest = mOrder[i];
                }
            }
        }
        // The inner children, the nearest searched first (pushed last):
        // farthest first by insertion.
        Entry inner[4];
        int count = 0;
        for (unsigned m = node.inner; m; m &= m - 1) {
            const int l = __builtin_ctz(m);
            int i = count++;
            for (; i > 0 && inner[i - 1].d2 < d2[l]; --i)
                inner[i] = inner[i - 1];
            inner[i] = {node.child[l], d2[l]};
        }
        for (int i = 0; i < count; ++i)
            if (inner[i].d2 < best)
                stack[top++] = inner[i];
    }
    return std::sqrt(best);
}

} // namespace meshsdf
