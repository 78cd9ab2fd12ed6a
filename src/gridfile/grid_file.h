// sdftrace — the one writer of grid files, shared by libsdftrace_vdb
// (`sdftrace bake`) and mesh2sdf: NanoVDB through NanoVDB's own converter
// and writer, OpenVDB through OpenVDB's. The interface of the internal
// library sdftrace_gridfile; its symbols are hidden in libsdftrace_vdb.
#ifndef SDFTRACE_GRIDFILE_GRID_FILE_H
#define SDFTRACE_GRIDFILE_GRID_FILE_H

#include <string>
#include <vector>

#include <nanovdb/util/GridHandle.h>
#include <openvdb/openvdb.h>

#include "sdftrace/vdb.h"

namespace sdft_vdb
{

// NanoVDB's own conversion of a float grid, leaves stored as `quant`.
nanovdb::GridHandle<> nano_handle(const openvdb::FloatGrid &grid, sdft_quant quant);

// The grid of `handle` with sdftrace's acceleration tables stored after it
// (sdft_grid_export: NanoVDB blind data; its checksum made again in the
// mode it had), or the handle as it is where the tracer does not take the
// grid. May throw std::bad_alloc.
nanovdb::GridHandle<> with_tables(nanovdb::GridHandle<> handle);

// Writes `grid` to `path`: NanoVDB (.nvdb, leaves as `quant`) or OpenVDB
// (.vdb, halves when quant is SDFT_QUANT_FP16), chosen by `nvdb`; a
// NanoVDB file carries the tracer's tables (with_tables). Writes in
// place: callers write to a temporary file (src/common/atomic_file.h) and
// rename it. SDFT_OK, or SDFT_EIO with "cannot write LABEL: reason" (label:
// the name to report, the final path rather than the temporary one). May
// throw std::bad_alloc.
sdft_error write_grid(const openvdb::FloatGrid &grid, bool nvdb, sdft_quant quant, const std::string &path,
                      const std::string &label, char *msg, size_t msg_len);

// The same with more grids after `grid` in the file, each stored as float
// whatever `quant` (a surface's material grids).
sdft_error write_grids(const openvdb::FloatGrid &grid, const std::vector<openvdb::FloatGrid::ConstPtr> &beside,
                       bool nvdb, sdft_quant quant, const std::string &path, const std::string &label, char *msg,
                       size_t msg_len);

} // namespace sdft_vdb

#endif
