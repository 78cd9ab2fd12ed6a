// sdftrace — the sign of every voxel by the winding number (see
// winding_sign.h).
//
// The winding number w off the mesh is the scalar potential of a unit
// current around each triangle's boundary, so its gradient is the
// Biot–Savart field of the edges where those currents do not cancel:
// boundary and non-manifold edges and edges between inconsistently oriented
// triangles (an edge used k times a->b and l times b->a carries k - l). For
// a closed, consistently oriented mesh there are none and w is constant on
// each connected region off the mesh.
//
// A straight edge of length L carrying current 1 has, at a point x at
// distance d from the segment and rho from its line,
//   |B(x)| = |cos a1 - cos a2| / (4 pi rho)    (a1, a2: angles to its ends).
// If the foot of the perpendicular lies on the segment, rho = d and
// |cos a1 - cos a2| <= 2, so |B| <= 1 / (2 pi d). If not, with the ends at
// 0 < s1 < s2 along the line from the foot, d^2 = rho^2 + s1^2 and
// |cos a1 - cos a2| < 1 - s1 / d <= rho^2 / d^2, so |B| <= 1 / (4 pi d).
// Integrating |dl x r| / |r|^3 <= 1 / d^2 over the edge gives L / (4 pi d^2).
// Hence |grad w(x)| <= sum over open edges of |k - l| f(dist(x, edge)), with
// f(d) = min(L / (4 pi d^2), 1 / (2 pi d)) (edgeField), decreasing in d, so a
// lower bound on the distance gives an upper bound on the field.
//
// A group of edges far away (EdgeField). Let currents c_e flow along edges
// a_e -> b_e, all within R of a centre c, with chord T = sum c_e (b_e - a_e)
// and mass M = sum c_e L_e. With f(r) = r / |r|^3,
//   B(x) = 1/(4 pi) sum c_e int_e dl x f(x - y)
//        = 1/(4 pi) [T x f(x - c) + sum c_e int_e dl x (f(x - y) - f(x - c))].
// The Jacobian of f is (I - 3 r r^T / |r|^2) / |r|^3, of norm 2 / |r|^3, and
// the segment from x - c to x - y keeps at least D - R from 0 when D = |x - c|
// > R (c and y lie in the ball of radius R about c), so |f(x - y) - f(x - c)|
// <= 2 R / (D - R)^3 and
//   |B(x)| <= (|T| / D^2 + 2 M R / (D - R)^3) / (4 pi),
// decreasing in D. For a closed loop T = 0 and the bound falls off as 1/D^3,
// where the sum edge by edge falls off as M/D^2. EdgeField keeps a tree of
// groups (median splits of the edges) and takes a group's bound, at a lower
// bound of D over the region, where it is smaller than the edges could give
// one by one; a leaf is one edge and its bound above.
//
// The exact field of one edge at p (segmentField) is the closed form of the
// Biot-Savart integral, (ra x rb) (|ra| + |rb|) / (|ra| |rb| (|ra| |rb| +
// ra . rb)) / (4 pi) with ra = p - a, rb = p - b; grad w = +-B with one sign
// for all edges (each is directed along its net current).
//
// Along a step from a to b = a + l t (|t| = 1) that crosses no mesh point,
// w(b) - w(a) = int_0^l g(s) ds with g(s) = grad w(a + s t) . t, and the
// trapezoid rule gives |int g| <= l |g(0) + g(l)| / 2 + l^3 / 12 sup |g''|.
// signBlock splits the edges into near ones, whose field it computes exactly
// at each voxel, and far ones, which add at most l times their bound on |B|.
// For the near part, g'' is a sum over edges of int dl x D^2 f[t, t] . t;
// f = -grad(1/|r|), so |D^2 f[t, t]| is at most the largest third
// directional derivative of 1/|r| (for a symmetric form the norm is reached
// on the diagonal), which is 3! |P_3(cos theta)| / |r|^4 <= 6 / |r|^4 (the
// derivatives at 0 of 1/|r - s u| = sum s^n P_n(cos theta) / |r|^(n+1)).
// Integrating |dl| 6 / |r|^4 / (4 pi) over an edge at distance >= d gives at
// most min(6 L / d^4, 3 pi / d^3) / (4 pi) = min(3 L / (2 pi d^4), 3 / (4
// d^3)) (edgeCurvature). Every point of the step lies within l/2 <= sqrt(3)/2
// voxel of a or b, so the larger of the sums K at a and b, each taken over
// the ball of that radius, bounds sup |g''|. A step takes the smaller of
// this and l times the larger edge by edge bound G at its ends.
//
// w is evaluated by FastWinding (winding.h), whose far-field expansion
// (beta = 2, order 2) is not exact: against the brute-force sum it errs by up
// to 0.06 at random points of the test meshes (median 0.003). Its Taylor
// remainder, 3 M2 / (4 pi (D - R)^4) per node (M2 the node's second area
// moment, D the distance to its centre, R its radius), is of order 1 at
// D = 2R and proves nothing useful, so the error is not bounded here:
// instead every decision that reaches beyond an evaluated point keeps a
// margin kMargin = 0.1 for it. With that, a voxel whose sign is inferred
// from an anchor evaluated at w0 gets the sign of its own true winding
// number whenever |w0 - w(anchor)| < kMargin, which is what evaluating the
// voxel itself would need as well.
//
// Off the band. The band is exact (distance/band.h), so a voxel off it is at least
// r = halfWidth voxels from the mesh, and every point of a cube of such
// voxel centres lies within sqrt(3)/2 voxel of one of them, hence at least
// r - sqrt(3)/2 voxels from the mesh: for r > sqrt(3)/2 the cube holds no
// mesh point, w is harmonic on it, and |w(p) - w(c)| <= rho * sup |grad w|
// for each voxel p of it, c its centre and rho its half-diagonal. cubeSide
// bounds sup |grad w| over the cube by the field bound above at a lower
// bound of each edge's distance to the cube (the larger of the boxes' gap,
// the edge's distance from c less rho, and r - sqrt(3)/2 voxels), and gives
// the cube the side of w(c) when |w(c) - 1/2| > rho * bound + kMargin. (With
// a band of r <= sqrt(3)/2 the clearance comes from the exact distance of c
// less rho instead.)
#include "sign/winding_sign.h"

