// sdftrace — `.vdb` files in: pick a scalar grid with OpenVDB, convert it with
// NanoVDB's own converter, hand the NanoVDB buffer to the C side.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include <nanovdb/util/OpenToNanoVDB.h>
#include <openvdb/openvdb.h>

#include "vdb.h"
#include "vdb_internal.h"

namespace sdft_vdb {

int fail(char *msg, unsigned msg_len, int code, const std::string &line)
{
    if (msg && msg_len)
        std::snprintf(msg, msg_len, "%s", line.c_str());
    return code;
}

template <typename BuildT> static nanovdb::GridHandle<> convert(const openvdb::FloatGrid &grid)
{
    return nanovdb::openToNanoVDB<nanovdb::HostBuffer, openvdb::FloatTree, BuildT>(grid);
}

int to_nano(const openvdb::FloatGrid &grid, sdft_quant quant, sdft_grid **out, char *msg, unsigned msg_len)
{
    nanovdb::GridHandle<> handle;
    switch (quant) {
    case SDFT_QUANT_FP16: handle = convert<nanovdb::Fp16>(grid); break;
    case SDFT_QUANT_FP8: handle = convert<nanovdb::Fp8>(grid); break;
    case SDFT_QUANT_FP4: handle = convert<nanovdb::Fp4>(grid); break;
    case SDFT_QUANT_FPN: handle = convert<nanovdb::FpN>(grid); break;
    default: handle = convert<float>(grid); break;
    }
    return sdft_grid_from_buffer(handle.data(), handle.size(), nullptr, out, msg, msg_len);
}

} // namespace sdft_vdb

using sdft_vdb::fail;

static bool is_scalar(const openvdb::GridBase &g)
{
    return g.isType<openvdb::FloatGrid>() || g.isType<openvdb::DoubleGrid>();
}

extern "C" sdft_vdb_options sdft_vdb_options_defaults(void) { return sdft_vdb_options{SDFT_QUANT_NONE, 0, 1}; }

extern "C" int sdft_vdb_load(const char *path, const char *name, sdft_quant quant, sdft_grid **out, char *msg,
                             unsigned msg_len)
{
    sdft_vdb_options o = sdft_vdb_options_defaults();
    o.quant = quant;
    return sdft_vdb_open(path, name, &o, out, msg, msg_len);
}

