// sdftrace — grid building (see build.h).
#include "grid/build.h"
#include "grid/flood_grid.h"

#include "distance/band.h"
#include "distance/nearest_triangle.h"
#include "sign/winding.h"
#include "sign/winding_sign.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace meshsdf
{

namespace
{

Vec3 worldOf(const BoxGeometry &box, const openvdb::Coord &ijk)
{
    return {box.origin[0] + ijk[0] * box.voxelSize, box.origin[1] + ijk[1] * box.voxelSize,
            box.origin[2] + ijk[2] * box.voxelSize};
}

// The exact band (band.h) as a tree with background `band` voxels in world
// units: a leaf per block, its band voxels active, signed by `sign` when
// given (else unsigned). Inactive values are +background, or -background
// where `sign` puts them inside.
openvdb::FloatGrid::Ptr exactBandGrid(const TriangleMesh &mesh, const BoxGeometry &box, float band,
                                      const WindingSign *sign, bool simd, Progress &progress)
{
    using Leaf = openvdb::FloatTree::LeafNodeType;
    static_assert(Leaf::DIM == kBlockDim, "band blocks are OpenVDB leaves");
    const float background = band * float(box.voxelSize);
    std::vector<Leaf *> leaves;
    std::mutex leavesMutex;
    // A cancelled progress (Progress::listen) throws out of exactBand: the
    // leaves made so far are not yet the tree's.
    try {
        exactBand(
            mesh, box.origin, box.voxelSize, band,
            [&](const std::array<int, 3> &origin, float *distance) {
                if (sign)
                    sign->signBlock(origin, distance);
                auto *leaf = new Leaf(openvdb::Coord(origin[0], origin[1], origin[2]), background, false);
                for (int v = 0; v < kBlockSize; ++v)
                    if (std::isfinite(distance[v]))
                        leaf->setValueOn(openvdb::Index(v), distance[v]);
                    else if (distance[v] < 0)
                        leaf->setValueOnly(openvdb::Index(v), -background);
                std::lock_guard<std::mutex> lock(leavesMutex);
                leaves.push_back(leaf);
            },
            [&](int percent) { progress.report(percent); }, simd);
    } catch (...) {
        for (Leaf *leaf : leaves)
            delete leaf;
        throw;
    }
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(background);
    for (Leaf *leaf : leaves)
        grid->tree().addLeaf(leaf); // the tree takes ownership
    return grid;
}

// The cubes of undecided tiles: 8^3 with their sides (0: a leaf signed voxel
// by voxel).
struct Cube {
    std::array<int, 3> origin;
    int side; // -1 inside, +1 outside, 0 split
};

// Appends the 8^3 cubes of the cube of size^3 voxels at `origin` with their
// sides: octants the bound decides whole pass their side to every 8^3 cube
// in them; 8^3 cubes it cannot decide get side 0.
void splitCube(const WindingSign &sign, const std::array<int, 3> &origin, int size, std::vector<Cube> &out)
{
    const int half = size / 2;
    for (int o = 0; o < 8; ++o) {
        const std::array<int, 3> at{origin[0] + (o >> 2) * half, origin[1] + ((o >> 1) & 1) * half,
                                    origin[2] + (o & 1) * half};
        const int side = sign.cubeSide(at, half);
        if (side == 0 && half > kBlockDim) {
            splitCube(sign, at, half, out);
            continue;
        }
        for (int x = 0; x < half; x += kBlockDim)
            for (int y = 0; y < half; y += kBlockDim)
                for (int z = 0; z < half; z += kBlockDim)
                    out.push_back({{at[0] + x, at[1] + y, at[2] + z}, side});
    }
}

// The sides of one internal node's tiles. Its table of children is split
// into octants: an octant that holds no child node is off the band whole
// and is decided in one piece when the bound allows (far from the surface
// most tiles go this way, many per winding number); otherwise it is split
// down to single tiles, and a tile still undecided into cubes.
template <typename NodeT> class NodeTileSides
{
  public:
    NodeTileSides(const NodeT &node, const WindingSign &sign) : mNode(node), mSign(sign) {}

    std::vector<std::pair<openvdb::Index, int>> decided; // (child offset, side)
    std::vector<Cube> cubes;                             // of undecided tiles

    void run() { octant({0, 0, 0}, kDim); }

  private:
    static constexpr int kDim = 1 << NodeT::LOG2DIM;         // children per axis
    static constexpr int kChild = NodeT::ChildNodeType::DIM; // voxels per child per axis

    static openvdb::Index offset(int x, int y, int z)
    {
        return openvdb::Index((((x << NodeT::LOG2DIM) | y) << NodeT::LOG2DIM) | z);
    }

    void octant(const std::array<int, 3> &at, int size)
    {
        bool children = false;
        for (int x = at[0]; x < at[0] + size && !children; ++x)
            for (int y = at[1]; y < at[1] + size && !children; ++y)
                for (int z = at[2]; z < at[2] + size && !children; ++z)
                    children = mNode.isChildMaskOn(offset(x, y, z));
        const openvdb::Coord origin = mNode.offsetToGlobalCoord(offset(at[0], at[1], at[2]));
        const std::array<int, 3> voxel{origin[0], origin[1], origin[2]};
        if (!children) {
            const int side = mSign.cubeSide(voxel, size * kChild);
            if (side != 0) {
                for (int x = at[0]; x < at[0] + size; ++x)
                    for (int y = at[1]; y < at[1] + size; ++y)
                        for (int z = at[2]; z < at[2] + size; ++z)
                            decided.emplace_back(offset(x, y, z), side);
                return;
            }
            if (size == 1) {
                if (kChild == kBlockDim)
                    cubes.push_back({voxel, 0});
                else
                    splitCube(mSign, voxel, kChild, cubes);
                return;
            }
        } else if (size == 1) {
            return; // a child node, signed on its own
        }
        const int half = size / 2;
        for (int o = 0; o < 8; ++o)
            octant({at[0] + (o >> 2) * half, at[1] + ((o >> 1) & 1) * half, at[2] + (o & 1) * half}, half);
    }

    const NodeT &mNode;
    const WindingSign &mSign;
};

// Gives every tile of a band tree whose leaves WindingSign has signed voxel
// by voxel the side its winding number gives (a flood fill would leak
// through a mesh's holes, and a tile's centre speaks only for itself), node
// by node in parallel (NodeTileSides); undecided 8^3 cubes become leaves of
// inactive voxels signed one by one. The background beyond the tree's
// internal nodes, far outside the box, stays outside.
void signTiles(openvdb::FloatTree &tree, const WindingSign &sign, Progress &progress)
{
    using Leaf = openvdb::FloatTree::LeafNodeType;
    using Node1 = openvdb::FloatTree::RootNodeType::ChildNodeType::ChildNodeType;
    using Node2 = openvdb::FloatTree::RootNodeType::ChildNodeType;
    const float background = tree.background();
    std::vector<Node1 *> nodes1;
    std::vector<Node2 *> nodes2;
    tree.getNodes(nodes1);
    tree.getNodes(nodes2);
    const size_t count = nodes1.size() + nodes2.size();
    std::vector<std::unique_ptr<NodeTileSides<Node1>>> sides1(nodes1.size());
    std::vector<std::unique_ptr<NodeTileSides<Node2>>> sides2(nodes2.size());
    std::atomic<size_t> done{0};
    // Decisions: 80% of this stage; leaves and the tree: the rest.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
            if (i < nodes1.size()) {
                sides1[i].reset(new NodeTileSides<Node1>(*nodes1[i], sign));
                sides1[i]->run();
            } else {
                sides2[i - nodes1.size()].reset(new NodeTileSides<Node2>(*nodes2[i - nodes1.size()], sign));
                sides2[i - nodes1.size()]->run();
            }
        }
        progress.report(int(80.0 * double(done.fetch_add(r.size()) + r.size()) / double(count)));
    });
    std::vector<Cube> cubes;
    for (const auto &s : sides1)
        cubes.insert(cubes.end(), s->cubes.begin(), s->cubes.end());
    for (const auto &s : sides2)
        cubes.insert(cubes.end(), s->cubes.begin(), s->cubes.end());
    // The undecided cubes alone, one task each: they are the costly few
    // among many decided ones, often side by side, and a range of all the
    // cubes left one thread to walk most of them.
    std::vector<size_t> undecided;
    for (size_t i = 0; i < cubes.size(); ++i)
        if (cubes[i].side == 0)
            undecided.push_back(i);
    std::vector<Leaf *> leaves(cubes.size(), nullptr);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, undecided.size(), 1), [&](const tbb::blocked_range<size_t> &r) {
        float distance[kBlockSize];
        for (size_t u = r.begin(); u != r.end(); ++u) {
            const size_t i = undecided[u];
            std::fill(distance, distance + kBlockSize, INFINITY);
            sign.signBlock(cubes[i].origin, distance);
            const openvdb::Coord at(cubes[i].origin[0], cubes[i].origin[1], cubes[i].origin[2]);
            leaves[i] = new Leaf(at, background, false);
            for (int v = 0; v < kBlockSize; ++v)
                if (distance[v] < 0)
                    leaves[i]->setValueOnly(openvdb::Index(v), -background);
        }
    });
    progress.report(90);
    // Tile values node by node, then the new structure.
    tbb::parallel_for(size_t(0), nodes1.size(), [&](size_t i) {
        for (const auto &d : sides1[i]->decided)
            nodes1[i]->addTile(d.first, d.second < 0 ? -background : background, false);
    });
    tbb::parallel_for(size_t(0), nodes2.size(), [&](size_t i) {
        for (const auto &d : sides2[i]->decided)
            nodes2[i]->addTile(d.first, d.second < 0 ? -background : background, false);
    });
    for (size_t i = 0; i < cubes.size(); ++i) {
        const openvdb::Coord at(cubes[i].origin[0], cubes[i].origin[1], cubes[i].origin[2]);
        if (leaves[i])
            tree.addLeaf(leaves[i]); // the tree takes ownership
        else
            tree.addTile(1, at, cubes[i].side < 0 ? -background : background, false);
    }
    progress.report(100);
}

