// mesh2sdf — grid building (see grid.h).
#include "grid.h"

#include "band.h"
#include "winding.h"

#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tree/LeafManager.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace mesh2sdf
{

namespace
{

// The mesh as OpenVDB's MeshDataAdapter wants it: triangles with points in
// the grid's index space, converted on the fly in double precision.
class IndexSpaceMesh
{
  public:
    IndexSpaceMesh(const TriangleMesh &mesh, const BoxGeometry &box) : mMesh(mesh), mBox(box) {}
    size_t polygonCount() const { return mMesh.triangles.size(); }
    size_t pointCount() const { return mMesh.points.size(); }
    size_t vertexCount(size_t) const { return 3; }
    void getIndexSpacePoint(size_t n, size_t v, openvdb::Vec3d &pos) const
    {
        const auto &p = mMesh.points[mMesh.triangles[n][v]];
        for (int k = 0; k < 3; ++k)
            pos[k] = (double(p[k]) - mBox.origin[k]) / mBox.voxelSize;
    }

  private:
    const TriangleMesh &mMesh;
    const BoxGeometry &mBox;
};

Vec3 worldOf(const BoxGeometry &box, const openvdb::Coord &ijk)
{
    return {box.origin[0] + ijk[0] * box.voxelSize, box.origin[1] + ijk[1] * box.voxelSize,
            box.origin[2] + ijk[2] * box.voxelSize};
}

// The winding number off the mesh is the scalar potential of a unit current
// around each triangle's boundary, so its gradient is the Biot–Savart field
// of the edges where those currents do not cancel: boundary and non-manifold
// edges and edges between inconsistently oriented triangles (an edge used
// k times a->b and l times b->a carries k - l). |grad w(x)| <= sum over such
// edges of |k - l| * length / (4 pi dist(x, edge)^2). One entry per edge:
// its bounding box and |k - l| * length / (4 pi). Vertices are welded by
// exact position, as the health counts do, so seams carry nothing.
struct OpenEdge {
    double lo[3], hi[3];
    double weight;
};

std::vector<OpenEdge> openEdges(const TriangleMesh &mesh)
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
    std::vector<OpenEdge> edges;
    for (const auto &kv : net) {
        if (kv.second == 0)
            continue;
        const auto &p = mesh.points[uint32_t(kv.first >> 32)];
        const auto &q = mesh.points[uint32_t(kv.first & 0xffffffffu)];
        OpenEdge e;
        double len2 = 0;
        for (int k = 0; k < 3; ++k) {
            e.lo[k] = std::min(double(p[k]), double(q[k]));
            e.hi[k] = std::max(double(p[k]), double(q[k]));
            len2 += (double(p[k]) - q[k]) * (double(p[k]) - q[k]);
        }
        e.weight = std::abs(kv.second) * std::sqrt(len2) / (4 * M_PI);
        edges.push_back(e);
    }
    return edges;
}

// Bound on |grad w| over the world-space box [lo, hi] (off the mesh).
double gradientBound(const std::vector<OpenEdge> &edges, const double lo[3], const double hi[3])
{
    double g = 0;
    for (const OpenEdge &e : edges) {
        double d2 = 0;
        for (int k = 0; k < 3; ++k) {
            const double gap = std::max({e.lo[k] - hi[k], 0.0, lo[k] - e.hi[k]});
            d2 += gap * gap;
        }
        if (!(d2 > 0))
            return INFINITY;
        g += e.weight / d2;
    }
    return g;
}

// Sign of the active voxels of one leaf by the winding number, without
// evaluating it at every voxel. Two face-adjacent voxels a, b whose exact
// distances satisfy d(a) + d(b) > h lie on a segment that cannot cross the
// mesh (a crossing point x would give d(a) + d(b) <= |a-x| + |x-b| = h), so
// the winding number is continuous, indeed smooth, between them, and changes
// along it by at most h * G, G a bound on its gradient over the leaf (see
// gradientBound, per octant of the leaf; 0 for a closed, consistently
// oriented mesh). So: split the leaf's voxels into such connected
// components; evaluate w at the voxel farthest from the surface and walk the
// component breadth first from it; a voxel whose walk from the last
// evaluated voxel (its anchor, value w0) can have changed w by at most D,
// with |w0 - 1/2| > D, has the anchor's sign; any other is evaluated and
// becomes the anchor of the voxels reached through it.
constexpr uint32_t kNone = 0xffffffffu;

void signLeaf(openvdb::FloatTree::LeafNodeType &leaf, const BoxGeometry &box, const FastWinding &winding,
              const std::vector<OpenEdge> &edges)
{
    using Leaf = openvdb::FloatTree::LeafNodeType;
    constexpr int kDim = int(Leaf::DIM), kSize = int(Leaf::SIZE);
    const float h = float(box.voxelSize) * (1.0f + 1e-5f);
    // Gradient bounds per octant (4^3 voxels) of the leaf, each box grown by
    // half a voxel so that a step between octants lies in the union of the
    // two boxes; the step's bound is the larger of the two.
    double octantStep[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    if (!edges.empty())
        for (int o = 0; o < 8; ++o) {
            const openvdb::Coord c0 = leaf.origin().offsetBy((o >> 2) * 4, ((o >> 1) & 1) * 4, (o & 1) * 4);
            const Vec3 a = worldOf(box, c0), b = worldOf(box, c0.offsetBy(kDim / 2 - 1));
            double lo[3], hi[3];
            for (int k = 0; k < 3; ++k) {
                lo[k] = a[k] - 0.5 * box.voxelSize;
                hi[k] = b[k] + 0.5 * box.voxelSize;
            }
            // Change of w per step, with a margin for rounding.
            octantStep[o] = gradientBound(edges, lo, hi) * box.voxelSize * (1 + 1e-6);
        }
    auto octant = [](int v) {
        return ((v >> (2 * Leaf::LOG2DIM + 2)) & 1) << 2 | ((v >> (Leaf::LOG2DIM + 2)) & 1) << 1 | ((v >> 2) & 1);
    };
    int component[kSize];
    std::fill(component, component + kSize, -1);
    int queue[kSize];
    double drift[kSize];   // bound on |w - w(anchor)| along the walk from the anchor
    double anchorW[kSize]; // winding number at the voxel's anchor
    auto neighbours = [&](int v, auto &&visit) {
        const int x = v >> (2 * Leaf::LOG2DIM), y = (v >> Leaf::LOG2DIM) & (kDim - 1), z = v & (kDim - 1);
        const float dv = leaf.getValue(openvdb::Index(v));
        const int next[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z},
                                {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
        for (const auto &n : next) {
            if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= kDim || n[1] >= kDim || n[2] >= kDim)
                continue;
            const int u = (n[0] << (2 * Leaf::LOG2DIM)) | (n[1] << Leaf::LOG2DIM) | n[2];
            if (leaf.isValueOn(openvdb::Index(u)) && dv + leaf.getValue(openvdb::Index(u)) > h)
                visit(u);
        }
    };
    for (int seed = 0; seed < kSize; ++seed) {
        if (!leaf.isValueOn(openvdb::Index(seed)) || component[seed] >= 0)
            continue;
        // Find one component from `seed` and its voxel farthest from the surface.
        int head = 0, tail = 0, farthest = seed;
        component[seed] = seed;
        queue[tail++] = seed;
        while (head < tail) {
            const int v = queue[head++];
            if (leaf.getValue(openvdb::Index(v)) > leaf.getValue(openvdb::Index(farthest)))
                farthest = v;
            neighbours(v, [&](int u) {
                if (component[u] < 0) {
                    component[u] = seed;
                    queue[tail++] = u;
                }
            });
        }
        // Walk it again from the farthest voxel, deciding signs in that order.
        head = tail = 0;
        queue[tail++] = farthest;
        component[farthest] = kSize; // visited mark for this walk
        drift[farthest] = 0;
        anchorW[farthest] = winding(worldOf(box, leaf.offsetToGlobalCoord(openvdb::Index(farthest))));
        while (head < tail) {
            const int v = queue[head++];
            if (!(std::abs(anchorW[v] - 0.5) > drift[v])) {
                anchorW[v] = winding(worldOf(box, leaf.offsetToGlobalCoord(openvdb::Index(v))));
                drift[v] = 0;
            }
            neighbours(v, [&](int u) {
                if (component[u] == seed) {
                    component[u] = kSize;
                    drift[u] = drift[v] + std::max(octantStep[octant(v)], octantStep[octant(u)]);
                    anchorW[u] = anchorW[v];
                    queue[tail++] = u;
                }
            });
        }
        // Negate only now: the walk reads the unsigned distances.
        for (int i = 0; i < tail; ++i)
            if (anchorW[queue[i]] > 0.5)
                leaf.setValueOnly(openvdb::Index(queue[i]), -leaf.getValue(openvdb::Index(queue[i])));
    }
}

// The exact unsigned band (band.h) as a tree with background `band` voxels
// in world units: a leaf per block, its band voxels active.
openvdb::FloatGrid::Ptr exactBandGrid(const TriangleMesh &mesh, const BoxGeometry &box, float band, Progress &progress)
{
    using Leaf = openvdb::FloatTree::LeafNodeType;
    static_assert(Leaf::DIM == kBlockDim, "band blocks are OpenVDB leaves");
    const float background = band * float(box.voxelSize);
    std::vector<Leaf *> leaves;
    std::mutex leavesMutex;
    exactBand(
        mesh, box.origin, box.voxelSize, band,
        [&](const std::array<int, 3> &origin, const float *distance) {
            auto *leaf = new Leaf(openvdb::Coord(origin[0], origin[1], origin[2]), background, false);
            for (int v = 0; v < kBlockSize; ++v)
                if (std::isfinite(distance[v]))
                    leaf->setValueOn(openvdb::Index(v), distance[v]);
            std::lock_guard<std::mutex> lock(leavesMutex);
            leaves.push_back(leaf);
        },
        [&](int percent) { progress.report(percent); });
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(background);
    for (Leaf *leaf : leaves)
        grid->tree().addLeaf(leaf); // the tree takes ownership
    return grid;
}

// Signs an exact unsigned band by the winding number: negative where it
// exceeds 1/2 (signLeaf, in parallel over leaves). Then gives inactive
// values the sign of their side: OpenVDB's signed flood fill inside leaves,
// the winding number at the centre of every tile (a flood fill would leak
// through a mesh's holes).
void signBand(openvdb::FloatTree &tree, const BoxGeometry &box, const FastWinding &winding, const TriangleMesh &mesh,
              Progress &progress)
{
    const std::vector<OpenEdge> edges = openEdges(mesh);
    openvdb::tree::LeafManager<openvdb::FloatTree> leaves(tree);
    const size_t leafCount = leaves.leafCount();
    std::atomic<size_t> done{0};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, leafCount, 8), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t n = r.begin(); n != r.end(); ++n)
            signLeaf(leaves.leaf(n), box, winding, edges);
        const size_t d = done.fetch_add(r.size()) + r.size();
        progress.report(int(100.0 * double(d) / double(leafCount)));
    });

    const float background = tree.background();
    openvdb::tools::signedFloodFill(tree);
    // Tile centres first, their winding numbers in parallel, then the
    // values in the same (deterministic) iteration order.
    std::vector<Vec3> centres;
    for (auto it = tree.cbeginValueOff(); it; ++it) {
        if (!it.isTileValue())
            continue;
        openvdb::CoordBBox bbox;
        it.getBoundingBox(bbox);
        const openvdb::Vec3d c = bbox.getCenter();
        centres.push_back({box.origin[0] + c[0] * box.voxelSize, box.origin[1] + c[1] * box.voxelSize,
                           box.origin[2] + c[2] * box.voxelSize});
    }
    std::vector<uint8_t> inside(centres.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, centres.size(), 64), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t i = r.begin(); i != r.end(); ++i)
            inside[i] = winding(centres[i]) > 0.5;
    });
    size_t next = 0;
    for (auto it = tree.beginValueOff(); it; ++it) {
        if (!it.isTileValue())
            continue;
        it.setValue(inside[next++] ? -background : background);
    }
}