extern "C" int sdft_vdb_open(const char *path, const char *name, const sdft_vdb_options *o, sdft_grid **out, char *msg,
                             unsigned msg_len)
{
    const sdft_quant quant = o->quant;
    *out = nullptr;
    if (FILE *f = std::fopen(path, "rb"))
        std::fclose(f);
    else
        return fail(msg, msg_len, SDFT_GRID_EIO, std::string("cannot open ") + path + ": " + std::strerror(errno));
    try {
        openvdb::initialize();
        openvdb::io::File file(path);
        file.open(true); // delayed loading: leaf values stay in the (mapped) file until read
        openvdb::GridPtrVecPtr metas = file.readAllGridMetadata();
        openvdb::GridBase::Ptr chosen;
        if (name) {
            for (auto &m : *metas)
                if (m->getName() == name)
                    chosen = m;
            if (!chosen)
                return fail(msg, msg_len, SDFT_GRID_ENOTFOUND, std::string(path) + " has no grid named '" + name + "'");
        } else {
            for (int pass = 0; pass < 2 && !chosen; pass++)
                for (auto &m : *metas)
                    if (!chosen && is_scalar(*m) && (pass == 1 || m->getGridClass() == openvdb::GRID_LEVEL_SET))
                        chosen = m;
            if (!chosen) {
                if (metas->empty())
                    return fail(msg, msg_len, SDFT_GRID_ENOTFOUND, std::string(path) + " holds no grids");
                const auto &first = *metas->front();
                return fail(msg, msg_len, SDFT_GRID_ENOTSCALAR,
                            std::string(path) + " holds no scalar grid (first grid '" + first.getName() + "' is " +
                                first.valueType() + ")");
            }
        }
        if (!is_scalar(*chosen))
            return fail(msg, msg_len, SDFT_GRID_ENOTSCALAR,
                        "grid '" + chosen->getName() + "' holds " + chosen->valueType() + " values, not scalar distances");
        const std::string grid_name = chosen->getName();
        openvdb::GridBase::Ptr base = file.readGrid(grid_name);
        file.close();
        openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
        if (!grid) { // a DoubleGrid: the same tree with float values
            auto dbl = openvdb::gridPtrCast<openvdb::DoubleGrid>(base);
            // Tree's converting constructor static_casts every value, tiles included.
            grid = openvdb::FloatGrid::create(std::make_shared<openvdb::FloatTree>(dbl->tree()));
            grid->setTransform(dbl->transform().copy());
            grid->setGridClass(dbl->getGridClass());
            grid->setName(grid_name);
        }
        if (grid->activeVoxelCount() == 0)
            return fail(msg, msg_len, SDFT_GRID_EEMPTY, "grid '" + grid_name + "' in " + path + " is empty: no active voxels");
        if (o->stream && (quant == SDFT_QUANT_NONE || quant == SDFT_QUANT_FP16))
            return sdft_vdb::stream_to_nano(*grid, path, quant, o->progress != 0, out, msg, msg_len);
        return sdft_vdb::to_nano(*grid, quant, out, msg, msg_len);
    } catch (const std::exception &e) {
        return fail(msg, msg_len, SDFT_GRID_EFORMAT, std::string("cannot read ") + path + ": " + e.what());
    }
}

extern "C" int sdft_grid_open(const char *path, const char *name, sdft_grid **out, char *msg, unsigned msg_len)
{
    const char *dot = std::strrchr(path, '.');
    if (dot && std::strcmp(dot, ".nvdb") == 0)
        return sdft_grid_load_nvdb(path, name, out, msg, msg_len);
    if (dot && std::strcmp(dot, ".vdb") == 0)
        return sdft_vdb_load(path, name, SDFT_QUANT_NONE, out, msg, msg_len);
    *out = nullptr;
    return fail(msg, msg_len, SDFT_GRID_EFORMAT, std::string(path) + ": expected a .vdb or .nvdb file");
}

extern "C" int sdft_vdb_bounds(const char *path, const char *name, sdft_aabb *bounds, char *msg, unsigned msg_len)
{
    try {
        openvdb::initialize();
        openvdb::io::File file(path);
        file.open(true);
        openvdb::GridBase::Ptr chosen;
        const openvdb::GridPtrVecPtr metas = file.readAllGridMetadata();
        for (auto &m : *metas)
            if (!chosen && (name ? m->getName() == name : is_scalar(*m)))
                chosen = m;
        if (!chosen)
            return fail(msg, msg_len, SDFT_GRID_ENOTFOUND, std::string(path) + " has no such grid");
        const openvdb::GridBase::Ptr grid = file.readGridMetadata(chosen->getName());
        const openvdb::Vec3i lo = grid->metaValue<openvdb::Vec3i>("file_bbox_min"),
                             hi = grid->metaValue<openvdb::Vec3i>("file_bbox_max");
        const openvdb::BBoxd world = grid->transform().indexToWorld(
            openvdb::BBoxd(openvdb::Vec3d(lo[0], lo[1], lo[2]) - 0.5, openvdb::Vec3d(hi[0], hi[1], hi[2]) + 0.5));
        *bounds = sdft_aabb{{float(world.min()[0]), float(world.min()[1]), float(world.min()[2])},
                            {float(world.max()[0]), float(world.max()[1]), float(world.max()[2])}};
        return SDFT_GRID_OK;
    } catch (const std::exception &e) {
        return fail(msg, msg_len, SDFT_GRID_EFORMAT, std::string("cannot read ") + path + ": " + e.what());
    }
}
