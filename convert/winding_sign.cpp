// mesh2sdf — the sign of band voxels by the winding number (see
// winding_sign.h).
//
// The winding number w off the mesh is the scalar potential of a unit
// current around each triangle's boundary, so its gradient is the
// Biot–Savart field of the edges where those currents do not cancel:
// boundary and non-manifold edges and edges between inconsistently oriented
// triangles (an edge used k times a->b and l times b->a carries k - l). For
// a closed, consistently oriented mesh there are none and w is constant off
// the mesh.
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
// f(d) = min(L / (4 pi d^2), 1 / (2 pi d)) (edgeField).
#include "winding_sign.h"

#include "band.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <unordered_map>

namespace mesh2sdf
{

namespace
{

constexpr double kPi = 3.14159265358979323846;

// Edges nearer than this (in voxels) to a block are bounded voxel by voxel,
// farther ones once for the whole block.
constexpr double kNearVoxels = 12;

// Bound on the field of one edge of length `length` carrying current 1, at
// distance d from it (infinite on it).
double edgeField(double d, double length)
{
    return d > 0 ? std::min(length / (4 * kPi * d * d), 1 / (2 * kPi * d)) : INFINITY;
}

double segmentDistance(const WindingSign::OpenEdge &e, const double *p)
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

// Vertices are welded by exact position, as the health counts do, so seams
// of duplicated vertices carry nothing.
std::vector<WindingSign::OpenEdge> openEdges(const TriangleMesh &mesh)
{
    struct PointHash {
        size_t operator()(const std::array<float, 3> &p) const
        {
            uint32_t b[3];
            std::memcpy(b, p.data(), sizeof b);
            return (size_t(b[0]) * 0x9E3779B97F4A7C15ull) ^ (size_t(b[1]) * 0xC2B2AE3D27D4EB4Full) ^ b[2];
        }
    };
    std::unordered_map<std::array<float, 3>, uint32_t, PointHash> weld;
    std::vector<uint32_t> id(mesh.points.size());
    for (size_t i = 0; i < mesh.points.size(); ++i)
        id[i] = weld.emplace(mesh.points[i], uint32_t(i)).first->second;
    std::unordered_map<uint64_t, int> net; // (min, max) -> uses min->max minus max->min
    net.reserve(mesh.triangles.size() * 2);
    for (const auto &t : mesh.triangles)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = id[t[e]], b = id[t[(e + 1) % 3]];
            if (a == b)
                continue;
            const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            net[key] += a < b ? 1 : -1;
        }
    std::vector<WindingSign::OpenEdge> edges;
    for (const auto &kv : net) {
        if (kv.second == 0)
            continue;
        const auto &p = mesh.points[uint32_t(kv.first >> 32)];
        const auto &q = mesh.points[uint32_t(kv.first & 0xffffffffu)];
        WindingSign::OpenEdge e;
        double len2 = 0;
        for (int k = 0; k < 3; ++k) {
            e.a[k] = p[k];
            e.b[k] = q[k];
            e.lo[k] = std::min(e.a[k], e.b[k]);
            e.hi[k] = std::max(e.a[k], e.b[k]);
            len2 += (e.b[k] - e.a[k]) * (e.b[k] - e.a[k]);
        }
        e.length = std::sqrt(len2);
        e.current = std::abs(kv.second);
        edges.push_back(e);
    }
    // A deterministic order, so that the bounds' rounding is the same each run.
    std::sort(edges.begin(), edges.end(), [](const WindingSign::OpenEdge &x, const WindingSign::OpenEdge &y) {
        return std::lexicographical_compare(x.a, x.a + 3, y.a, y.a + 3) ||
               (std::equal(x.a, x.a + 3, y.a) && std::lexicographical_compare(x.b, x.b + 3, y.b, y.b + 3));
    });
    return edges;
}

// Bound on |grad w| within half a voxel of a voxel centre of one block: a
// step between face-adjacent voxels lies within half a voxel of one of its
// two ends, so the larger of their two bounds holds along it.
class BlockGradientBound
{
  public:
    BlockGradientBound(const std::vector<WindingSign::OpenEdge> &edges, const double lo[3], const double hi[3],
                       double voxelSize)
        : mHalfVoxel(0.5 * voxelSize)
    {
        for (const auto &e : edges) {
            double d2 = 0;
            for (int k = 0; k < 3; ++k) {
                const double gap = std::max({e.lo[k] - hi[k], 0.0, lo[k] - e.hi[k]});
                d2 += gap * gap;
            }
            const double d = std::sqrt(d2) - mHalfVoxel;
            if (d > kNearVoxels * voxelSize)
                mFar += e.current * edgeField(d, e.length);
            else
                mNear.push_back(&e);
        }
    }
    double at(const double *p) const
    {
        double g = mFar;
        for (const auto *e : mNear)
            g += e->current * edgeField(segmentDistance(*e, p) - mHalfVoxel, e->length);
        return g;
    }

