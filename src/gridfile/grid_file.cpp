// sdftrace — the one writer of grid files, for `sdftrace bake` and mesh2sdf:
// NanoVDB through NanoVDB's own converter and writer, OpenVDB through
// OpenVDB's. See grid_file.h.
#include "grid_file.h"

#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>

#include <nanovdb/util/GridChecksum.h>
#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>
#include <openvdb/openvdb.h>

#include "fail.h"
#include "sdftrace/grid.h"

namespace sdft_vdb
{

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

// The checksum `grid` (a buffer's grid of type `type`) had, in the mode it
// was made (none, partial or full), computed again over its bytes.
template <typename BuildT> static void checksum_again(nanovdb::GridHandle<> &handle, uint64_t was)
{
    if (auto *grid = handle.grid<BuildT>())
        nanovdb::updateChecksum(*grid, nanovdb::GridChecksum(was).mode());
}

nanovdb::GridHandle<> with_tables(nanovdb::GridHandle<> handle)
{
    sdft_grid_options o = sdft_grid_options_defaults();
    o.data = handle.data(), o.size = handle.size(), o.memory = SDFT_GRID_BORROW;
    sdft_grid *g = nullptr;
    void *bytes = nullptr;
    size_t size = 0;
    sdft_error rc = sdft_grid_open(&o, &g, nullptr, 0);
    if (rc == SDFT_OK)
        rc = sdft_grid_export(g, &bytes, &size, nullptr, 0);
    sdft_grid_free(g);
    if (rc == SDFT_ENOMEM)
        throw std::bad_alloc();
    if (rc != SDFT_OK) // a grid the tracer does not take (not scalar, empty): as it is
        return handle;
    const std::unique_ptr<void, decltype(&std::free)> exported(bytes, &std::free);
    const uint64_t was = handle.gridMetaData()->checksum();
    const nanovdb::GridType type = handle.gridMetaData()->gridType();
    // The grid without its tables goes before the copy with them is made:
    // two copies of the grid in memory at a time, not three.
    handle.reset();
    nanovdb::HostBuffer buffer = nanovdb::HostBuffer::create(size);
    std::memcpy(buffer.data(), exported.get(), size);
    nanovdb::GridHandle<> out(std::move(buffer));
    switch (type) {
    case nanovdb::GridType::Float:
        checksum_again<float>(out, was);
        break;
    case nanovdb::GridType::Fp16:
        checksum_again<nanovdb::Fp16>(out, was);
        break;
    case nanovdb::GridType::Fp8:
        checksum_again<nanovdb::Fp8>(out, was);
        break;
    case nanovdb::GridType::Fp4:
        checksum_again<nanovdb::Fp4>(out, was);
        break;
    case nanovdb::GridType::FpN:
        checksum_again<nanovdb::FpN>(out, was);
        break;
    default:
        break;
    }
    return out;
}

sdft_error write_grid(const openvdb::FloatGrid &grid, bool nvdb, sdft_quant quant, const std::string &path,
                      const std::string &label, char *msg, size_t msg_len)
{
    return write_grids(grid, {}, nvdb, quant, path, label, msg, msg_len);
}

sdft_error write_grids(const openvdb::FloatGrid &grid, const std::vector<openvdb::FloatGrid::ConstPtr> &beside,
                       bool nvdb, sdft_quant quant, const std::string &path, const std::string &label, char *msg,
                       size_t msg_len)
{
    try {
        openvdb::initialize(); // the grid and metadata types a file names
        if (nvdb) {
            std::vector<nanovdb::GridHandle<>> handles;
            handles.push_back(with_tables(nano_handle(grid, quant)));
            for (const auto &g : beside)
                handles.push_back(nano_handle(*g, SDFT_QUANT_NONE));
            nanovdb::io::writeGrids(path, handles);
        } else {
            // A shallow copy (own metadata, shared tree) carries the half-float flag.
            openvdb::FloatGrid::Ptr out = openvdb::ConstPtrCast<openvdb::FloatGrid>(grid.copy());
            out->setSaveFloatAsHalf(quant == SDFT_QUANT_FP16);
            openvdb::GridCPtrVec grids{out};
            grids.insert(grids.end(), beside.begin(), beside.end());
            openvdb::io::File file(path);
            file.write(grids);
            file.close();
        }
    } catch (const std::bad_alloc &) {
        throw;
    } catch (const std::exception &e) {
        return fail_with(msg, msg_len, SDFT_EIO, "cannot write %s: %s", label.c_str(), e.what());
    }
    return SDFT_OK;
}

} // namespace sdft_vdb
