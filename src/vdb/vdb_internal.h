// sdftrace — what the C++ seam's translation units share. Internal header.
#ifndef SDFTRACE_VDB_INTERNAL_H
#define SDFTRACE_VDB_INTERNAL_H

#include <string>

#include <openvdb/openvdb.h>

#include "vdb.h"

namespace sdft_vdb {

// Writes one line to msg; returns code.
int fail(char *msg, unsigned msg_len, int code, const std::string &line);

// NanoVDB copy of a float grid, leaves stored as `quant`.
int to_nano(const openvdb::FloatGrid &grid, sdft_quant quant, sdft_grid **out, char *msg, unsigned msg_len);

} // namespace sdft_vdb

#endif
