// mesh2sdf — grid building (see grid.h).
#include "grid.h"

#include "band.h"
#include "nearest_triangle.h"
#include "winding.h"
#include "winding_sign.h"

#include <openvdb/tools/MeshToVolume.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
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

// The exact band (band.h) as a tree with background `band` voxels in world
// units: a leaf per block, its band voxels active, signed by `sign` when
// given (else unsigned). Inactive values are +background, or -background
// where `sign` puts them inside.
openvdb::FloatGrid::Ptr exactBandGrid(const TriangleMesh &mesh, const BoxGeometry &box, float band,
                                      const WindingSign *sign, Progress &progress)
{
    using Leaf = openvdb::FloatTree::LeafNodeType;
    static_assert(Leaf::DIM == kBlockDim, "band blocks are OpenVDB leaves");
    const float background = band * float(box.voxelSize);
    std::vector<Leaf *> leaves;
    std::mutex leavesMutex;
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
        [&](int percent) { progress.report(percent); });
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(background);
    for (Leaf *leaf : leaves)
        grid->tree().addLeaf(leaf); // the tree takes ownership
    return grid;
}

// Appends the 8^3 cubes of the cube of size^3 voxels at `origin` with their
// sides: octants the bound decides whole pass their side to every 8^3 cube
// in them; 8^3 cubes it cannot decide get side 0.
template <typename Cube>
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

// Gives every tile of a band tree whose leaves WindingSign has signed voxel
// by voxel the side its winding number gives (a flood fill would leak
// through a mesh's holes, and a tile's centre speaks only for itself): a
// cube the bound decides (WindingSign::cubeSide) takes one value; one it
// cannot decide is split into octants down to 8^3, and an 8^3 cube it cannot
// decide becomes a leaf of inactive voxels signed one by one.
void signTiles(openvdb::FloatTree &tree, const WindingSign &sign, Progress &progress)
{
    using Leaf = openvdb::FloatTree::LeafNodeType;
    const float background = tree.background();
    struct Cube {
        std::array<int, 3> origin;
        int side; // -1 inside, +1 outside, 0 split
    };
    std::vector<Cube> tiles;
    std::vector<int> sizes;
    for (auto it = tree.cbeginValueOff(); it; ++it) {
        if (!it.isTileValue())
            continue;
        openvdb::CoordBBox bbox;
        it.getBoundingBox(bbox);
        tiles.push_back({{bbox.min()[0], bbox.min()[1], bbox.min()[2]}, 0});
        sizes.push_back(bbox.dim()[0]);
    }
    // Each undecided tile's 8^3 cubes, in parallel; then the undecided ones
    // become leaves.
    std::vector<std::vector<Cube>> parts(tiles.size());
    std::atomic<size_t> done{0};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 16), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
            tiles[i].side = sign.cubeSide(tiles[i].origin, sizes[i]);
            if (tiles[i].side == 0 && sizes[i] > kBlockDim)
                splitCube(sign, tiles[i].origin, sizes[i], parts[i]);
            else if (tiles[i].side == 0)
                parts[i].push_back(tiles[i]);
        }
        progress.report(int(100.0 * double(done.fetch_add(r.size()) + r.size()) / double(tiles.size())));
    });
    std::vector<Cube> cubes;
    for (const auto &part : parts)
        cubes.insert(cubes.end(), part.begin(), part.end());
    std::vector<Leaf *> leaves(cubes.size(), nullptr);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, cubes.size(), 16), [&](const tbb::blocked_range<size_t> &r) {
        float distance[kBlockSize];
        for (size_t i = r.begin(); i != r.end(); ++i) {
            if (cubes[i].side != 0)
                continue;
            std::fill(distance, distance + kBlockSize, INFINITY);
            sign.signBlock(cubes[i].origin, distance);
            const openvdb::Coord at(cubes[i].origin[0], cubes[i].origin[1], cubes[i].origin[2]);
            leaves[i] = new Leaf(at, background, false);
            for (int v = 0; v < kBlockSize; ++v)
                if (distance[v] < 0)
                    leaves[i]->setValueOnly(openvdb::Index(v), -background);
        }
    });
    // Values first, in the iteration order of the list; then the structure.
    size_t next = 0;
    for (auto it = tree.beginValueOff(); it; ++it) {
        if (!it.isTileValue())
            continue;
        const Cube &tile = tiles[next++];
        if (tile.side != 0)
            it.setValue(tile.side < 0 ? -background : background);
    }
    for (size_t i = 0; i < cubes.size(); ++i) {
        const openvdb::Coord at(cubes[i].origin[0], cubes[i].origin[1], cubes[i].origin[2]);
        if (leaves[i])
            tree.addLeaf(leaves[i]); // the tree takes ownership
        else
            tree.addTile(1, at, cubes[i].side < 0 ? -background : background, false);
    }
}

