// sdftrace — the one writer of grid files, for `sdftrace bake` and mesh2sdf:
// NanoVDB through NanoVDB's own converter and writer, OpenVDB through
// OpenVDB's. See grid_file.h.
#include "grid_file.h"

#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>
#include <openvdb/openvdb.h>

#include "fail.h"

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
            handles.push_back(nano_handle(grid, quant));
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