// Voxel v of the packet at `packet` (NearestTriangle's numbering).
openvdb::Coord packetVoxel(const openvdb::Coord &packet, int v)
{
    constexpr int n = NearestTriangle::kPacketDim;
    return packet + openvdb::Coord(v / (n * n), v / n % n, v % n);
}

// The seed of a voxel at `offset` in its block, in the packet at
// `packetOffset`: the nearest triangle of the voxel on the face of the
// packet before it along z, y or x (the first of these that a search
// found), or none.
uint32_t packetSeed(const uint32_t *blockNearest, const openvdb::Coord &offset, const openvdb::Coord &packetOffset)
{
    using Leaf = openvdb::FloatTree::LeafNodeType;
    for (int k = 2; k >= 0; --k) {
        if (packetOffset[k] == 0)
            continue;
        openvdb::Coord before = offset;
        before[k] = packetOffset[k] - 1;
        const uint32_t t = blockNearest[Leaf::coordToOffset(before)];
        if (t != NearestTriangle::kNone)
            return t;
    }
    return NearestTriangle::kNone;
}

// --full: every voxel of the box not in the band gets its exact distance
// (NearestTriangle), with the sign its value in the tree already has (the
// winding sign of signTiles, OpenVDB's flood fill, or none). Block by block
// in parallel, each 8^3 block a leaf: the band's leaf where there is one,
// else a new leaf filled from the tile's value, added to the tree at the
// end. Each block is searched as packets of 4^3 voxels, one search per
// packet; band voxels (exact already) and voxels beyond the box only lend
// their known distance or nothing to the search.
void fillBox(openvdb::FloatGrid &grid, const BoxGeometry &box, const NearestTriangle &nearest, Progress &progress)
{
    using Leaf = openvdb::FloatTree::LeafNodeType;
    constexpr int kPacketDim = NearestTriangle::kPacketDim;
    static_assert(kBlockDim % kPacketDim == 0, "packets tile a block");
    openvdb::FloatTree &tree = grid.tree();
    struct Block {
        openvdb::Coord origin;
        Leaf *leaf; // the band's, or null: a new one from `tile`
        float tile;
    };
    std::vector<Block> blocks;
    for (int x = 0; x < box.dims[0]; x += kBlockDim)
        for (int y = 0; y < box.dims[1]; y += kBlockDim)
            for (int z = 0; z < box.dims[2]; z += kBlockDim) {
                const openvdb::Coord at(x, y, z);
                blocks.push_back({at, tree.probeLeaf(at), tree.getValue(at)});
            }
    std::atomic<size_t> done{0};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks.size()), [&](const tbb::blocked_range<size_t> &r) {
        constexpr int kPackets = kBlockDim / kPacketDim; // per axis
        double best[NearestTriangle::kPacketSize];
        uint32_t seed[NearestTriangle::kPacketSize];
        uint32_t blockNearest[kBlockSize];                   // leaf order
        openvdb::Index offset[NearestTriangle::kPacketSize]; // of the packet's voxels in the leaf
        bool wanted[NearestTriangle::kPacketSize];           // in the box, and not in the band
        for (size_t b = r.begin(); b != r.end(); ++b) {
            Block &block = blocks[b];
            if (!block.leaf)
                block.leaf = new Leaf(block.origin, block.tile, false);
            Leaf &leaf = *block.leaf;
            float *values = leaf.buffer().data();
            std::fill(blockNearest, blockNearest + kBlockSize, NearestTriangle::kNone);
            for (int p = 0; p < kPackets * kPackets * kPackets; ++p) {
                const openvdb::Coord packetOffset(p / (kPackets * kPackets) * kPacketDim,
                                                  p / kPackets % kPackets * kPacketDim, p % kPackets * kPacketDim);
                const openvdb::Coord packet = block.origin + packetOffset;
                bool any = false;
                for (int v = 0; v < NearestTriangle::kPacketSize; ++v) {
                    const openvdb::Coord ijk = packetVoxel(packet, v);
                    const openvdb::Index at = Leaf::coordToOffset(ijk);
                    offset[v] = at;
                    const bool inBox = ijk[0] < box.dims[0] && ijk[1] < box.dims[1] && ijk[2] < box.dims[2];
                    wanted[v] = inBox && !leaf.isValueOn(at);
                    if (!inBox)
                        best[v] = 0; // beyond the box: wanted by no one
                    else if (!wanted[v])
                        best[v] = double(values[at]) * values[at]; // the band's, exact
                    else
                        best[v] = INFINITY;
                    any = any || wanted[v];
                    seed[v] = packetSeed(blockNearest, ijk - block.origin, packetOffset);
                }
                if (!any)
                    continue;
                const Vec3 corner = worldOf(box, packet);
                nearest.packetDistance2(corner.data(), box.voxelSize, best, seed);
                for (int v = 0; v < NearestTriangle::kPacketSize; ++v) {
                    const openvdb::Index at = offset[v];
                    blockNearest[at] = seed[v];
                    if (!wanted[v])
                        continue;
                    const float d = float(std::sqrt(best[v]));
                    values[at] = values[at] < 0 ? -d : d; // the sign the tree gave it
                    leaf.setActiveState(at, true);
                }
            }
        }
        progress.report(int(100.0 * double(done.fetch_add(r.size()) + r.size()) / double(blocks.size())));
    });
    for (const Block &block : blocks)
        if (!tree.probeConstLeaf(block.origin))
            tree.addLeaf(block.leaf); // the tree takes ownership
}

} // namespace

