// sdftrace — a delay-loaded OpenVDB float grid streamed into a NanoVDB
// buffer, leaf by leaf, so that the OpenVDB tree and the whole NanoVDB copy
// are never in memory together.
//
// WHY. NanoVDB's own converter (openToNanoVDB) wants the whole OpenVDB grid
// in memory and keeps it while it writes the whole NanoVDB grid: a 4096^3
// level set (2.3 GB as NanoVDB) peaked at 5.2 GB and took 25 s to load. Here
// the file is opened with OpenVDB's delayed loading, so reading the grid
// gives its topology only (masks and tiles; each leaf knows where its
// values lie in the memory-mapped file). The NanoVDB layout follows from
// the topology alone (breadth-first, as openToNanoVDB writes it: grid,
// tree, root, upper nodes, lower nodes, leaves), so the buffer is
// allocated once at its final size, and each lower node's leaves are
// loaded, copied (or quantized to Fp16) into their place and deleted, in
// parallel over lower nodes, a batch of about 64 MiB of values at a time.
// After each batch the mapped file's pages, which count as resident memory
// once read, are dropped from this process's mapping (they stay in the
// page cache), and the deleted leaves' memory is handed back to the system
// (malloc_trim), so that resident memory stays near the NanoVDB grid's
// size plus the OpenVDB tree's internal nodes.
//
// WHERE. In the process that keeps the grid (deferred leaves) on TBB's
// pool; loaded whole, in the reader process (vdb_load.cpp, stream_into),
// on threads of its own, into the memory the caller will map.
//
// DEFERRED (sdft_grid_options.defer, what `render` uses on big grids): the same layout
// and every node above the leaves, but no leaf is read here. The NanoVDB
// grid keeps the OpenVDB grid and a list of its leaves in NanoVDB's order,
// and fills a leaf from the file the first time it is read
// (fill_deferred; the core's side is src/grid/grid_deferred.c), the way
// vdb_render reads only the leaves its rays reach.
//
// WHAT IT WRITES. The same structure as openToNanoVDB with StatsMode::
// Disable and ChecksumMode::Disable: node origins as bounding boxes,
// statistics zero, checksum "none", the root's bounding box the active
// voxels'. Fp16 leaves are quantized as NanoVDB quantizes them (leaf
// minimum, quantum (max - min) / 65535, codes rounded to nearest). Tested
// voxel for voxel against openToNanoVDB's grid (tests/test_vdb_stream.c).
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <sys/mman.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <unistd.h>

#include <nanovdb/NanoVDB.h>
#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>

#include "vdb_internal.h"

