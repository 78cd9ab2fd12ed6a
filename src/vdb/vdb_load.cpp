// sdftrace — `.vdb` files in: pick a scalar grid with OpenVDB (by the rule
// every loader shares, src/grid/grid_choose.h), convert it with NanoVDB's own
// converter, hand the NanoVDB buffer to the C side.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <nanovdb/util/OpenToNanoVDB.h>
#include <openvdb/openvdb.h>

#include "../grid/grid_choose.h"
#include "vdb_internal.h"

namespace sdft_vdb {

template <typename BuildT> static nanovdb::GridHandle<> convert(const openvdb::FloatGrid &grid)
{
    return nanovdb::openToNanoVDB<nanovdb::HostBuffer, openvdb::FloatTree, BuildT>(grid);
}

nanovdb::GridHandle<> nano_handle(const openvdb::FloatGrid &grid, sdft_quant quant)
{
    switch (quant) {
    case SDFT_QUANT_FP16:
        return convert<nanovdb::Fp16>(grid);
    case SDFT_QUANT_FP8:
        return convert<nanovdb::Fp8>(grid);
    case SDFT_QUANT_FP4:
        return convert<nanovdb::Fp4>(grid);
    case SDFT_QUANT_FPN:
        return convert<nanovdb::FpN>(grid);
    default:
        return convert<float>(grid);
    }
}

sdft_error to_nano(const openvdb::FloatGrid &grid, sdft_quant quant, sdft_grid **out, char *msg, size_t msg_len)
{
    nanovdb::GridHandle<> handle = nano_handle(grid, quant);
    return sdft_grid_from_buffer(handle.data(), handle.size(), nullptr, out, msg, msg_len);
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

static sdft_error load(const char *path, const char *name, sdft_quant quant, sdft_grid **out, char *msg, size_t msg_len)
{
    if (FILE *f = std::fopen(path, "rb"))
        std::fclose(f);
    else
        return fail(msg, msg_len, SDFT_EIO, std::string("cannot open ") + path + ": " + std::strerror(errno));
    openvdb::initialize();
    openvdb::io::File file(path);
    openvdb::GridPtrVecPtr metas;
    try {
        file.open(false);
        metas = file.readAllGridMetadata();
    } catch (const std::exception &e) {
        return fail(msg, msg_len, SDFT_EFORMAT, std::string("cannot read ") + path + ": " + e.what());
    }
    std::vector<std::string> names, types;
    for (const auto &m : *metas)
        names.push_back(m->getName()), types.push_back(m->valueType());
    std::vector<sdft_grid_entry> entries;
    for (size_t i = 0; i < metas->size(); i++) {
        const openvdb::GridBase &m = *(*metas)[i];
        entries.push_back(
            {names[i].c_str(), types[i].c_str(), is_scalar(m), m.getGridClass() == openvdb::GRID_LEVEL_SET});
    }
    size_t pick = 0;
    if (sdft_error rc = sdft_grid_choose(entries.data(), entries.size(), name, path, &pick, msg, msg_len))
        return rc;
    openvdb::FloatGrid::Ptr grid;
    try {
        grid = read_float_grid(file, names[pick]);
        file.close();
    } catch (const std::bad_alloc &) {
        throw;
    } catch (const std::exception &e) {
        return fail(msg, msg_len, SDFT_EFORMAT, std::string("cannot read ") + path + ": " + e.what());
    }
    if (grid->activeVoxelCount() == 0)
        return fail(msg, msg_len, SDFT_EEMPTY, "grid '" + names[pick] + "' in " + path + " is empty: no active voxels");
    return sdft_vdb::to_nano(*grid, quant, out, msg, msg_len);
}

// The checked entry point is sdft_vdb_load (vdb_open.c): in C, where an
// out-of-range sdft_quant is a plain int, not undefined behaviour.
extern "C" sdft_error sdft_vdb_load_checked(const char *path, const char *name, sdft_quant quant, sdft_grid **out,
                                            char *msg, size_t msg_len)
{
    return sdft_vdb::guarded(path, msg, msg_len, [&] { return load(path, name, quant, out, msg, msg_len); });
}
