// sdftrace — `.vdb` files in: pick a scalar grid with OpenVDB (by the rule
// every loader shares, src/grid/grid_choose.h), make it a NanoVDB buffer,
// hand that to the C side.
//
// ONE READ. The file is untrusted, so OpenVDB reads it in a child process
// first (vdb_isolate.cpp). A grid loaded whole (streamed, float or Fp16,
// not deferred: what `render` does up to about 1024^3) is read by that
// child alone: it streams the grid into a shared file (memfd), its leaves
// decompressed on its own threads, and this process maps the file's pages
// as the grid's buffer, no copy and no second read. Otherwise (deferred
// leaves, other quantizations, NanoVDB's own converter) the child
// decompresses every leaf once, in parallel, and this process then reads
// the file itself as it wants it. The child's progress reaches the
// caller's callback through a shared page, read while it waits.
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <omp.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <openvdb/openvdb.h>

#include "../grid/grid_choose.h"
#include "vdb_internal.h"

namespace sdft_vdb
{

double seconds_now()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

sdft_error to_nano(const openvdb::FloatGrid &grid, sdft_quant quant, sdft_grid **out, char *msg, size_t msg_len,
                   const ReadTimes *times)
{
    nanovdb::GridHandle<> handle = nano_handle(grid, quant);
    sdft_grid_options o = sdft_grid_options_defaults();
    o.data = handle.data(), o.size = handle.size();
    if (times)
        o.read_ms = 1e3 * (seconds_now() - times->start), o.read_serial_ms = times->serial_ms;
    return sdft_grid_open(&o, out, msg, msg_len);
}

} // namespace sdft_vdb

using sdft_vdb::fail;

static bool is_scalar(const openvdb::GridBase &g)
{
    return g.isType<openvdb::FloatGrid>() || g.isType<openvdb::DoubleGrid>();
}

// The grid called `name` of `file` (already chosen), as floats.
static openvdb::FloatGrid::Ptr read_float_grid(openvdb::io::File &file, const std::string &name)
{
    openvdb::GridBase::Ptr base = file.readGrid(name);
    openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (grid)
        return grid;
    // A DoubleGrid: the same tree with float values. Tree's converting
    // constructor static_casts every value, tiles included.
    auto dbl = openvdb::gridPtrCast<openvdb::DoubleGrid>(base);
    grid = openvdb::FloatGrid::create(std::make_shared<openvdb::FloatTree>(dbl->tree()));
    grid->setTransform(dbl->transform().copy());
    grid->setGridClass(dbl->getGridClass());
    grid->setName(name);
    return grid;
}

// Opens `path` with delayed loading (leaf values stay in the mapped file
// until read) and picks its grid by the shared rule: SDFT_OK with *chosen.
static sdft_error choose(openvdb::io::File &file, const char *path, const char *name, std::string *chosen, char *msg,
                         size_t msg_len)
{
    if (FILE *f = std::fopen(path, "rb"))
        std::fclose(f);
    else
        return fail(msg, msg_len, SDFT_EIO, std::string("cannot open ") + path + ": " + std::strerror(errno));
    openvdb::initialize();
    openvdb::GridPtrVecPtr metas;
    try {
        file.open(true);
        metas = file.readAllGridMetadata();
    } catch (const std::bad_alloc &) {
        throw;
    } catch (const std::exception &e) {
        return fail(msg, msg_len, SDFT_EFORMAT, std::string("cannot read ") + path + ": " + e.what());
    }
    std::vector<std::string> names, types;
    for (const auto &m : *metas)
        names.push_back(m->getName()), types.push_back(m->valueType());
    std::vector<grid_candidate> entries;
    for (size_t i = 0; i < metas->size(); i++) {
        const openvdb::GridBase &m = *(*metas)[i];
        entries.push_back(
            {names[i].c_str(), types[i].c_str(), is_scalar(m), m.getGridClass() == openvdb::GRID_LEVEL_SET});
    }
    size_t pick = 0;
    if (sdft_error rc = grid_choose(entries.data(), entries.size(), name, path, &pick, msg, msg_len))
        return rc;
    *chosen = names[pick];
    return SDFT_OK;
}