// --full: every voxel of the box not yet in the band gets its exact
// distance, signed by the winding number when `signByWinding`, else with the
// sign its region already has (OpenVDB's flood fill, or none). Slab by slab:
// distances in parallel, insertion into the tree serially.
void fillBox(openvdb::FloatGrid &grid, const BoxGeometry &box, const FastWinding &tree, bool signByWinding,
             Progress &progress)
{
    const int nx = box.dims[0], ny = box.dims[1], nz = box.dims[2];
    std::vector<float> slab(size_t(ny) * nz);
    std::vector<char> fill(size_t(ny) * nz);
    openvdb::FloatGrid::Accessor acc = grid.getAccessor();
    for (int i = 0; i < nx; ++i) {
        tbb::parallel_for(tbb::blocked_range<int>(0, ny), [&](const tbb::blocked_range<int> &r) {
            openvdb::FloatGrid::ConstAccessor read = grid.getConstAccessor();
            for (int j = r.begin(); j != r.end(); ++j)
                for (int k = 0; k < nz; ++k) {
                    const openvdb::Coord ijk(i, j, k);
                    const size_t at = size_t(j) * nz + k;
                    fill[at] = !read.isValueOn(ijk);
                    if (fill[at]) {
                        const Vec3 q = worldOf(box, ijk);
                        const float d = float(tree.distance(q));
                        const bool inside = signByWinding ? tree(q) > 0.5 : read.getValue(ijk) < 0;
                        slab[at] = inside ? -d : d;
                    }
                }
        });
        for (int j = 0; j < ny; ++j)
            for (int k = 0; k < nz; ++k)
                if (fill[size_t(j) * nz + k])
                    acc.setValueOn(openvdb::Coord(i, j, k), slab[size_t(j) * nz + k]);
        progress.report(100 * (i + 1) / nx);
    }
}