#include "distance/band.h"
#include "distance/packet_rows.h"
#include "sign/block_flood.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

namespace meshsdf
{

namespace
{

constexpr double kPi = 3.14159265358979323846;

// Edges nearer than this (in voxels) to a block are bounded voxel by voxel,
// farther ones once for the whole block.
constexpr double kNearVoxels = 12;

// What a decision keeps for FastWinding's error (see the top of the file).
constexpr double kMargin = 0.1;
// A winding number within this of 1/2 signs its voxels, but says little:
// WindingSign::ambiguousVoxels counts them.
constexpr double kAmbiguous = 0.25;

bool ambiguous(double w) { return std::abs(w - 0.5) < kAmbiguous; }

// Bound on the field of one edge of length `length` carrying current 1, at
// distance d from it (infinite on it).
double edgeField(double d, double length)
{
    return d > 0 ? std::min(length / (4 * kPi * d * d), 1 / (2 * kPi * d)) : INFINITY;
}

// Bound on the second derivative along any line of the field of one edge
// of length `length` carrying current 1, at distance d from it.
double edgeCurvature(double d, double length)
{
    return d > 0 ? std::min(3 * length / (2 * kPi * d * d * d * d), 3 / (4 * d * d * d)) : INFINITY;
}

double segmentDistance(const OpenEdge &e, const double *p)
{
    double ab[3], ap[3], ab2 = 0, t = 0;
    for (int k = 0; k < 3; ++k) {
        ab[k] = e.b[k] - e.a[k];
        ap[k] = p[k] - e.a[k];
        ab2 += ab[k] * ab[k];
        t += ab[k] * ap[k];
    }
    t = ab2 > 0 ? std::min(std::max(t / ab2, 0.0), 1.0) : 0.0;
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        const double d = ap[k] - t * ab[k];
        d2 += d * d;
    }
    return std::sqrt(d2);
}

// On the mesh's welded vertices (TriangleMesh::welded, as the health counts
// take them), so seams of duplicated vertices carry nothing.
std::vector<OpenEdge> openEdges(const TriangleMesh &mesh)
{
    // Each edge's net current: uses from the smaller welded vertex to the
    // larger, less those the other way (the runs of edgeUses).
    const std::vector<EdgeUse> uses = edgeUses(mesh);
    std::vector<OpenEdge> edges;
    for (size_t i = 0, j; i < uses.size(); i = j) {
        int net = 0;
        for (j = i; j < uses.size() && uses[j].key == uses[i].key; ++j)
            net += edgeFrom(mesh, uses[j].halfEdge) < edgeTo(mesh, uses[j].halfEdge) ? 1 : -1;
        if (net == 0)
            continue;
        const uint64_t key = uses[i].key;
        // Directed along the net current: min -> max when positive.
        const auto &p = mesh.points[uint32_t(net > 0 ? key >> 32 : key & 0xffffffffu)];
        const auto &q = mesh.points[uint32_t(net > 0 ? key & 0xffffffffu : key >> 32)];
        OpenEdge e;
        double len2 = 0;
        for (int k = 0; k < 3; ++k) {
            e.a[k] = p[k];
            e.b[k] = q[k];
            e.lo[k] = std::min(e.a[k], e.b[k]);
            e.hi[k] = std::max(e.a[k], e.b[k]);
            len2 += (e.b[k] - e.a[k]) * (e.b[k] - e.a[k]);
        }
        e.length = std::sqrt(len2);
        e.current = std::abs(net);
        edges.push_back(e);
    }
    // A deterministic order, so that the bounds' rounding is the same each run.
    std::sort(edges.begin(), edges.end(), [](const OpenEdge &x, const OpenEdge &y) {
        return std::lexicographical_compare(x.a, x.a + 3, y.a, y.a + 3) ||
               (std::equal(x.a, x.a + 3, y.a) && std::lexicographical_compare(x.b, x.b + 3, y.b, y.b + 3));
    });
    return edges;
}

// Adds to B the field of edge e, current e.current from a to b, at p:
// (ra x rb) (|ra| + |rb|) / (|ra| |rb| (|ra| |rb| + ra . rb)) / (4 pi) with
// ra = p - a, rb = p - b, the closed form of the Biot-Savart integral, zero
// on the edge's line beyond its ends.
void segmentField(const OpenEdge &e, const double *p, double B[3])
{
    double ra[3], rb[3];
    for (int k = 0; k < 3; ++k) {
        ra[k] = p[k] - e.a[k];
        rb[k] = p[k] - e.b[k];
    }
    const double la = std::sqrt(ra[0] * ra[0] + ra[1] * ra[1] + ra[2] * ra[2]);
    const double lb = std::sqrt(rb[0] * rb[0] + rb[1] * rb[1] + rb[2] * rb[2]);
    const double denominator = la * lb * (la * lb + ra[0] * rb[0] + ra[1] * rb[1] + ra[2] * rb[2]);
    const double f = denominator > 0 ? e.current * (la + lb) / (4 * kPi * denominator) : INFINITY;
    B[0] += f * (ra[1] * rb[2] - ra[2] * rb[1]);
    B[1] += f * (ra[2] * rb[0] - ra[0] * rb[2]);
    B[2] += f * (ra[0] * rb[1] - ra[1] * rb[0]);
}

// A lower bound on the distance from edge e to every point within `inflate`
// of the box [lo, hi]: the gap between the boxes, or e's distance from the
// box's centre less its half-diagonal, less `inflate`.
double edgeGap(const OpenEdge &e, const double lo[3], const double hi[3], double inflate)
{
    double gap2 = 0, half2 = 0, centre[3];
    for (int k = 0; k < 3; ++k) {
        const double gap = std::max({e.lo[k] - hi[k], 0.0, lo[k] - e.hi[k]});
        gap2 += gap * gap;
        centre[k] = 0.5 * (lo[k] + hi[k]);
        half2 += 0.25 * (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    return std::max(std::sqrt(gap2), segmentDistance(e, centre) - std::sqrt(half2)) - inflate;
}

} // namespace

EdgeField::EdgeField(const TriangleMesh &mesh) : mEdges(openEdges(mesh))
{
    std::vector<uint32_t> order(mEdges.size());
    for (size_t i = 0; i < order.size(); ++i)
        order[i] = uint32_t(i);
    mGroups.reserve(2 * mEdges.size());
    if (!mEdges.empty())
        build(order, 0, order.size());
}

// Splits the edges order[first, first + count) at the median of their
// midpoints along the longest side of their box; a group per node.
uint32_t EdgeField::build(std::vector<uint32_t> &order, size_t first, size_t count)
{
    const uint32_t index = uint32_t(mGroups.size());
    mGroups.push_back(Group{});
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, chord[3] = {0, 0, 0};
    double mass = 0;
    for (size_t i = first; i < first + count; ++i) {
        const OpenEdge &e = mEdges[order[i]];
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], e.lo[k]);
            hi[k] = std::max(hi[k], e.hi[k]);
            chord[k] += e.current * (e.b[k] - e.a[k]);
        }
        mass += e.current * e.length;
    }
    Group g;
    double radius2 = 0;
    for (int k = 0; k < 3; ++k)
        g.centre[k] = 0.5 * (lo[k] + hi[k]);
    for (size_t i = first; i < first + count; ++i) {
        const OpenEdge &e = mEdges[order[i]];
        double a2 = 0, b2 = 0;
        for (int k = 0; k < 3; ++k) {
            a2 += (e.a[k] - g.centre[k]) * (e.a[k] - g.centre[k]);
            b2 += (e.b[k] - g.centre[k]) * (e.b[k] - g.centre[k]);
        }
        radius2 = std::max({radius2, a2, b2});
    }
    // Margins for rounding: the chord of a closed loop sums to zero only up
    // to rounding, and the radius must hold the endpoints as stored.
    g.radius = std::sqrt(radius2) * (1 + 1e-9);
    g.chord = std::sqrt(chord[0] * chord[0] + chord[1] * chord[1] + chord[2] * chord[2]) + 1e-9 * mass;
    g.mass = mass;
    if (count == 1) {
        g.left = g.right = order[first];
        mGroups[index] = g;
        return index;
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (hi[k] - lo[k] > hi[axis] - lo[axis])
            axis = k;
    auto mid = [&](uint32_t i) { return mEdges[i].a[axis] + mEdges[i].b[axis]; };
    const size_t half = count / 2;
    std::nth_element(order.begin() + first, order.begin() + first + half, order.begin() + first + count,
                     [&](uint32_t x, uint32_t y) { return mid(x) < mid(y) || (mid(x) == mid(y) && x < y); });
    g.left = build(order, first, half);
    g.right = build(order, first + half, count - half);
    mGroups[index] = g;
    return index;
}

