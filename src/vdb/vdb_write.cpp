// sdftrace — the one writer of grid files, for `sdftrace bake` and mesh2sdf:
// NanoVDB through NanoVDB's own converter and writer, OpenVDB through
// OpenVDB's. See vdb_internal.h.
#include <nanovdb/util/IO.h>
#include <openvdb/openvdb.h>

#include "vdb_internal.h"

namespace sdft_vdb
{

sdft_error write_grid(const openvdb::FloatGrid &grid, bool nvdb, sdft_quant quant, const std::string &path,
                      const std::string &label, char *msg, size_t msg_len)
{
    try {
        openvdb::initialize(); // the grid and metadata types a file names
        if (nvdb) {
            nanovdb::io::writeGrid(path, nano_handle(grid, quant));
        } else {
            // A shallow copy (own metadata, shared tree) carries the half-float flag.
            openvdb::FloatGrid::Ptr out = openvdb::ConstPtrCast<openvdb::FloatGrid>(grid.copy());
            out->setSaveFloatAsHalf(quant == SDFT_QUANT_FP16);
            openvdb::io::File file(path);
            file.write({out});
            file.close();
        }
    } catch (const std::bad_alloc &) {
        throw;
    } catch (const std::exception &e) {
        return fail(msg, msg_len, SDFT_EIO, "cannot write " + label + ": " + e.what());
    }
    return SDFT_OK;
}

} // namespace sdft_vdb