double seconds(std::chrono::steady_clock::time_point since)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

} // namespace

bool planBox(const TriangleMesh &mesh, const Options &opt, BoxGeometry &box, std::string &error)
{
    double extent[3], longest = 0;
    for (int k = 0; k < 3; ++k) {
        extent[k] = mesh.hi[k] - mesh.lo[k];
        longest = std::max(longest, extent[k]);
    }
    const double pad = opt.padding;
    if (opt.voxelSize > 0) {
        box.voxelSize = opt.voxelSize;
    } else {
        const double intervals = opt.res - 1 - 2 * pad;
        if (intervals < 1) {
            error = "--res " + std::to_string(opt.res) + " leaves no room for the mesh inside a padding of " +
                    std::to_string(pad) + " voxels on each side";
            return false;
        }
        box.voxelSize = longest / intervals;
    }
    for (int k = 0; k < 3; ++k) {
        const double sides = std::ceil(extent[k] / box.voxelSize + 2 * pad - 1e-9) + 1;
        if (!(sides <= kMaxResolution)) {
            error = "voxel size " + std::to_string(box.voxelSize) + " makes the box " + std::to_string(sides) +
                    " voxels long, above the limit of " + std::to_string(kMaxResolution);
            return false;
        }
        box.dims[k] = int(sides);
        box.origin[k] = mesh.lo[k] - pad * box.voxelSize;
    }
    if ((opt.full || !opt.npy.empty()) && box.voxelCount() > kMaxDenseVoxels) {
        error = "dense output (--full or --npy) of " + std::to_string(box.voxelCount()) +
                " voxels is above the limit of 2^31";
        return false;
    }
    return true;
}