// The sum, over a cut of the tree, of group bounds (the group's field at
// every point within `inflate` of the box, by the dipole argument at the top
// of the file) where they are small, and of leaf(edge, gap) at the edges
// reached, gap a lower bound on the edge's distance from those points.
template <typename Leaf>
double EdgeField::walk(uint32_t node, const double lo[3], const double hi[3], double inflate, Leaf &&leaf) const
{
    const Group &g = mGroups[node];
    if (g.left == g.right) {
        const OpenEdge &e = mEdges[g.left];
        return leaf(e, edgeGap(e, lo, hi, inflate));
    }
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        const double gap = std::max({lo[k] - g.centre[k], 0.0, g.centre[k] - hi[k]});
        d2 += gap * gap;
    }
    const double d = std::sqrt(d2) - inflate, r = g.radius;
    if (d > r) {
        const double q = d - r;
        const double group = (g.chord / (d * d) + 2 * g.mass * r / (q * q * q)) / (4 * kPi);
        // Taken where no edge by edge sum could do much better: each edge
        // gives at least about current * length / (4 pi (d + r)^2).
        if (group <= g.mass / (4 * kPi * (d + r) * (d + r)))
            return group;
    }
    return walk(g.left, lo, hi, inflate, leaf) + walk(g.right, lo, hi, inflate, leaf);
}

