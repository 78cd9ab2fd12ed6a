// mesh2sdf — grid building (see grid.h).
#include "grid.h"

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
#include <limits>
#include <vector>

namespace mesh2sdf {

namespace {

// The mesh as OpenVDB's MeshDataAdapter wants it: triangles with points in
// the grid's index space, converted on the fly in double precision.
class IndexSpaceMesh {
public:
    IndexSpaceMesh(const TriangleMesh& mesh, const BoxGeometry& box) : mMesh(mesh), mBox(box) {}
    size_t polygonCount() const { return mMesh.triangles.size(); }
    size_t pointCount() const { return mMesh.points.size(); }
    size_t vertexCount(size_t) const { return 3; }
    void getIndexSpacePoint(size_t n, size_t v, openvdb::Vec3d& pos) const
    {
        const auto& p = mMesh.points[mMesh.triangles[n][v]];
        for (int k = 0; k < 3; ++k)
            pos[k] = (double(p[k]) - mBox.origin[k]) / mBox.voxelSize;
    }

private:
    const TriangleMesh& mMesh;
    const BoxGeometry& mBox;
};

Vec3 worldOf(const BoxGeometry& box, const openvdb::Coord& ijk)
{
    return {box.origin[0] + ijk[0] * box.voxelSize, box.origin[1] + ijk[1] * box.voxelSize,
            box.origin[2] + ijk[2] * box.voxelSize};
}

// Sign of the active voxels of one leaf by the winding number, without
// evaluating it at every voxel. Two face-adjacent voxels a, b whose exact
// distances satisfy d(a) + d(b) > h lie on a segment that cannot cross the
// mesh (a crossing point x would give d(a) + d(b) <= |a-x| + |x-b| = h), so
// the winding number is continuous between them. It then changes sign
// (crosses 1/2) only in open space across a hole, i.e. next to a boundary
// or non-manifold edge. So: split the leaf's voxels into such connected
// components; a component whose voxels' nearest triangles are all away from
// open edges takes the sign of one voxel (the farthest from the surface);
// any other component is evaluated voxel by voxel.
constexpr uint32_t kNone = 0xffffffffu;

void signLeaf(openvdb::FloatTree::LeafNodeType& leaf, const BoxGeometry& box, const FastWinding& winding,
              const TriangleMesh& mesh, const uint32_t* nearest)
{
    using Leaf = openvdb::FloatTree::LeafNodeType;
    constexpr int kDim = int(Leaf::DIM), kSize = int(Leaf::SIZE);
    const float h = float(box.voxelSize) * (1.0f + 1e-5f);
    int component[kSize];
    std::fill(component, component + kSize, -1);
    int queue[kSize];
    for (int seed = 0; seed < kSize; ++seed) {
        if (!leaf.isValueOn(openvdb::Index(seed)) || component[seed] >= 0)
            continue;
        // Flood one component from `seed`, noting whether it touches an open
        // edge's triangles and which voxel lies farthest from the surface.
        int head = 0, tail = 0, farthest = seed;
        bool open = false;
        component[seed] = seed;
        queue[tail++] = seed;
        while (head < tail) {
            const int v = queue[head++];
            const float dv = leaf.getValue(openvdb::Index(v));
            open = open || mesh.nearOpenEdge[nearest[v]];
            if (dv > leaf.getValue(openvdb::Index(farthest)))
                farthest = v;
            const int x = v >> (2 * Leaf::LOG2DIM), y = (v >> Leaf::LOG2DIM) & (kDim - 1), z = v & (kDim - 1);
            const int next[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z}, {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
            for (const auto& n : next) {
                if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= kDim || n[1] >= kDim || n[2] >= kDim)
                    continue;
                const int u = (n[0] << (2 * Leaf::LOG2DIM)) | (n[1] << Leaf::LOG2DIM) | n[2];
                if (component[u] >= 0 || !leaf.isValueOn(openvdb::Index(u)) ||
                    !(dv + leaf.getValue(openvdb::Index(u)) > h))
                    continue;
                component[u] = seed;
                queue[tail++] = u;
            }
        }
        const bool inside = !open && winding(worldOf(box, leaf.offsetToGlobalCoord(openvdb::Index(farthest)))) > 0.5;
        for (int i = 0; i < tail; ++i) {
            const openvdb::Index v = openvdb::Index(queue[i]);
            const bool in = open ? winding(worldOf(box, leaf.offsetToGlobalCoord(v))) > 0.5 : inside;
            if (in)
                leaf.setValueOnly(v, -leaf.getValue(v));
        }
    }
}

// Makes every active voxel of OpenVDB's unsigned band exact and, when
// `sign`, negative where the winding number exceeds 1/2; in parallel over
// leaf nodes. OpenVDB's band values are exact next to the surface but only
// upper bounds farther out (its band expansion takes the nearest of the
// neighbours' triangles), so each is the bound of an exact search. Then
// gives inactive values the sign of their side: OpenVDB's signed flood fill
// inside leaves, the winding number at the centre of every tile (a flood
// fill would leak through a mesh's holes).
void finishBand(openvdb::FloatTree& tree, const BoxGeometry& box, const FastWinding& winding,
                const TriangleMesh& mesh, bool sign, Progress& progress)
{
    openvdb::tree::LeafManager<openvdb::FloatTree> leaves(tree);
    const size_t leafCount = leaves.leafCount();
    std::atomic<size_t> done{0};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, leafCount, 8), [&](const tbb::blocked_range<size_t>& r) {
        uint32_t nearest[openvdb::FloatTree::LeafNodeType::SIZE];
        for (size_t n = r.begin(); n != r.end(); ++n) {
            auto& leaf = leaves.leaf(n);
            for (auto it = leaf.beginValueOn(); it; ++it) {
                const Vec3 q = worldOf(box, it.getCoord());
                uint32_t& tri = nearest[it.pos()];
                tri = kNone;
                double d = winding.distance(q, double(*it) * (1.0 + 1e-4) + 1e-6 * box.voxelSize, &tri);
                if (tri == kNone) // OpenVDB's value was not an upper bound after all
                    d = winding.distance(q, INFINITY, &tri);
                it.setValue(float(d));
            }
            if (sign)
                signLeaf(leaf, box, winding, mesh, nearest);
        }
        const size_t d = done.fetch_add(r.size()) + r.size();
        progress.report(int(100.0 * double(d) / double(leafCount)));
    });