int buildGridEnd(const sdft_mesh_grid_params &p) { return p.full ? 95 : 90; }

double gridPadding(const sdft_mesh_grid_params &p) { return p.padding < 0 ? p.band + 1.0 : p.padding; }

bool planBox(const TriangleMesh &mesh, const sdft_mesh_grid_params &p, BoxGeometry &box, std::string &error)
{
    double extent[3], longest = 0;
    for (int k = 0; k < 3; ++k) {
        extent[k] = mesh.hi[k] - mesh.lo[k];
        longest = std::max(longest, extent[k]);
    }
    const double pad = gridPadding(p);
    if (p.voxel_size > 0) {
        box.voxelSize = p.voxel_size;
    } else {
        const double intervals = p.res - 1 - 2 * pad;
        if (intervals < 1) {
            error = "--res " + std::to_string(p.res) + " leaves no room for the mesh inside a padding of " +
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
    if ((p.full || (p.formats & (1u << SDFT_MESH_FORMAT_NPY))) && box.voxelCount() > kMaxDenseVoxels) {
        error = "dense output (full, or an .npy file) of " + std::to_string(box.voxelCount()) +
                " voxels is above the limit of 2^31";
        return false;
    }
    return true;
}

openvdb::FloatGrid::Ptr buildGrid(const TriangleMesh &mesh, const BoxGeometry &box, const sdft_mesh_grid_params &p,
                                  Simd simd, WindingAccuracy accuracy, Progress &progress, BuildStats &stats)
{
    openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(box.voxelSize);
    xform->postTranslate(openvdb::Vec3d(box.origin[0], box.origin[1], box.origin[2]));

    const bool winding = p.sign == SDFT_MESH_SIGN_WINDING;
    const float band = float(p.band);

    // The hierarchies the run needs, built side by side (each is serial):
    // the winding tree and the open edges for the signs, the nearest
    // triangle's for --full.
    std::unique_ptr<FastWinding> tree;
    std::unique_ptr<EdgeField> edges;
    std::unique_ptr<NearestTriangle> nearest;
    const auto indexStart = std::chrono::steady_clock::now();
    tbb::parallel_invoke(
        [&] {
            if (winding)
                tree.reset(new FastWinding(mesh.points, mesh.triangles, simd.vector));
        },
        [&] {
            if (winding)
                edges.reset(new EdgeField(mesh));
        },
        [&] {
            if (p.full)
                nearest.reset(new NearestTriangle(mesh, simd.vector, simd.wide));
        });
    if (winding || p.full)
        stats.indexSeconds = seam::secondsSince(indexStart);

    // The bar: the band (with its leaves' signs) and the tiles' signs, then
    // dense distances with --full, each its share of the run's time on the
    // test meshes; writing takes the rest (the caller's).
    const int end = buildGridEnd(p), bandEnd = p.full ? 10 : 70, signEnd = p.full ? 15 : end;
    openvdb::FloatGrid::Ptr grid;
    if (p.sign == SDFT_MESH_SIGN_FLOOD) {
        // OpenVDB's own band and sign, for comparison.
        progress.stage("distances", 0, signEnd);
        grid = floodGrid(mesh, box, *xform, band, progress);
    } else {
        const auto t0 = std::chrono::steady_clock::now();
        progress.stage(winding ? "exact distance, sign" : "exact distance", 0, winding ? bandEnd : signEnd);
        std::unique_ptr<WindingSign> sign;
        // The ambiguous voxels counted are the grid's active ones: the band's,
        // and with --full the whole box's.
        if (winding)
            sign.reset(new WindingSign(std::move(*edges), *tree, box.origin, box.voxelSize, band, simd.vector, accuracy,
                                       p.full ? box.dims : std::array<int, 3>{0, 0, 0}));
        grid = exactBandGrid(mesh, box, band, sign.get(), simd.vector, progress);
        if (winding) {
            progress.stage("sign off the band", bandEnd, signEnd);
            signTiles(grid->tree(), *sign, progress);
            stats.ambiguousVoxels = sign->ambiguousVoxels();
            stats.windingSeconds = seam::secondsSince(t0);
        }
    }
    grid->setTransform(xform);
    if (p.full) {
        progress.stage("dense distances", signEnd, end);
        fillBox(*grid, box, *nearest, progress);
    }
    grid->setGridClass(p.sign == SDFT_MESH_SIGN_NONE ? openvdb::GRID_UNKNOWN : openvdb::GRID_LEVEL_SET);
    return grid;
}

} // namespace meshsdf