double EdgeField::overBox(const double lo[3], const double hi[3], double inflate, double floor) const
{
    if (mGroups.empty())
        return 0;
    return walk(0, lo, hi, inflate,
                [&](const OpenEdge &e, double gap) { return e.current * edgeField(std::max(gap, floor), e.length); });
}

void EdgeField::field(const double p[3], double B[3]) const
{
    B[0] = B[1] = B[2] = 0;
    for (const OpenEdge &e : mEdges)
        segmentField(e, p, B);
}

double EdgeField::curvature(const double p[3], double inflate) const
{
    double K = 0;
    for (const OpenEdge &e : mEdges)
        K += e.current * edgeCurvature(segmentDistance(e, p) - inflate, e.length);
    return K;
}

double EdgeField::farPart(const double lo[3], const double hi[3], double inflate, double nearDistance,
                          std::vector<const OpenEdge *> &near) const
{
    if (mGroups.empty())
        return 0;
    return walk(0, lo, hi, inflate, [&](const OpenEdge &e, double gap) {
        if (gap > nearDistance)
            return e.current * edgeField(gap, e.length);
        near.push_back(&e);
        return 0.0;
    });
}

namespace
{

// Bound on |grad w| within sqrt(3)/2 voxel of a voxel centre of one block:
// every point of a step to one of the 26 neighbours lies within half the
// step's length, at most sqrt(3)/2 voxel, of one of its two ends, so the
// larger of their two bounds holds along it.
class BlockGradientBound
{
  public:
    BlockGradientBound(const EdgeField &field, const double lo[3], const double hi[3], double voxelSize)
        : mReach(0.5 * std::sqrt(3.0) * voxelSize)
    {
        mFar = field.farPart(lo, hi, mReach, kNearVoxels * voxelSize, mNear);
    }
    double far() const { return mFar; }
    // At p, the near edges' exact field B; and over every point within
    // sqrt(3)/2 voxel of p that no edge is nearer than `floor`, their bound
    // G on |B| and K on the second derivative of B along any line.
    void nearField(const double *p, double floor, double B[3], double &G, double &K) const
    {
        B[0] = B[1] = B[2] = G = K = 0;
        for (const auto *e : mNear) {
            const double d = std::max(segmentDistance(*e, p) - mReach, floor);
            G += e->current * edgeField(d, e->length);
            K += e->current * edgeCurvature(d, e->length);
            segmentField(*e, p, B);
        }
    }
    // nearField at the four points (x, y, z[l]), floors floor[l]; B[k][l]
    // is component k at point l. With AVX2 and FMA where `vectorized`: the
    // same formulas, four points at once.
    void nearFieldRow(bool vectorized, double x, double y, const double *z, const double *floor, double (*B)[4],
                      double *G, double *K) const
    {
#ifdef SDFT_MESH_ROWS_AVX2
        if (vectorized)
            return nearFieldRowAvx2(x, y, z, floor, B, G, K);
#endif
        for (int l = 0; l < 4; ++l) {
            const double p[3] = {x, y, z[l]};
            double b[3];
            nearField(p, floor[l], b, G[l], K[l]);
            for (int k = 0; k < 3; ++k)
                B[k][l] = b[k];
        }
    }
    // The bound at every point within `slack` of p, where no edge is nearer
    // than `floor`.
    double at(const double *p, double slack, double floor) const
    {
        double g = mFar;
        for (const auto *e : mNear)
            g += e->current * edgeField(std::max(segmentDistance(*e, p) - mReach - slack, floor), e->length);
        return g;
    }