// Every leaf of `tree` loaded (decompressed from the file) once, lower
// nodes on `threads` threads (run_in_threads: this runs in the forked
// child): each node's leaves read, then deleted, so that memory holds a
// few lower nodes' leaves at a time; progress counts leaves.
template <typename TreeT> static void load_every_leaf(TreeT &tree, int threads, sdft_vdb::Progress &shown)
{
    using Lower = typename TreeT::RootNodeType::ChildNodeType::ChildNodeType;
    std::vector<Lower *> lowers;
    tree.getNodes(lowers);
    shown.total = std::max<uint64_t>(1, tree.leafCount());
    const auto background = tree.background();
    sdft_vdb::run_in_threads(threads, lowers.size(), [&](uint64_t i) {
        Lower *lower = lowers[i];
        uint64_t n = 0;
        for (auto it = lower->beginChildOn(); it; ++it, ++n)
            (void)it->buffer().data();
        lower->fill(lower->getNodeBoundingBox(), background, false);
        shown.step(n);
    });
}

// What the child tells the caller of the grid it read.
struct ChildAnswer {
    uint64_t size;     // converted: the NanoVDB grid's bytes, from byte kGridAt of the shared file
    int32_t converted; // 1: the grid is in the shared file; 0: only read through, the caller reads the file itself
};

// The NanoVDB grid starts this far into the shared file; the page before
// holds the length of the mapping (for release_shared).
constexpr uint64_t kGridAt = 4096;

// Shared with the child: its progress, a fraction of its work done, and
// when its first parallel phase began (sdft_vdb::seconds_now; 0: not yet).
struct SharedProgress {
    std::atomic<float> done;
    std::atomic<double> parallel_at;
};

// The child's Progress callback: the fraction into the shared page.
static int child_progress(void *user, float done)
{
    static_cast<SharedProgress *>(user)->done.store(done, std::memory_order_relaxed);
    return 0;
}

// What the caller's thread watches while the child works: the child's
// progress, handed to the caller's callback a percent at a time (each one
// the child has passed since the last look, in order), and its answer to
// stop.
struct Watch {
    const sdft_grid_options *o;
    const SharedProgress *shared;
    int shown; /* percent */
};

static int watch_child(void *ctx)
{
    Watch *w = static_cast<Watch *>(ctx);
    const int done = int(100.0f * w->shared->done.load(std::memory_order_relaxed));
    for (; w->o->progress && w->shown < done;)
        if (w->o->progress(w->o->progress_user, float(++w->shown) / 100.0f))
            return 1;
    return 0;
}

// Whether the grid is loaded whole (by the child, into shared memory) or
// read by the caller itself: deferred (sdft_grid_defers, on the active box
// the file's metadata gives, as sdft_vdb_bounds reads it), other
// quantizations and NanoVDB's own converter are the caller's.
static bool loaded_whole(const openvdb::FloatGrid &grid, const sdft_grid_options *o)
{
    if (!o->stream || (o->quant != SDFT_QUANT_NONE && o->quant != SDFT_QUANT_FP16))
        return false;
    if (o->defer == SDFT_DEFER_NONE)
        return true;
    openvdb::CoordBBox box;
    try {
        const openvdb::Vec3i lo = grid.metaValue<openvdb::Vec3i>("file_bbox_min"),
                             hi = grid.metaValue<openvdb::Vec3i>("file_bbox_max");
        box = openvdb::CoordBBox(openvdb::Coord(lo[0], lo[1], lo[2]), openvdb::Coord(hi[0], hi[1], hi[2]));
    } catch (const openvdb::Exception &) { // not written by OpenVDB's own writer
        box = grid.evalActiveVoxelBoundingBox();
    }
    const int32_t lo[3] = {box.min()[0], box.min()[1], box.min()[2]},
                  hi[3] = {box.max()[0], box.max()[1], box.max()[2]};
    return !sdft_grid_defers(o->defer, grid.getGridClass() == openvdb::GRID_LEVEL_SET, grid.background(), lo, hi);
}

