// sdftrace — `.vdb` files in: pick a scalar grid with OpenVDB (by the rule
// every loader shares, src/grid/grid_choose.h), convert it with NanoVDB's own
// converter, hand the NanoVDB buffer to the C side.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>

#include "../grid/grid_choose.h"
#include "vdb_internal.h"

namespace sdft_vdb
{

sdft_error to_nano(const openvdb::FloatGrid &grid, sdft_quant quant, sdft_grid **out, char *msg, size_t msg_len)
{
    nanovdb::GridHandle<> handle = nano_handle(grid, quant);
    sdft_grid_options o = sdft_grid_options_defaults();
    o.data = handle.data(), o.size = handle.size();
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

// Every leaf of `tree` loaded (decompressed from the file) once, one lower
// node at a time: each is taken out of the tree, its leaves read, and
// deleted, so that memory holds one lower node's leaves. Serial: it runs in
// the forked child, where no thread pool survives.
template <typename TreeT> static void load_every_leaf(TreeT &tree)
{
    using Upper = typename TreeT::RootNodeType::ChildNodeType;
    using Lower = typename Upper::ChildNodeType;
    const auto background = tree.background();
    std::vector<openvdb::Coord> uppers, lowers;
    for (auto it = tree.root().cbeginChildOn(); it; ++it)
        uppers.push_back(it->origin());
    for (const openvdb::Coord &u : uppers) {
        std::unique_ptr<Upper> upper(tree.root().template stealNode<Upper>(u, background, false));
        lowers.clear();
        for (auto it = upper->cbeginChildOn(); it; ++it)
            lowers.push_back(it->origin());
        for (const openvdb::Coord &l : lowers) {
            std::unique_ptr<Lower> lower(upper->template stealNode<Lower>(l, background, false));
            for (auto it = lower->cbeginChildOn(); it; ++it)
                (void)it->buffer().data();
        }
    }
}

// What load() reads of `path` through OpenVDB, read once to see that
// OpenVDB can (in read_isolated's child): the header, the metadata, the
// chosen grid's topology with delayed loading, and every leaf's values.
static sdft_error read_through(const char *path, const char *name, char *msg, size_t msg_len)
{
    openvdb::io::File file(path);
    std::string chosen;
    if (sdft_error rc = choose(file, path, name, &chosen, msg, msg_len))
        return rc;
    try {
        openvdb::GridBase::Ptr base = file.readGrid(chosen);
        if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(base))
            load_every_leaf(f->tree());
        else if (auto d = openvdb::gridPtrCast<openvdb::DoubleGrid>(base))
            load_every_leaf(d->tree());
        file.close();
    } catch (const std::bad_alloc &) {
        throw;
    } catch (const std::exception &e) {
        return fail(msg, msg_len, SDFT_EFORMAT, std::string("cannot read ") + path + ": " + e.what());
    }
    return SDFT_OK;
}

static sdft_error load(const char *path, const char *name, const sdft_grid_options *o, sdft_grid **out, char *msg,
                       size_t msg_len)
{
    // The file is untrusted and OpenVDB's reader is not safe on corrupt
    // files: a child reads it first (vdb_isolate.cpp).
    if (sdft_error rc = sdft_vdb::read_isolated(
            path, nullptr, 0, [&](void *, char *m, size_t n) { return read_through(path, name, m, n); }, msg, msg_len))
        return rc;
    openvdb::io::File file(path);
    std::string chosen;
    if (sdft_error rc = choose(file, path, name, &chosen, msg, msg_len))
        return rc;
    openvdb::FloatGrid::Ptr grid;
    try {
        grid = read_float_grid(file, chosen);
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
                                        msg_len);
    return sdft_vdb::to_nano(*grid, o->quant, out, msg, msg_len);
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