  private:
#ifdef SDFT_MESH_ROWS_AVX2
    // segmentDistance, edgeField, edgeCurvature and segmentField, lane by
    // lane as written above (std::min(x, y) is _mm256_min_pd(y, x): the
    // same operand wins on NaN).
    __attribute__((target("avx2,fma"))) void nearFieldRowAvx2(double x, double y, const double *z, const double *floor,
                                                              double (*B)[4], double *G, double *K) const
    {
        const __m256d zs = _mm256_loadu_pd(z), zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
        const __m256d inf = _mm256_set1_pd(INFINITY), pi = _mm256_set1_pd(kPi), reach = _mm256_set1_pd(mReach);
        const __m256d floors = _mm256_loadu_pd(floor);
        __m256d bx = zero, by = zero, bz = zero, g = zero, kk = zero;
        for (const auto *e : mNear) {
            // ra = p - a, rb = p - b; x and y are the same in every lane.
            const double rax = x - e->a[0], ray = y - e->a[1], rbx = x - e->b[0], rby = y - e->b[1];
            const __m256d raz = _mm256_sub_pd(zs, _mm256_set1_pd(e->a[2]));
            const __m256d rbz = _mm256_sub_pd(zs, _mm256_set1_pd(e->b[2]));
            // segmentDistance
            const double abx = e->b[0] - e->a[0], aby = e->b[1] - e->a[1], abz = e->b[2] - e->a[2];
            const double ab2 = abx * abx + aby * aby + abz * abz;
            __m256d t = _mm256_fmadd_pd(_mm256_set1_pd(abz), raz, _mm256_set1_pd(abx * rax + aby * ray));
            t = ab2 > 0 ? _mm256_min_pd(_mm256_max_pd(_mm256_div_pd(t, _mm256_set1_pd(ab2)), zero), one) : zero;
            const __m256d dx = _mm256_fnmadd_pd(t, _mm256_set1_pd(abx), _mm256_set1_pd(rax));
            const __m256d dy = _mm256_fnmadd_pd(t, _mm256_set1_pd(aby), _mm256_set1_pd(ray));
            const __m256d dz = _mm256_fnmadd_pd(t, _mm256_set1_pd(abz), raz);
            const __m256d dist =
                _mm256_sqrt_pd(_mm256_fmadd_pd(dz, dz, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx))));
            // d = max(dist - reach, floor): std::max(x, y) is _mm256_max_pd(y, x).
            const __m256d d = _mm256_max_pd(floors, _mm256_sub_pd(dist, reach));
            const __m256d positive = _mm256_cmp_pd(d, zero, _CMP_GT_OQ);
            const __m256d length = _mm256_set1_pd(e->length), current = _mm256_set1_pd(e->current);
            const __m256d d2 = _mm256_mul_pd(d, d), d3 = _mm256_mul_pd(d2, d);
            const __m256d field = _mm256_min_pd(_mm256_div_pd(one, _mm256_mul_pd(_mm256_set1_pd(2 * kPi), d)),
                                                _mm256_div_pd(length, _mm256_mul_pd(_mm256_set1_pd(4 * kPi), d2)));
            const __m256d curvature = _mm256_min_pd(
                _mm256_div_pd(_mm256_set1_pd(3.0), _mm256_mul_pd(_mm256_set1_pd(4.0), d3)),
                _mm256_div_pd(_mm256_mul_pd(_mm256_set1_pd(3.0), length),
                              _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(2.0), pi), _mm256_mul_pd(d3, d))));
            g = _mm256_add_pd(g, _mm256_mul_pd(current, _mm256_blendv_pd(inf, field, positive)));
            kk = _mm256_add_pd(kk, _mm256_mul_pd(current, _mm256_blendv_pd(inf, curvature, positive)));
            // segmentField
            const __m256d la = _mm256_sqrt_pd(_mm256_fmadd_pd(raz, raz, _mm256_set1_pd(rax * rax + ray * ray)));
            const __m256d lb = _mm256_sqrt_pd(_mm256_fmadd_pd(rbz, rbz, _mm256_set1_pd(rbx * rbx + rby * rby)));
            const __m256d lab = _mm256_mul_pd(la, lb);
            const __m256d dot = _mm256_fmadd_pd(raz, rbz, _mm256_set1_pd(rax * rbx + ray * rby));
            const __m256d denominator = _mm256_mul_pd(lab, _mm256_add_pd(lab, dot));
            const __m256d f = _mm256_blendv_pd(inf,
                                               _mm256_div_pd(_mm256_mul_pd(current, _mm256_add_pd(la, lb)),
                                                             _mm256_mul_pd(_mm256_set1_pd(4 * kPi), denominator)),
                                               _mm256_cmp_pd(denominator, zero, _CMP_GT_OQ));
            // ra x rb
            const __m256d cx = _mm256_fmsub_pd(_mm256_set1_pd(ray), rbz, _mm256_mul_pd(raz, _mm256_set1_pd(rby)));
            const __m256d cy = _mm256_fmsub_pd(raz, _mm256_set1_pd(rbx), _mm256_mul_pd(_mm256_set1_pd(rax), rbz));
            const __m256d cz = _mm256_set1_pd(rax * rby - ray * rbx);
            bx = _mm256_fmadd_pd(f, cx, bx);
            by = _mm256_fmadd_pd(f, cy, by);
            bz = _mm256_fmadd_pd(f, cz, bz);
        }
        _mm256_storeu_pd(B[0], bx);
        _mm256_storeu_pd(B[1], by);
        _mm256_storeu_pd(B[2], bz);
        _mm256_storeu_pd(G, g);
        _mm256_storeu_pd(K, kk);
    }
#endif

    double mReach;
    double mFar = 0;
    std::vector<const OpenEdge *> mNear;
};

// The cheap way to sign a block (signBlock gives the argument): one bound
// on the change of w per step for the whole block, its joined components
// flooded by masks (block_flood.h), one evaluation per component. `distance`
// and `reach` are signBlock's; `lo` is the block's first voxel centre;
// `clearance` the distance from the mesh that every point within sqrt(3)/2
// voxel of a voxel off the band keeps; `windingAt(v)` evaluates w at voxel
// v; `counted(v)` says whether voxel v counts in `ambiguousVoxels`. Returns false, having changed nothing, when the
// bound is infinite or some component reaches farther from its evaluated voxel than the bound allows.
template <typename Winding, typename Counted>
bool signByComponents(float *distance, const float *reach, const BlockGradientBound &gradient, const double lo[3],
                      double voxelSize, double clearance, Winding &&windingAt, Counted &&counted,
                      uint64_t &ambiguousVoxels)
{
    bool anyBand = false;
    for (int v = 0; v < kBlockSize; ++v)
        anyBand = anyBand || std::isfinite(distance[v]);
    const double h = voxelSize, halfSide = 0.5 * (kBlockDim - 1) * h;
    const double centre[3] = {lo[0] + halfSide, lo[1] + halfSide, lo[2] + halfSide};
    const double perStep =
        std::sqrt(3.0) * h * (1 + 1e-6) * gradient.at(centre, std::sqrt(3.0) * halfSide, anyBand ? 0.0 : clearance);
    if (!std::isfinite(perStep))
        return false;
    const BlockFlood flood(reach, voxelSize);
    VoxelMask remaining, inside;
    for (int v = 0; v < kBlockSize; ++v)
        remaining.add(v);
    while (!remaining.empty()) {
        int seed = -1;
        remaining.forEach([&](int v) {
            if (seed < 0 || reach[v] > reach[seed])
                seed = v;
        });
        const double w = windingAt(seed);
        // The most steps that keep |w - 1/2| - steps * perStep > kMargin.
        const double margin = std::abs(w - 0.5) - kMargin;
        int maxLayers = 0;
        if (margin > 0)
            maxLayers = perStep > 0 ? int(std::min(std::ceil(margin / perStep) - 1, double(kBlockSize))) : kBlockSize;
        while (maxLayers > 0 && !(margin > maxLayers * perStep))
            --maxLayers;
        int layers = 0;
        const VoxelMask component = flood.flood(seed, remaining, maxLayers, layers);
        if (layers > maxLayers)
            return false;
        if (w > 0.5)
            inside = inside | component;
        if (ambiguous(w))
            component.forEach([&](int v) { ambiguousVoxels += counted(v); });
        remaining = remaining.without(component);
    }
    for (int v = 0; v < kBlockSize; ++v)
        if (inside.has(v))
            distance[v] = -distance[v];
    return true;
}

} // namespace