openvdb::FloatGrid::Ptr buildGrid(const TriangleMesh &mesh, const BoxGeometry &box, const Options &opt,
                                  Progress &progress, BuildStats &stats)
{
    openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(box.voxelSize);
    xform->postTranslate(openvdb::Vec3d(box.origin[0], box.origin[1], box.origin[2]));

    const bool winding = opt.sign == SignMethod::Winding;
    const float band = float(opt.band);

    const bool needTree = winding || opt.full;
    std::unique_ptr<FastWinding> tree;
    if (needTree)
        tree.reset(new FastWinding(mesh.points, mesh.triangles));

    openvdb::FloatGrid::Ptr grid;
    if (opt.sign == SignMethod::Flood) {
        // OpenVDB's own band and sign, for comparison.
        progress.stage("distances", 0, opt.full ? 60 : 100);
        IndexSpaceMesh adapter(mesh, box);
        grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(progress, adapter, *xform, band, band, 0);
    } else {
        const auto t0 = std::chrono::steady_clock::now();
        progress.stage("exact distance", 0, winding ? 40 : (opt.full ? 60 : 100));
        grid = exactBandGrid(mesh, box, band, progress);
        if (winding) {
            progress.stage("sign", 40, opt.full ? 60 : 100);
            signBand(grid->tree(), box, *tree, mesh, progress);
        }
        stats.windingSeconds = seconds(t0);
    }
    grid->setTransform(xform);
    if (opt.full) {
        progress.stage("dense distances", 60, 100);
        fillBox(*grid, box, *tree, winding, progress);
    }
    grid->setGridClass(opt.sign == SignMethod::None ? openvdb::GRID_UNKNOWN : openvdb::GRID_LEVEL_SET);
    return grid;
}

} // namespace mesh2sdf