// The child's work (in read_isolated): choose the grid as load() would and
// read it with delayed loading; then either stream it whole into the
// shared file `memfd` (its pages become the caller's grid), or, when the
// caller reads the file itself, load every leaf once to see that OpenVDB
// can. Leaves on `threads` threads of its own.
static sdft_error read_in_child(const char *path, const char *name, const sdft_grid_options *o, int memfd, int threads,
                                SharedProgress *shared, void *answer, char *msg, size_t msg_len)
{
    openvdb::io::File file(path);
    std::string chosen;
    if (sdft_error rc = choose(file, path, name, &chosen, msg, msg_len))
        return rc;
    sdft_vdb::Progress shown;
    shown.fn = child_progress;
    shown.user = shared;
    std::memset(answer, 0, sizeof(ChildAnswer)); /* unaligned in the child's answer: bytes, not a ChildAnswer */
    try {
        openvdb::GridBase::Ptr base = file.readGrid(chosen); /* the topology, on one thread */
        shared->parallel_at.store(sdft_vdb::seconds_now());
        openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
        if (!grid || memfd < 0 || !loaded_whole(*grid, o)) {
            if (grid)
                load_every_leaf(grid->tree(), threads, shown);
            else if (auto d = openvdb::gridPtrCast<openvdb::DoubleGrid>(base))
                load_every_leaf(d->tree(), threads, shown);
            file.close();
            return SDFT_OK;
        }
        if (grid->activeVoxelCount() == 0)
            return fail(msg, msg_len, SDFT_EEMPTY, "grid '" + chosen + "' in " + path + " is empty: no active voxels");
        const auto place = [memfd](uint64_t size) -> void * {
            const uint64_t bytes = kGridAt + size;
            if (ftruncate(memfd, off_t(bytes)) != 0)
                return nullptr;
            void *at = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, memfd, 0);
            if (at == MAP_FAILED)
                return nullptr;
            std::memcpy(at, &bytes, sizeof bytes);
            return static_cast<char *>(at) + kGridAt;
        };
        uint64_t size = 0;
        if (sdft_error rc = sdft_vdb::stream_into(*grid, path, o->quant, threads, shown, place, &size, msg, msg_len))
            return rc;
        file.close();
        const ChildAnswer converted{size, 1};
        std::memcpy(answer, &converted, sizeof converted);
    } catch (const std::bad_alloc &) {
        throw;
    } catch (const std::exception &e) {
        return fail(msg, msg_len, SDFT_EFORMAT, std::string("cannot read ") + path + ": " + e.what());
    }
    return SDFT_OK;
}

// The grid's release function for a grid the child wrote: the shared
// mapping, whose length the page before the grid holds.
static void release_shared(void *data)
{
    char *at = static_cast<char *>(data) - kGridAt;
    uint64_t bytes;
    std::memcpy(&bytes, at, sizeof bytes);
    munmap(at, bytes);
}

// The grid the child wrote into `memfd`, `size` bytes, adopted.
static sdft_error map_child_grid(int memfd, uint64_t size, const char *path, const sdft_vdb::ReadTimes &times,
                                 sdft_grid **out, char *msg, size_t msg_len)
{
    struct stat st;
    if (fstat(memfd, &st) != 0 || uint64_t(st.st_size) != kGridAt + size)
        return fail(msg, msg_len, SDFT_EINTERNAL, std::string("reading ") + path + ": the reader process gave no grid");
    void *at = mmap(nullptr, kGridAt + size, PROT_READ | PROT_WRITE, MAP_SHARED, memfd, 0);
    if (at == MAP_FAILED)
        return fail(msg, msg_len, SDFT_ENOMEM, std::string("cannot map the grid read from ") + path);
    sdft_grid_options g = sdft_grid_options_defaults();
    g.data = static_cast<char *>(at) + kGridAt;
    g.size = size_t(size);
    g.memory = SDFT_GRID_ADOPT;
    g.release = release_shared;
    g.read_ms = 1e3 * (sdft_vdb::seconds_now() - times.start), g.read_serial_ms = times.serial_ms;
    return sdft_grid_open(&g, out, msg, msg_len); // releases the mapping when it refuses it
}

// A file descriptor closed on every way out.
struct Fd {
    int fd;
    ~Fd()
    {
        if (fd >= 0)
            close(fd);
    }
};