WindingSign::WindingSign(EdgeField field, const FastWinding &winding, const std::array<double, 3> &origin,
                         double voxelSize, double halfWidth, bool simd, const std::array<int, 3> &counted)
    : mWinding(winding), mOrigin(origin), mVoxelSize(voxelSize), mOffBand(halfWidth * voxelSize),
      mField(std::move(field)), mVectorized(simd && rowsVectorizable()), mCounted(counted)
{
}

uint64_t WindingSign::countedOffBand(const std::array<int, 3> &origin, int size) const
{
    uint64_t voxels = 1;
    for (int k = 0; k < 3; ++k)
        voxels *= uint64_t(std::max(0, std::min(origin[k] + size, mCounted[k]) - std::max(origin[k], 0)));
    return voxels;
}

int WindingSign::cubeSide(const std::array<int, 3> &origin, int size) const
{
    const double h = mVoxelSize;
    double lo[3], hi[3], centre[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = mOrigin[k] + origin[k] * h;
        hi[k] = lo[k] + (size - 1) * h;
        centre[k] = 0.5 * (lo[k] + hi[k]);
    }
    const double rho = 0.5 * std::sqrt(3.0) * (size - 1) * h;
    // A lower bound on the distance from any point of the cube to the mesh,
    // less a margin for rounding: from the band; where the band is thinner
    // than a voxel's half-diagonal, from the centre's distance.
    double clearance = mOffBand * (1 - 1e-6) - 0.5 * std::sqrt(3.0) * h;
    if (!(clearance > 0))
        clearance = mWinding.distance({centre[0], centre[1], centre[2]}) * (1 - 1e-6) - rho;
    if (!(clearance > 0))
        return 0;
    const double gradient = mField.overBox(lo, hi, 0.0, clearance);
    const double w = mWinding({centre[0], centre[1], centre[2]});
    // A margin for rounding in the bound, as in signBlock.
    if (!(std::abs(w - 0.5) > rho * gradient * (1 + 1e-6) + kMargin))
        return 0;
    if (ambiguous(w))
        countAmbiguous(countedOffBand(origin, size));
    return w > 0.5 ? -1 : 1;
}