// --full: every voxel of the box not in the band gets its exact distance
// (NearestTriangle), with the sign its value in the tree already has (the
// winding sign of signTiles, OpenVDB's flood fill, or none). Block by block
// in parallel, each 8^3 block a leaf: the band's leaf where there is one,
// else a new leaf filled from the tile's value, added to the tree at the
// end. Within a block, each voxel's search starts from the nearest triangle
// of the voxel before it along z (of the row before, for a row's first).
void fillBox(openvdb::FloatGrid &grid, const BoxGeometry &box, const NearestTriangle &nearest, Progress &progress)
{
    using Leaf = openvdb::FloatTree::LeafNodeType;
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
        for (size_t b = r.begin(); b != r.end(); ++b) {
            Block &block = blocks[b];
            if (!block.leaf)
                block.leaf = new Leaf(block.origin, block.tile, false);
            Leaf &leaf = *block.leaf;
            const int end[3] = {std::min(kBlockDim, box.dims[0] - block.origin[0]),
                                std::min(kBlockDim, box.dims[1] - block.origin[1]),
                                std::min(kBlockDim, box.dims[2] - block.origin[2])};
            uint32_t rowSeed = NearestTriangle::kNone;
            for (int x = 0; x < end[0]; ++x)
                for (int y = 0; y < end[1]; ++y) {
                    uint32_t seed = rowSeed;
                    bool first = true;
                    for (int z = 0; z < end[2]; ++z) {
                        const openvdb::Index v = openvdb::Index((((x << kBlockLog2) | y) << kBlockLog2) | z);
                        if (leaf.isValueOn(v))
                            continue; // in the band: exact already
                        const Vec3 q = worldOf(box, block.origin + openvdb::Coord(x, y, z));
                        const float d = float(std::sqrt(nearest.distance2(q.data(), seed)));
                        leaf.setValueOn(v, leaf.getValue(v) < 0 ? -d : d);
                        if (first)
                            rowSeed = seed;
                        first = false;
                    }
                }
        }
        progress.report(int(100.0 * double(done.fetch_add(r.size()) + r.size()) / double(blocks.size())));
    });
    for (const Block &block : blocks)
        if (!tree.probeConstLeaf(block.origin))
            tree.addLeaf(block.leaf); // the tree takes ownership
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

    std::unique_ptr<FastWinding> tree;
    if (winding)
        tree.reset(new FastWinding(mesh.points, mesh.triangles));

    openvdb::FloatGrid::Ptr grid;
    if (opt.sign == SignMethod::Flood) {
        // OpenVDB's own band and sign, for comparison.
        progress.stage("distances", 0, opt.full ? 60 : 100);
        IndexSpaceMesh adapter(mesh, box);
        grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(progress, adapter, *xform, band, band, 0);
    } else {
        const auto t0 = std::chrono::steady_clock::now();
        progress.stage(winding ? "exact distance, sign" : "exact distance", 0, opt.full ? 60 : 100);
        std::unique_ptr<WindingSign> sign;
        if (winding)
            sign.reset(new WindingSign(mesh, *tree, box.origin, box.voxelSize, band));
        grid = exactBandGrid(mesh, box, band, sign.get(), progress);
        if (winding)
            signTiles(grid->tree(), *sign, progress);
        stats.windingSeconds = seconds(t0);
    }
    grid->setTransform(xform);
    if (opt.full) {
        progress.stage("dense distances", 60, 100);
        fillBox(*grid, box, NearestTriangle(mesh), progress);
    }
    grid->setGridClass(opt.sign == SignMethod::None ? openvdb::GRID_UNKNOWN : openvdb::GRID_LEVEL_SET);
    return grid;
}

} // namespace mesh2sdf