    if (!sign)
        return;
    const float background = tree.background();
    openvdb::tools::signedFloodFill(tree);
    for (auto it = tree.beginValueOff(); it; ++it) {
        if (!it.isTileValue())
            continue;
        openvdb::CoordBBox bbox;
        it.getBoundingBox(bbox);
        const openvdb::Vec3d c = bbox.getCenter();
        const Vec3 q{box.origin[0] + c[0] * box.voxelSize, box.origin[1] + c[1] * box.voxelSize,
                     box.origin[2] + c[2] * box.voxelSize};
        it.setValue(winding(q) > 0.5 ? -background : background);
    }
}

// --full: every voxel of the box not yet in the band gets its exact
// distance, signed by the winding number when `signByWinding`, else with the
// sign its region already has (OpenVDB's flood fill, or none). Slab by slab:
// distances in parallel, insertion into the tree serially.
void fillBox(openvdb::FloatGrid& grid, const BoxGeometry& box, const FastWinding& tree, bool signByWinding,
             Progress& progress)
{
    const int nx = box.dims[0], ny = box.dims[1], nz = box.dims[2];
    std::vector<float> slab(size_t(ny) * nz);
    std::vector<char> fill(size_t(ny) * nz);
    openvdb::FloatGrid::Accessor acc = grid.getAccessor();
    for (int i = 0; i < nx; ++i) {
        tbb::parallel_for(tbb::blocked_range<int>(0, ny), [&](const tbb::blocked_range<int>& r) {
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

bool planBox(const TriangleMesh& mesh, const Options& opt, BoxGeometry& box, std::string& error)
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
            error = "voxel size " + std::to_string(box.voxelSize) + " makes the box " +
                    std::to_string(sides) + " voxels long, above the limit of " + std::to_string(kMaxResolution);
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

openvdb::FloatGrid::Ptr buildGrid(const TriangleMesh& mesh, const BoxGeometry& box, const Options& opt,
                                  Progress& progress, BuildStats& stats)
{
    openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(box.voxelSize);
    xform->postTranslate(openvdb::Vec3d(box.origin[0], box.origin[1], box.origin[2]));

    const bool winding = opt.sign == SignMethod::Winding;
    const int flags = opt.sign == SignMethod::Flood ? 0 : openvdb::tools::UNSIGNED_DISTANCE_FIELD;
    const float band = float(opt.band);

    const bool needTree = opt.sign != SignMethod::Flood || opt.full;
    std::unique_ptr<FastWinding> tree;
    if (needTree)
        tree.reset(new FastWinding(mesh.points, mesh.triangles));

    progress.stage("distances", 0, opt.sign != SignMethod::Flood ? 55 : (opt.full ? 60 : 100));
    IndexSpaceMesh adapter(mesh, box);
    openvdb::FloatGrid::Ptr grid =
        openvdb::tools::meshToVolume<openvdb::FloatGrid>(progress, adapter, *xform, band, band, flags);

    if (opt.sign != SignMethod::Flood) {
        progress.stage(winding ? "exact distance, sign" : "exact distance", 55, opt.full ? 75 : 100);
        const auto t0 = std::chrono::steady_clock::now();
        finishBand(grid->tree(), box, *tree, mesh, winding, progress);
        stats.windingSeconds = seconds(t0);
    }
    if (opt.full) {
        progress.stage("dense distances", opt.sign != SignMethod::Flood ? 75 : 60, 100);
        fillBox(*grid, box, *tree, winding, progress);
    }
    grid->setGridClass(opt.sign == SignMethod::None ? openvdb::GRID_UNKNOWN : openvdb::GRID_LEVEL_SET);
    return grid;
}

} // namespace mesh2sdf