// Without evaluating w at every voxel: two voxels a, b, neighbours in the
// 26-neighbourhood, whose distances satisfy d(a) + d(b) > |a-b| lie on a
// segment that cannot cross the mesh (a crossing point x would give
// d(a) + d(b) <= |a-x| + |x-b| = |a-b|), so w is smooth between them and
// changes along it by at most the step bound at the top of the file: the
// far edges' bound on |B| times |a-b|, plus for the near edges the smaller of
// |a-b| times the larger of their bounds G at a and b, and the trapezoid rule
// on their exact fields at a and b with its remainder (BlockGradientBound's
// nearField, computed once per voxel). (Diagonal steps matter: next to a surface that is
// not axis-aligned, a voxel nearer than half a voxel often has no face
// neighbour far enough for the test, but one along a diagonal.) A band
// voxel's d is its exact distance; a voxel off the band has d >= the
// half-width r (distance/band.h), and r stands in for it: with r >= 1 every two
// neighbours off the band pass the test (2r > sqrt(3)), and with a thinner
// band the test decides as it does in the band.
//
// So, first the band voxels: split them into components connected by such
// steps; evaluate w at the voxel farthest from the surface and walk the
// component from it, most certain first; a voxel whose walk from the last
// evaluated voxel (its anchor, value w0) can have changed w by at most D has
// the anchor's sign when |w0 - 1/2| > D + kMargin; any other is evaluated
// and becomes the anchor of the voxels reached through it. Then the voxels
// off the band, breadth first from the band's: the same rule, the first walk
// that decides a voxel kept (any walk proves its side), a voxel no walk
// reaches evaluated. Off the band G and K are taken with no edge nearer
// than r - sqrt(3)/2 voxels (every point that near an off-band voxel is
// that far from the mesh).
//
// Before that walk, the cheap way (signByComponents): one bound G on |grad w|
// for every point within sqrt(3)/2 voxel of any voxel of the block (the
// bound at the block's centre with its half-diagonal as slack; where no
// voxel is in the band, no edge nearer than the clearance), so a step
// changes w by at most perStep = sqrt(3) voxels times G. The block's
// components under the same joining rule (d(a) + d(b) > |a-b|, off-band
// voxels at r) are flooded breadth first from their voxel farthest from the
// surface, evaluated at w0: a voxel L steps from it has a walk of L joined
// steps within the block, so its w differs from w(seed) by at most
// L * perStep, and it takes the seed's side when |w0 - 1/2| - L * perStep >
// kMargin, the walk's own rule with every step at its longest and largest
// bound. Where that holds for every component the block is done, with one
// evaluation per component; where not (open edges near the block make G
// large), the walk above decides it, reusing the evaluations made.
//
// One function of about 200 lines, on purpose: its three phases (the cheap
// way, the band walk, the off-band walk) share the block's per-voxel state
// on the stack (evaluated values, anchors, drifts, margins, the near
// edges' fields), which split functions would pass a dozen arrays of; the
// lambdas name each step.
void WindingSign::signBlock(const std::array<int, 3> &origin, float *distance) const
{
    const double h = mVoxelSize;
    auto world = [&](int v, double *p) {
        const int x = v >> (2 * kBlockLog2), y = (v >> kBlockLog2) & (kBlockDim - 1), z = v & (kBlockDim - 1);
        p[0] = mOrigin[0] + (origin[0] + x) * h;
        p[1] = mOrigin[1] + (origin[1] + y) * h;
        p[2] = mOrigin[2] + (origin[2] + z) * h;
    };
    auto windingAt = [&](int v) {
        double p[3];
        world(v, p);
        return mWinding({p[0], p[1], p[2]});
    };
    double lo[3], hi[3];
    world(0, lo);
    world(kBlockSize - 1, hi);
    const BlockGradientBound gradient(mField, lo, hi, h);
    const double clearance = std::max(mOffBand * (1 - 1e-6) - 0.5 * std::sqrt(3.0) * h, 0.0);
    // Distance, or for a voxel off the band the bound every such voxel keeps.
    const float offBand = float(mOffBand);
    float reach[kBlockSize];
    for (int v = 0; v < kBlockSize; ++v)
        reach[v] = std::isfinite(distance[v]) ? distance[v] : offBand;
    // Winding numbers evaluated so far (NaN: not yet).
    double evaluated[kBlockSize];
    std::fill(evaluated, evaluated + kBlockSize, NAN);
    auto windingOnce = [&](int v) {
        if (std::isnan(evaluated[v]))
            evaluated[v] = windingAt(v);
        return evaluated[v];
    };
    // The voxels the ambiguous count counts: the band's, and those off it
    // within mCounted's box.
    auto counted = [&](int v) {
        const int x = origin[0] + (v >> (2 * kBlockLog2)), y = origin[1] + ((v >> kBlockLog2) & (kBlockDim - 1)),
                  z = origin[2] + (v & (kBlockDim - 1));
        return std::isfinite(distance[v]) ||
               (x >= 0 && y >= 0 && z >= 0 && x < mCounted[0] && y < mCounted[1] && z < mCounted[2]);
    };
    uint64_t uncertain = 0;
    if (signByComponents(distance, reach, gradient, lo, h, clearance, windingOnce, counted, uncertain)) {
        countAmbiguous(uncertain);
        return;
    }
    // The near edges' field at each voxel (computed when first needed): the
    // exact field B, and over every point within sqrt(3)/2 voxel of the
    // voxel, the edge by edge bound G on |B| and the bound K on the second
    // derivative of B along a line; off the band no edge is nearer than the
    // clearance. The edges farther away add at most gradient.far() to |B|.
    auto inBand = [&](int v) { return std::isfinite(distance[v]); };
    // Per voxel, in the units a step needs: B h / 2, G h, K h^3 / 12, and
    // a margin for rounding in B's sums.
    struct NearField {
        double B[3], G, K, rounding;
    };
    NearField field[kBlockSize];
    if (!mField.edges().empty())
        for (int v = 0; v < kBlockSize; v += 4) { // four voxels along z at a time
            double p[3], z[4], floor[4], B[3][4], G[4], K[4];
            for (int l = 0; l < 4; ++l) {
                world(v + l, p);
                z[l] = p[2];
                floor[l] = inBand(v + l) ? 0.0 : clearance;
            }
            gradient.nearFieldRow(mVectorized, p[0], p[1], z, floor, B, G, K);
            for (int l = 0; l < 4; ++l) {
                NearField &f = field[v + l];
                for (int k = 0; k < 3; ++k)
                    f.B[k] = B[k][l] * (0.5 * h);
                f.G = G[l] * h;
                f.K = K[l] * (h * h * h / 12);
                f.rounding = 2e-9 * (std::abs(f.B[0]) + std::abs(f.B[1]) + std::abs(f.B[2]));
            }
        }
    // A bound on the change of w along the step from v to its neighbour u
    // (offset o, `length` voxels), with a margin for rounding: the far
    // edges' part, plus the smaller of the near edges' bound by G and their
    // trapezoid rule with its remainder (see the top of the file).
    const double far = gradient.far() * h;
    auto change = [&](int v, int u, const int *o, double length) {
        const NearField &a = field[v], &b = field[u];
        const double byG = length * std::max(a.G, b.G);
        const double dot = (a.B[0] + b.B[0]) * o[0] + (a.B[1] + b.B[1]) * o[1] + (a.B[2] + b.B[2]) * o[2];
        const double byB =
            std::abs(dot) + length * length * length * std::max(a.K, b.K) + length * (a.rounding + b.rounding);
        return (std::min(byG, byB) + length * far) * (1 + 1e-6);
    };
    // The 26 neighbour offsets, their lengths in voxels, the length in world
    // units (with a margin for rounding) that d(a) + d(b) must exceed, and
    // the offset in the block's voxel numbering.
    struct Step {
        int offset[3];
        double length;
        float crossing;
        int delta;
    };
    Step steps[26];
    int stepCount = 0;
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz)
                if (dx || dy || dz) {
                    const double length = std::sqrt(double(dx * dx + dy * dy + dz * dz));
                    steps[stepCount++] = {{dx, dy, dz},
                                          length,
                                          float(length * h) * (1.0f + 1e-5f),
                                          (dx * kBlockDim + dy) * kBlockDim + dz};
                }

    // Which steps join each voxel to a neighbour in the block: bit s of
    // joined[v] for steps[s] when reach[v] + reach[u] exceeds its crossing,
    // computed once, step by step over the voxels that have that neighbour
    // (a loop without branches), so that the walk below visits a voxel's
    // joined neighbours, in the steps' order, without testing the others.
    uint32_t joined[kBlockSize] = {};
    for (int si = 0; si < stepCount; ++si) {
        const Step &s = steps[si];
        const int delta = s.delta;
        const int zlo = std::max(0, -s.offset[2]), zhi = std::min(kBlockDim, kBlockDim - s.offset[2]);
        for (int x = std::max(0, -s.offset[0]); x < std::min(kBlockDim, kBlockDim - s.offset[0]); ++x)
            for (int y = std::max(0, -s.offset[1]); y < std::min(kBlockDim, kBlockDim - s.offset[1]); ++y) {
                const int row = ((x << kBlockLog2) + y) << kBlockLog2;
                for (int z = zlo; z < zhi; ++z)
                    joined[row + z] |= uint32_t(reach[row + z] + reach[row + z + delta] > s.crossing) << si;
            }
    }
    auto neighbours = [&](int v, auto &&visit) {
        for (uint32_t m = joined[v]; m; m &= m - 1) {
            const Step &s = steps[__builtin_ctz(m)];
            visit(v + s.delta, s);
        }
    };
    // Most certain first: a max-heap on margin = |w(anchor) - 1/2| - drift.
    double margin[kBlockSize], drift[kBlockSize], anchorW[kBlockSize];
    bool decided[kBlockSize];
    std::fill(margin, margin + kBlockSize, -INFINITY);
    std::fill(decided, decided + kBlockSize, false);
    std::vector<std::pair<double, int>> heap;
    heap.reserve(2 * kBlockSize);
    auto push = [&](int v) {
        heap.emplace_back(margin[v], v);
        std::push_heap(heap.begin(), heap.end());
    };
    auto evaluate = [&](int v) {
        anchorW[v] = windingOnce(v);
        drift[v] = 0;
        margin[v] = std::abs(anchorW[v] - 0.5);
    };
    // First the band voxels, most certain first.
    for (;;) {
        if (heap.empty()) {
            // A new component: evaluate at its voxel farthest from the surface.
            int farthest = -1;
            for (int v = 0; v < kBlockSize; ++v)
                if (inBand(v) && !decided[v] && (farthest < 0 || reach[v] > reach[farthest]))
                    farthest = v;
            if (farthest < 0)
                break;
            evaluate(farthest);
            push(farthest);
        }
        std::pop_heap(heap.begin(), heap.end());
        const auto [top, v] = heap.back();
        heap.pop_back();
        if (decided[v] || top < margin[v])
            continue; // settled already, or a stale entry
        if (!(margin[v] > kMargin))
            evaluate(v); // no walk from an evaluated voxel decides it
        decided[v] = true;
        neighbours(v, [&](int u, const Step &s) {
            if (decided[u] || !inBand(u))
                return;
            const double d = mField.edges().empty() ? 0.0 : drift[v] + change(v, u, s.offset, s.length);
            const double m = std::abs(anchorW[v] - 0.5) - d;
            if (m > margin[u]) {
                margin[u] = m;
                drift[u] = d;
                anchorW[u] = anchorW[v];
                push(u);
            }
        });
    }
    // Then the voxels off the band, breadth first from the band: each takes
    // the first walk that decides it (any walk proves its side), and one no
    // walk reaches is evaluated.
    std::vector<int> queue;
    queue.reserve(kBlockSize);
    for (int v = 0; v < kBlockSize; ++v)
        if (decided[v])
            queue.push_back(v);
    for (size_t next = 0, start = 0;;) {
        if (next == queue.size()) {
            while (start < size_t(kBlockSize) && decided[start])
                ++start;
            if (start == size_t(kBlockSize))
                break;
            evaluate(int(start));
            decided[start] = true;
            queue.push_back(int(start));
        }
        const int v = queue[next++];
        neighbours(v, [&](int u, const Step &s) {
            if (decided[u])
                return;
            const double d = mField.edges().empty() ? 0.0 : drift[v] + change(v, u, s.offset, s.length);
            if (std::abs(anchorW[v] - 0.5) - d > kMargin) {
                decided[u] = true;
                drift[u] = d;
                anchorW[u] = anchorW[v];
                queue.push_back(u);
            }
        });
    }
    // Negate only now: the walk reads the unsigned distances.
    uncertain = 0;
    for (int v = 0; v < kBlockSize; ++v) {
        if (anchorW[v] > 0.5)
            distance[v] = -distance[v];
        uncertain += ambiguous(anchorW[v]) && counted(v);
    }
    countAmbiguous(uncertain);
}

} // namespace meshsdf