static sdft_error load(const char *path, const char *name, const sdft_grid_options *o, sdft_grid **out, char *msg,
                       size_t msg_len)
{
    // The file is untrusted and OpenVDB's reader is not safe on corrupt
    // files: only a child reads it (vdb_isolate.cpp), and where the grid
    // is loaded whole the child's reading is the only one: it writes the
    // NanoVDB grid into a shared file whose pages become this grid.
    // Otherwise the child reads every leaf once, in parallel, and then this
    // process reads the file itself.
    sdft_vdb::ReadTimes times;
    times.start = sdft_vdb::seconds_now();
    const int threads = std::max(1, omp_get_max_threads());
    Fd memfd{int(syscall(SYS_memfd_create, "sdftrace-grid", 1u /* MFD_CLOEXEC */))};
    void *page = mmap(nullptr, sizeof(SharedProgress), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (page == MAP_FAILED)
        return fail(msg, msg_len, SDFT_ENOMEM, "out of memory for a reader process");
    std::unique_ptr<SharedProgress, void (*)(SharedProgress *)> shared(new (page) SharedProgress{{0.0f}, {0.0}},
                                                                       [](SharedProgress *p) { munmap(p, sizeof *p); });
    Watch watch{o, shared.get(), 0};
    const isolated_extra extra{threads * sdft_vdb::thread_bytes, watch_child, &watch};
    ChildAnswer answer{0, 0};
    if (sdft_error rc = sdft_vdb::read_isolated(
            path, &answer, sizeof answer,
            [&](void *ans, char *m, size_t n) {
                return read_in_child(path, name, o, memfd.fd, threads, shared.get(), ans, m, n);
            },
            msg, msg_len, &extra))
        return rc;
    if (watch_child(&watch)) /* the last report, 1 when it is done */
        return fail(msg, msg_len, SDFT_ECANCELED, std::string("loading ") + path + " stopped by its progress callback");
    const double parallel_at = shared->parallel_at.load();
    times.serial_ms = parallel_at > 0.0 ? 1e3 * (parallel_at - times.start) : 0.0;
    if (answer.converted)
        return map_child_grid(memfd.fd, answer.size, path, times, out, msg, msg_len);
    openvdb::io::File file(path);
    std::string chosen;
    if (sdft_error rc = choose(file, path, name, &chosen, msg, msg_len))
        return rc;
    openvdb::FloatGrid::Ptr grid;
    try {
        const double topology = sdft_vdb::seconds_now();
        grid = read_float_grid(file, chosen); /* the topology again, on one thread, here */
        times.serial_ms += 1e3 * (sdft_vdb::seconds_now() - topology);
        file.close();
    } catch (const std::bad_alloc &) {
        throw;
    } catch (const std::exception &e) {
        return fail(msg, msg_len, SDFT_EFORMAT, std::string("cannot read ") + path + ": " + e.what());
    }
    if (grid->activeVoxelCount() == 0)
        return fail(msg, msg_len, SDFT_EEMPTY, "grid '" + chosen + "' in " + path + " is empty: no active voxels");
    if (o->stream && (o->quant == SDFT_QUANT_NONE || o->quant == SDFT_QUANT_FP16))
        return sdft_vdb::stream_to_nano(grid, path, o->quant, o->defer, o->progress, o->progress_user, out, msg,
                                        msg_len, &times);
    return sdft_vdb::to_nano(*grid, o->quant, out, msg, msg_len, &times);
}

static sdft_error bounds(const char *path, const char *name, sdft_aabb *box, char *msg, size_t msg_len)
{
    openvdb::io::File file(path);
    std::string chosen;
    if (sdft_error rc = choose(file, path, name, &chosen, msg, msg_len))
        return rc;
    try {
        // OpenVDB writes the active index box as file_bbox_min / file_bbox_max.
        const openvdb::GridBase::Ptr grid = file.readGridMetadata(chosen);
        const openvdb::Vec3i lo = grid->metaValue<openvdb::Vec3i>("file_bbox_min"),
                             hi = grid->metaValue<openvdb::Vec3i>("file_bbox_max");
        const openvdb::BBoxd world = grid->transform().indexToWorld(
            openvdb::BBoxd(openvdb::Vec3d(lo[0], lo[1], lo[2]) - 0.5, openvdb::Vec3d(hi[0], hi[1], hi[2]) + 0.5));
        *box = sdft_aabb{{float(world.min()[0]), float(world.min()[1]), float(world.min()[2])},
                         {float(world.max()[0]), float(world.max()[1]), float(world.max()[2])}};
    } catch (const std::bad_alloc &) {
        throw;
    } catch (const std::exception &e) {
        return fail(msg, msg_len, SDFT_EFORMAT, std::string("cannot read ") + path + ": " + e.what());
    }
    return SDFT_OK;
}

// The checked entry points are in vdb_open.c: in C, where an out-of-range
// sdft_quant is a plain int, not undefined behaviour.
extern "C" sdft_error vdb_open_checked(const char *path, const char *name, const sdft_grid_options *o, sdft_grid **out,
                                       char *msg, size_t msg_len)
{
    return sdft_vdb::guarded(path, msg, msg_len, [&] { return load(path, name, o, out, msg, msg_len); });
}

extern "C" sdft_error vdb_bounds_checked(const char *path, const char *name, sdft_aabb *box, char *msg, size_t msg_len)
{
    // Only the metadata is read; in a child all the same (vdb_isolate.cpp),
    // which hands the box back.
    return sdft_vdb::guarded(path, msg, msg_len, [&] {
        return sdft_vdb::read_isolated(
            path, box, sizeof *box,
            [&](void *o, char *m, size_t n) { return bounds(path, name, static_cast<sdft_aabb *>(o), m, n); }, msg,
            msg_len);
    });
}