  private:
    double mHalfVoxel;
    double mFar = 0;
    std::vector<const WindingSign::OpenEdge *> mNear;
};

} // namespace

WindingSign::WindingSign(const TriangleMesh &mesh, const FastWinding &winding, const std::array<double, 3> &origin,
                         double voxelSize)
    : mWinding(winding), mOrigin(origin), mVoxelSize(voxelSize), mEdges(openEdges(mesh))
{
}

// Without evaluating w at every voxel: two face-adjacent voxels a, b whose
// exact distances satisfy d(a) + d(b) > h lie on a segment that cannot cross
// the mesh (a crossing point x would give d(a) + d(b) <= |a-x| + |x-b| = h),
// so w is smooth between them and changes along it by at most h times the
// larger gradient bound of a and b (BlockGradientBound). So: split the
// block's band voxels into components connected by such steps; evaluate w
// at the voxel farthest from the surface and walk the component breadth
// first from it; a voxel whose walk from the last evaluated voxel (its
// anchor, value w0) can have changed w by at most D, with |w0 - 1/2| > D,
// has the anchor's sign; any other is evaluated and becomes the anchor of
// the voxels reached through it.
void WindingSign::signBlock(const std::array<int, 3> &origin, float *distance) const
{
    const double h = mVoxelSize;
    const float crossing = float(h) * (1.0f + 1e-5f);
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
    const BlockGradientBound gradient(mEdges, lo, hi, h);
    // Change of w per step from voxel v, with a margin for rounding; < 0
    // until computed.
    double stepBound[kBlockSize];
    std::fill(stepBound, stepBound + kBlockSize, -1.0);
    auto stepAt = [&](int v) {
        if (stepBound[v] < 0) {
            double p[3];
            world(v, p);
            stepBound[v] = gradient.at(p) * h * (1 + 1e-6);
        }
        return stepBound[v];
    };

    auto inBand = [&](int v) { return std::isfinite(distance[v]); };
    auto neighbours = [&](int v, auto &&visit) {
        const int x = v >> (2 * kBlockLog2), y = (v >> kBlockLog2) & (kBlockDim - 1), z = v & (kBlockDim - 1);
        const int next[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z},
                                {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
        for (const auto &n : next) {
            if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= kBlockDim || n[1] >= kBlockDim || n[2] >= kBlockDim)
                continue;
            const int u = (((n[0] << kBlockLog2) | n[1]) << kBlockLog2) | n[2];
            if (inBand(u) && distance[v] + distance[u] > crossing)
                visit(u);
        }
    };
    constexpr int kUnseen = -1, kWalked = kBlockSize;
    int component[kBlockSize];
    std::fill(component, component + kBlockSize, kUnseen);
    int queue[kBlockSize];
    double drift[kBlockSize];   // bound on |w - w(anchor)| along the walk from the anchor
    double anchorW[kBlockSize]; // winding number at the voxel's anchor
    for (int seed = 0; seed < kBlockSize; ++seed) {
        if (!inBand(seed) || component[seed] != kUnseen)
            continue;
        // Find one component from `seed` and its voxel farthest from the surface.
        int head = 0, tail = 0, farthest = seed;
        component[seed] = seed;
        queue[tail++] = seed;
        while (head < tail) {
            const int v = queue[head++];
            if (distance[v] > distance[farthest])
                farthest = v;
            neighbours(v, [&](int u) {
                if (component[u] == kUnseen) {
                    component[u] = seed;
                    queue[tail++] = u;
                }
            });
        }
        // Walk it again from the farthest voxel, deciding signs in that order.
        head = tail = 0;
        queue[tail++] = farthest;
        component[farthest] = kWalked;
        drift[farthest] = 0;
        anchorW[farthest] = windingAt(farthest);
        while (head < tail) {
            const int v = queue[head++];
            if (!(std::abs(anchorW[v] - 0.5) > drift[v])) {
                anchorW[v] = windingAt(v);
                drift[v] = 0;
            }
            neighbours(v, [&](int u) {
                if (component[u] == seed) {
                    component[u] = kWalked;
                    drift[u] = mEdges.empty() ? 0.0 : drift[v] + std::max(stepAt(v), stepAt(u));
                    anchorW[u] = anchorW[v];
                    queue[tail++] = u;
                }
            });
        }
        // Negate only now: the walk reads the unsigned distances.
        for (int i = 0; i < tail; ++i)
            if (anchorW[queue[i]] > 0.5)
                distance[queue[i]] = -distance[queue[i]];
    }
}

} // namespace mesh2sdf