namespace sdft_vdb
{

namespace
{

using OpenTree = openvdb::FloatTree;
using OpenRoot = OpenTree::RootNodeType;
using OpenUpper = OpenRoot::ChildNodeType;
using OpenLower = OpenUpper::ChildNodeType;
using OpenLeaf = OpenLower::ChildNodeType;

// The mapping of `path` that OpenVDB's delayed loading made, found in
// /proc/self/maps; {nullptr, 0} when there is none (or not on Linux).
struct Mapping {
    void *at = nullptr;
    size_t size = 0;
};

Mapping find_mapping(const char *path)
{
    Mapping m;
    char real[4096];
    if (!realpath(path, real))
        return m;
    std::ifstream maps("/proc/self/maps");
    std::string line;
    while (std::getline(maps, line)) {
        const size_t slash = line.find('/');
        if (slash == std::string::npos || line.compare(slash, std::string::npos, real) != 0)
            continue;
        unsigned long lo, hi, offset;
        if (std::sscanf(line.c_str(), "%lx-%lx %*s %lx", &lo, &hi, &offset) == 3 && offset == 0 && hi - lo > m.size)
            m = {reinterpret_cast<void *>(lo), hi - lo};
    }
    return m;
}

// body(l) for every l in [l0, l1), in parallel: on TBB's pool in the
// process that keeps the grid, on threads of its own in read_isolated's
// child (run_in_threads), where no pool survives fork.
using Runner = std::function<void(uint64_t l0, uint64_t l1, const std::function<void(uint64_t)> &body)>;

void run_on_tbb(uint64_t l0, uint64_t l1, const std::function<void(uint64_t)> &body)
{
    tbb::parallel_for(tbb::blocked_range<uint64_t>(l0, l1, 1), [&](const tbb::blocked_range<uint64_t> &r) {
        for (uint64_t l = r.begin(); l != r.end(); ++l)
            body(l);
    });
}

template <typename BuildT> struct Stream {
    using NanoGrid = nanovdb::NanoGrid<BuildT>;
    using NanoTree = nanovdb::NanoTree<BuildT>;
    using NanoRoot = nanovdb::NanoRoot<BuildT>;
    using NanoUpper = nanovdb::NanoUpper<BuildT>;
    using NanoLower = nanovdb::NanoLower<BuildT>;
    using NanoLeaf = nanovdb::NanoLeaf<BuildT>;

    openvdb::FloatGrid &grid;
    std::vector<const OpenUpper *> uppers;
    std::vector<OpenLower *> lowers;
    std::vector<uint64_t> first_lower; // per upper: index of its first child in lowers
    std::vector<uint64_t> first_leaf;  // per lower: index of its first child leaf
    uint64_t leaves = 0;
    uint64_t at_tree = 0, at_root = 0, at_upper = 0, at_lower = 0, at_leaf = 0, size = 0;
    uint32_t root_tiles = 0, tile_count[3] = {0, 0, 0}; // active tiles per level, as TreeData counts them
    uint8_t *buf = nullptr;

    explicit Stream(openvdb::FloatGrid &g) : grid(g) {}

    // The breadth-first layout, from the topology alone.
    void layout()
    {
        OpenRoot &root = grid.tree().root();
        for (auto it = root.beginChildOn(); it; ++it) {
            first_lower.push_back(lowers.size());
            uppers.push_back(&*it);
            tile_count[1] += it->getValueMask().countOn();
            for (auto jt = it->beginChildOn(); jt; ++jt) {
                first_leaf.push_back(leaves);
                lowers.push_back(&*jt);
                leaves += jt->getChildMask().countOn();
                tile_count[0] += jt->getValueMask().countOn();
            }
        }
        for (auto it = root.cbeginValueOn(); it; ++it)
            tile_count[2]++;
        root_tiles = root.getTableSize();
        at_tree = NanoGrid::memUsage();
        at_root = at_tree + NanoTree::memUsage();
        at_upper = at_root + NanoRoot::memUsage(root_tiles);
        at_lower = at_upper + uppers.size() * NanoUpper::memUsage();
        at_leaf = at_lower + lowers.size() * NanoLower::memUsage();
        size = at_leaf + leaves * NanoLeaf::DataType::memUsage();
    }

    // The active voxels of a leaf, as a box: its value mask holds voxel
    // (x, y, z) at bit 64 x + 8 y + z, so word x says whether column x has
    // any, the words' union has byte y set for each row y that does, and the
    // union of its bytes bit z for each z. Empty when none is active.
    static openvdb::CoordBBox leaf_active_box(const OpenLeaf &leaf)
    {
        const auto &mask = leaf.getValueMask();
        uint64_t any = 0;
        int x0 = 8, x1 = -1;
        for (int x = 0; x < 8; x++) {
            const uint64_t w = mask.template getWord<uint64_t>(x);
            any |= w;
            if (w)
                x0 = std::min(x0, x), x1 = x;
        }
        if (!any)
            return openvdb::CoordBBox();
        uint32_t rows = 0, zs = 0;
        for (int y = 0; y < 8; y++) {
            const uint32_t b = uint32_t(any >> (8 * y)) & 0xFFu;
            rows |= uint32_t(b != 0) << y;
            zs |= b;
        }
        const int y0 = __builtin_ctz(rows), y1 = 31 - __builtin_clz(rows);
        const int z0 = __builtin_ctz(zs), z1 = 31 - __builtin_clz(zs);
        const openvdb::Coord o = leaf.origin();
        return openvdb::CoordBBox(o.offsetBy(x0, y0, z0), o.offsetBy(x1, y1, z1));
    }

    // The active voxels' index box, as grid.evalActiveVoxelBoundingBox()
    // gives it: the union of the active tiles' boxes and of each leaf's
    // active voxels. A union does not depend on the order it is taken in,
    // so the lower nodes go in parallel, and a leaf's box comes from its
    // mask's words (OpenVDB visits every active voxel, serially: about
    // 0.1 s for the million leaves of a 4096^3 level set).
    openvdb::CoordBBox active_box(const Runner &run) const
    {
        const OpenRoot &root = grid.tree().root();
        std::vector<openvdb::CoordBBox> per_lower(lowers.size());
        run(0, lowers.size(), [&](uint64_t i) {
            openvdb::CoordBBox b;
            for (auto it = lowers[i]->cbeginValueOn(); it; ++it)
                b.expand(it.getCoord(), OpenLeaf::DIM);
            for (auto it = lowers[i]->cbeginChildOn(); it; ++it)
                b.expand(leaf_active_box(*it));
            per_lower[i] = b;
        });
        openvdb::CoordBBox box;
        for (const openvdb::CoordBBox &b : per_lower)
            box.expand(b);
        for (const OpenUpper *u : uppers)
            for (auto it = u->cbeginValueOn(); it; ++it)
                box.expand(it.getCoord(), OpenLower::DIM);
        for (auto it = root.cbeginValueOn(); it; ++it)
            box.expand(it.getCoord(), OpenUpper::DIM);
        return box;
    }

    NanoUpper *upper(uint64_t i) const
    {
        return reinterpret_cast<NanoUpper *>(buf + at_upper + i * NanoUpper::memUsage());
    }
    NanoLower *lower(uint64_t i) const
    {
        return reinterpret_cast<NanoLower *>(buf + at_lower + i * NanoLower::memUsage());
    }
    NanoLeaf *leaf(uint64_t i) const
    {
        return reinterpret_cast<NanoLeaf *>(buf + at_leaf + i * NanoLeaf::DataType::memUsage());
    }

    // A leaf's header: zeroed (the values too, for Fp16, whose header and
    // codes interleave with padding), its origin and active mask. Returns
    // its data, for the values.
    static typename NanoLeaf::DataType *write_header(const OpenLeaf &from, NanoLeaf *to)
    {
        auto *data = to->data();
        if constexpr (std::is_same<BuildT, float>::value) /* the header; the values follow */
            std::memset(static_cast<void *>(data), 0,
                        size_t(reinterpret_cast<uint8_t *>(data->mValues) - reinterpret_cast<uint8_t *>(data)));
        else
            std::memset(static_cast<void *>(data), 0, NanoLeaf::DataType::memUsage());
        data->setOrigin(from.origin());
        data->mValueMask = from.valueMask();
        return data;
    }

    // A leaf whose values could not be read: its header and masks, NaN
    // values (rays see no surface there).
    static void write_unreadable_leaf(const OpenLeaf &from, NanoLeaf *to)
    {
        auto *data = write_header(from, to);
        const float nan = std::numeric_limits<float>::quiet_NaN();
        if constexpr (std::is_same<BuildT, float>::value)
            std::fill(data->mValues, data->mValues + 512, nan);
        else
            data->init(nan, nan, 16);
    }

    // One leaf's values, from the file, into its NanoVDB leaf.
    static void write_leaf(const OpenLeaf &from, NanoLeaf *to)
    {
        auto *data = write_header(from, to);
        const float *src = from.buffer().data(); // reads the leaf from the mapped file
        if constexpr (std::is_same<BuildT, float>::value) {
            std::memcpy(data->mValues, src, sizeof(data->mValues));
        } else { // as OpenToNanoVDB's processLeafs for Fp16
            float min = std::numeric_limits<float>::max(), max = -min;
            for (int i = 0; i < 512; i++)
                min = src[i] < min ? src[i] : min, max = src[i] > max ? src[i] : max;
            data->init(min, max, 16);
            const double encode = max > min ? 65535.0 / double(max - min) : 0.0; /* float difference, as NanoVDB */
            auto *code = reinterpret_cast<uint16_t *>(data->mCode);
            for (int i = 0; i < 512; i++)
                code[i] = uint16_t(encode * (src[i] - min) + 0.5);
        }
    }

    // A lower node, its leaves written and then deleted from the OpenVDB
    // tree (their values no longer needed); with `deferred`, its leaves
    // only listed there, in NanoVDB's order, for fill_deferred.
    void write_lower(uint64_t l, Progress &progress, const OpenLeaf **deferred)
    {
        OpenLower &from = *lowers[l];
        auto *data = lower(l)->data();
        std::memset(static_cast<void *>(data), 0, NanoLower::memUsage());
        data->mBBox[0] = from.origin();
        data->mBBox[1] = from.origin() + openvdb::Coord(OpenLower::DIM - 1);
        data->mValueMask = from.getValueMask();
        data->mChildMask = from.getChildMask();
        // Entry by entry through the node's own table (OpenVDB's iterators
        // test the mask and build a coordinate per entry: 4096 per node).
        // Progress counts leaves: each one copied, or, when they are only
        // listed, all of the node's at once (a shared count, touched by
        // every thread, costs more than listing a leaf).
        const uint64_t first = first_leaf[l];
        uint64_t next = first;
        const auto *table = from.getTable();
        const auto &children = from.getChildMask();
        for (uint32_t n = 0; n < OpenLower::NUM_VALUES; n++) {
            if (children.isOn(n)) {
                const OpenLeaf *child = table[n].getChild();
                if (deferred) {
                    deferred[next] = child;
                } else {
                    write_leaf(*child, leaf(next));
                    progress.step();
                }
                data->setChild(n, leaf(next++));
            } else {
                data->setValue(n, table[n].getValue());
            }
        }
        if (deferred)
            progress.step(next - first);
        // Children become tiles: the leaves and their buffers are freed.
        if (!deferred)
            from.fill(from.getNodeBoundingBox(), grid.background(), false);
    }

    void write_upper(uint64_t u)
    {
        const OpenUpper &from = *uppers[u];
        auto *data = upper(u)->data();
        std::memset(static_cast<void *>(data), 0, NanoUpper::memUsage());
        data->mBBox[0] = from.origin();
        data->mBBox[1] = from.origin() + openvdb::Coord(OpenUpper::DIM - 1);
        data->mValueMask = from.getValueMask();
        data->mChildMask = from.getChildMask();
        uint64_t next = first_lower[u];
        float value = 0.0f;
        for (auto it = from.cbeginChildAll(); it; ++it) {
            if (it.probeChild(value))
                data->setChild(it.pos(), lower(next++));
            else
                data->setValue(it.pos(), value);
        }
    }

    void write_root(const openvdb::CoordBBox &active)
    {
        const OpenRoot &from = grid.tree().root();
        auto *data = reinterpret_cast<NanoRoot *>(buf + at_root)->data();
        std::memset(static_cast<void *>(data), 0, NanoRoot::memUsage(root_tiles));
        data->mBBox[0] = active.min();
        data->mBBox[1] = active.max();
        data->mBackground = data->mMinimum = data->mMaximum = from.background();
        uint64_t next = 0;
        float value = 0.0f;
        for (auto it = from.cbeginChildAll(); it; ++it) {
            auto *tile = data->tile(data->mTableSize++);
            if (it.probeChild(value))
                tile->setChild(it.getCoord(), upper(next++), data);
            else
                tile->setValue(it.getCoord(), it.isValueOn(), value);
        }
    }

    void write_tree(uint64_t voxels)
    {
        auto *data = reinterpret_cast<NanoTree *>(buf + at_tree)->data();
        std::memset(static_cast<void *>(data), 0, NanoTree::memUsage());
        data->setRoot(reinterpret_cast<NanoRoot *>(buf + at_root));
        data->setFirstNode(uppers.empty() ? nullptr : upper(0));
        data->setFirstNode(lowers.empty() ? nullptr : lower(0));
        data->setFirstNode(leaves == 0 ? nullptr : leaf(0));
        data->mNodeCount[0] = uint32_t(leaves);
        data->mNodeCount[1] = uint32_t(lowers.size());
        data->mNodeCount[2] = uint32_t(uppers.size());
        for (int k = 0; k < 3; k++)
            data->mTileCount[k] = tile_count[k];
        data->mVoxelCount = voxels;
    }

    void write_grid(const openvdb::CoordBBox &active)
    {
        auto *data = reinterpret_cast<NanoGrid *>(buf)->data();
        std::memset(static_cast<void *>(data), 0, NanoGrid::memUsage());
        data->mMagic = NANOVDB_MAGIC_NUMBER;
        data->mChecksum = ~uint64_t(0); // no checksum
        data->mVersion = nanovdb::Version();
        data->mFlags = static_cast<uint32_t>(nanovdb::GridFlags::IsBreadthFirst);
        data->mGridIndex = 0;
        data->mGridCount = 1;
        data->mGridSize = size;
        std::strncpy(data->mGridName, grid.getName().c_str(), nanovdb::GridData::MaxNameSize - 1);
        data->mGridClass = grid.getGridClass() == openvdb::GRID_LEVEL_SET    ? nanovdb::GridClass::LevelSet
                           : grid.getGridClass() == openvdb::GRID_FOG_VOLUME ? nanovdb::GridClass::FogVolume
                                                                             : nanovdb::GridClass::Unknown;
        data->mGridType = std::is_same<BuildT, float>::value ? nanovdb::GridType::Float : nanovdb::GridType::Fp16;
        const auto affine = grid.transform().baseMap()->getAffineMap();
        const openvdb::Vec3d voxel = affine->voxelSize();
        data->mVoxelSize =
            grid.hasUniformVoxels() ? nanovdb::Vec3R(voxel[0]) : nanovdb::Vec3R(voxel[0], voxel[1], voxel[2]);
        const auto mat = affine->getMat4();
        data->mMap.set(mat, mat.inverse(), 1.0);
        const openvdb::BBoxd world = grid.transform().indexToWorld(active);
        const openvdb::Vec3d lo = world.min(), hi = world.max();
        data->mWorldBBox =
            nanovdb::BBox<nanovdb::Vec3R>(nanovdb::Vec3R(lo[0], lo[1], lo[2]), nanovdb::Vec3R(hi[0], hi[1], hi[2]));
    }

    // Every lower node written, its leaves copied (or with `listed`, only
    // listed there), in batches of an eighth of the leaves, at most 32768
    // (64 MiB of values); after each, the file pages read so far and the
    // deleted leaves leave this process's resident memory. false: stopped
    // by the progress callback.
    bool write_lowers(const char *path, Progress &shown, const OpenLeaf **listed, const Runner &run)
    {
        const Mapping mapping = listed ? Mapping() : find_mapping(path);
        const uint64_t per_batch =
            listed ? leaves + 1 : std::min<uint64_t>(32768, std::max<uint64_t>(1024, leaves / 8));
        for (uint64_t l0 = 0; l0 < lowers.size();) {
            uint64_t l1 = l0;
            while (l1 < lowers.size() && first_leaf[l1] - first_leaf[l0] < per_batch)
                l1++;
            run(l0, l1, [&](uint64_t l) { write_lower(l, shown, listed); });
            if (mapping.at)
                madvise(mapping.at, mapping.size, MADV_DONTNEED); // a read-only file mapping: re-read on demand
#if defined(__GLIBC__)
            if (!listed)
                malloc_trim(0); // the deleted leaves' memory back to the system, not kept in malloc's free lists
#endif
            l0 = l1;
            if (shown.stop)
                return false;
        }
        return true;
    }

    // Every node above the lower nodes, the tree and the grid.
    void write_top(const openvdb::CoordBBox &active, uint64_t voxels)
    {
        for (uint64_t u = 0; u < uppers.size(); u++)
            write_upper(u);
        write_root(active);
        write_tree(voxels);
        write_grid(active);
    }
};

// The grid's release function for the buffer it adopts.
void release_buffer(void *buf) { std::free(buf); }

// What a deferred grid keeps to fill its leaves: the OpenVDB grid (its tree
// and, through its leaves, the mapped file) and its leaves in NanoVDB's
// order.
struct Deferred {
    openvdb::FloatGrid::Ptr grid;
    std::vector<const OpenLeaf *> leaves;
};

// sdft_leaf_fill_fn: leaf `index` read from the file into `leaf`. Called
// by the grid at most once per leaf, from any thread; OpenVDB's delayed
// loading reads a leaf under that leaf's own lock. No exception leaves.
template <typename BuildT> int fill_deferred(void *user, uint64_t index, void *leaf) noexcept
{
    const auto *d = static_cast<const Deferred *>(user);
    auto *to = static_cast<typename Stream<BuildT>::NanoLeaf *>(leaf);
    if (index >= d->leaves.size())
        return 1;
    try {
        Stream<BuildT>::write_leaf(*d->leaves[index], to);
        // The OpenVDB leaf's copy of its values goes: swapped with an empty
        // buffer, which frees it. Nothing reads that leaf again (the grid
        // fills each leaf once), and no other thread touches it.
        openvdb::FloatTree::LeafNodeType::Buffer empty(openvdb::PartialCreate(), 0.0f);
        const_cast<OpenLeaf *>(d->leaves[index])->buffer().swap(empty);
        return 0;
    } catch (...) { // the file changed or went away under the grid
        Stream<BuildT>::write_unreadable_leaf(*d->leaves[index], to);
        return 1;
    }
}

// The deferred grid's OpenVDB tree goes in parallel: a million leaves,
// each with its file reference, take a while to free one by one (spot at
// 4096^3: 0.24 s to free the grid, against 0.30 s deleting it whole).
void release_deferred(void *user) noexcept
{
    std::unique_ptr<Deferred> d(static_cast<Deferred *>(user));
    try {
        std::vector<OpenLower *> lowers;
        d->grid->tree().getNodes(lowers);
        const float background = d->grid->background();
        tbb::parallel_for(tbb::blocked_range<size_t>(0, lowers.size(), 16), [&](const tbb::blocked_range<size_t> &r) {
            for (size_t i = r.begin(); i != r.end(); ++i)
                lowers[i]->fill(lowers[i]->getNodeBoundingBox(), background, false);
        });
    } catch (...) { // out of memory for the list: the grid goes whole, below
    }
}

// The layout of `grid`, checked: an affine transform, a size this machine
// can hold.
template <typename BuildT> sdft_error plan(Stream<BuildT> &s, char *msg, size_t msg_len)
{
    if (!s.grid.transform().baseMap()->isLinear())
        return fail(msg, msg_len, SDFT_EFORMAT, "grid '" + s.grid.getName() + "' has a non-affine transform");
    s.layout();
    return SDFT_OK;
}

template <typename BuildT>
sdft_error stream(openvdb::FloatGrid::Ptr grid_ptr, const char *path, sdft_defer defer, sdft_progress_fn progress,
                  void *progress_user, sdft_grid **out, char *msg, size_t msg_len, const ReadTimes *times)
{
    openvdb::FloatGrid &grid = *grid_ptr;
    Stream<BuildT> s(grid);
    if (sdft_error rc = plan(s, msg, msg_len))
        return rc;
    const openvdb::CoordBBox active = s.active_box(run_on_tbb);
    const uint64_t voxels = grid.tree().activeVoxelCount();
    s.buf = static_cast<uint8_t *>(std::aligned_alloc(64, (s.size + 63) & ~uint64_t(63)));
    if (!s.buf)
        return fail(msg, msg_len, SDFT_ENOMEM,
                    "out of memory for a " + std::to_string(s.size >> 20) + " MiB grid '" + grid.getName() + "'");
    std::unique_ptr<Deferred> deferred(defer ? new Deferred{grid_ptr, {}} : nullptr);
    if (deferred)
        deferred->leaves.resize(s.leaves);
    // The buffer is the grid's once adopted; until then, freed on every way out.
    std::unique_ptr<uint8_t, void (*)(void *)> owned(s.buf, std::free);
    Progress shown;
    shown.fn = progress;
    shown.user = progress_user;
    shown.total = s.leaves ? s.leaves : 1;
    if (!s.write_lowers(path, shown, deferred ? deferred->leaves.data() : nullptr, run_on_tbb))
        return fail(msg, msg_len, SDFT_ECANCELED, std::string("loading ") + path + " stopped by its progress callback");
    s.write_top(active, voxels);
    sdft_grid_options o = sdft_grid_options_defaults();
    o.memory = SDFT_GRID_ADOPT;
    o.release = release_buffer;
    o.size = s.size;
    if (deferred) {
        o.fill = fill_deferred<BuildT>, o.fill_release = release_deferred, o.defer = defer;
        o.fill_user = deferred.release();
    } else {
        grid.clear(); // the OpenVDB tree's nodes (~100 MB at 4096^3) go before the bounds are built
    }
    o.data = owned.release();
    if (times)
        o.read_ms = 1e3 * (seconds_now() - times->start), o.read_serial_ms = times->serial_ms;
    return sdft_grid_open(&o, out, msg, msg_len);
}

template <typename BuildT>
sdft_error stream_into_as(openvdb::FloatGrid &grid, const char *path, int threads, Progress &shown,
                          const std::function<void *(uint64_t)> &place, uint64_t *size, char *msg, size_t msg_len)
{
    Stream<BuildT> s(grid);
    if (sdft_error rc = plan(s, msg, msg_len))
        return rc;
    const Runner run = [threads](uint64_t l0, uint64_t l1, const std::function<void(uint64_t)> &body) {
        run_in_threads(threads, l1 - l0, [&](uint64_t i) { body(l0 + i); });
    };
    const openvdb::CoordBBox active = s.active_box(run);
    const uint64_t voxels = grid.tree().activeVoxelCount();
    s.buf = static_cast<uint8_t *>(place(s.size));
    if (!s.buf)
        return fail(msg, msg_len, SDFT_ENOMEM,
                    "out of memory for a " + std::to_string(s.size >> 20) + " MiB grid '" + grid.getName() + "'");
    shown.total = s.leaves ? s.leaves : 1;
    if (!s.write_lowers(path, shown, nullptr, run))
        return fail(msg, msg_len, SDFT_ECANCELED, std::string("loading ") + path + " stopped");
    s.write_top(active, voxels);
    *size = s.size;
    return SDFT_OK;
}

} // namespace

sdft_error stream_to_nano(openvdb::FloatGrid::Ptr grid, const char *path, sdft_quant quant, sdft_defer defer,
                          sdft_progress_fn progress, void *progress_user, sdft_grid **out, char *msg, size_t msg_len,
                          const ReadTimes *times)
{
    return quant == SDFT_QUANT_FP16
               ? stream<nanovdb::Fp16>(grid, path, defer, progress, progress_user, out, msg, msg_len, times)
               : stream<float>(grid, path, defer, progress, progress_user, out, msg, msg_len, times);
}

sdft_error stream_into(openvdb::FloatGrid &grid, const char *path, sdft_quant quant, int threads, Progress &progress,
                       const std::function<void *(uint64_t)> &place, uint64_t *size, char *msg, size_t msg_len)
{
    return quant == SDFT_QUANT_FP16
               ? stream_into_as<nanovdb::Fp16>(grid, path, threads, progress, place, size, msg, msg_len)
               : stream_into_as<float>(grid, path, threads, progress, place, size, msg, msg_len);
}

} // namespace sdft_vdb
