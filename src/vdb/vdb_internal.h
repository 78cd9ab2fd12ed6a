// sdftrace — what the C++ seam's translation units share, and what mesh2sdf
// borrows from them: NanoVDB conversion and the one NanoVDB / OpenVDB file
// writer. Internal header; its symbols are hidden in libsdftrace_vdb.
#ifndef SDFTRACE_VDB_INTERNAL_H
#define SDFTRACE_VDB_INTERNAL_H

#include <new>
#include <string>

#include <nanovdb/util/GridHandle.h>
#include <openvdb/openvdb.h>

#include "../core/fail.h"
#include "sdftrace/vdb.h"

// sdft_vdb_load once its arguments are checked (vdb_open.c).
extern "C" SDFT_INTERNAL sdft_error sdft_vdb_load_checked(const char *path, const char *name, sdft_quant quant,
                                                          sdft_grid **out, char *msg, size_t msg_len);

namespace sdft_vdb {

// Writes one line to msg; returns code.
inline sdft_error fail(char *msg, size_t msg_len, sdft_error code, const std::string &line)
{
    return sdft_fail(msg, msg_len, code, "%s", line.c_str());
}

// Runs body() and returns its code; an exception becomes a code and one
// line ("WHAT: reason"), so that none leaves an extern "C" function.
template <typename Body> sdft_error guarded(const char *what, char *msg, size_t msg_len, Body &&body) noexcept
{
    try {
        return body();
    } catch (const std::bad_alloc &) {
        return sdft_fail(msg, msg_len, SDFT_ENOMEM, "%s: out of memory", what);
    } catch (const std::exception &e) {
        return sdft_fail(msg, msg_len, SDFT_EINTERNAL, "%s: %s", what, e.what());
    } catch (...) {
        return sdft_fail(msg, msg_len, SDFT_EINTERNAL, "%s: unknown exception", what);
    }
}

// NanoVDB's own conversion of a float grid, leaves stored as `quant`.
nanovdb::GridHandle<> nano_handle(const openvdb::FloatGrid &grid, sdft_quant quant);

// NanoVDB copy of a float grid, leaves stored as `quant`, as an sdft_grid.
sdft_error to_nano(const openvdb::FloatGrid &grid, sdft_quant quant, sdft_grid **out, char *msg, size_t msg_len);

// Writes `grid` to `path`: NanoVDB (.nvdb, leaves as `quant`) or OpenVDB
// (.vdb, halves when quant is SDFT_QUANT_FP16), chosen by `nvdb`. Writes in
// place: callers write to a temporary file (src/util/atomic_file.h) and
// rename it. SDFT_OK, or SDFT_EIO with "cannot write LABEL: reason" (label:
// the name to report, the final path rather than the temporary one). May
// throw std::bad_alloc.
sdft_error write_grid(const openvdb::FloatGrid &grid, bool nvdb, sdft_quant quant, const std::string &path,
                      const std::string &label, char *msg, size_t msg_len);

} // namespace sdft_vdb

#endif
