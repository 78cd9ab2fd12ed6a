// sdftrace — what the C++ seam's translation units share. Internal header.
#ifndef SDFTRACE_VDB_INTERNAL_H
#define SDFTRACE_VDB_INTERNAL_H

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <string>

#include <openvdb/openvdb.h>

#include "vdb.h"

// The grid side's memory and adoption (src/grid): a big table on huge pages
// where offered, and a grid made from a NanoVDB buffer from it, which it
// then owns (freed with the grid, or on failure).
extern "C" void *sdft_grid_table_alloc(size_t bytes);
extern "C" int sdft_grid_adopt(void *words, size_t size, sdft_grid **out, char *msg, unsigned msg_len);

namespace sdft_vdb {

// Writes one line to msg; returns code.
int fail(char *msg, unsigned msg_len, int code, const std::string &line);

// NanoVDB copy of a float grid, leaves stored as `quant`.
int to_nano(const openvdb::FloatGrid &grid, sdft_quant quant, sdft_grid **out, char *msg, unsigned msg_len);

// A delay-loaded float grid (read from `path`) streamed into a NanoVDB grid
// of float or Fp16 leaves (vdb_stream.cpp); the grid's leaves are deleted
// as they are copied. `progress`: a progress line on stderr if a terminal.
int stream_to_nano(openvdb::FloatGrid &grid, const char *path, sdft_quant quant, bool progress, sdft_grid **out,
                   char *msg, unsigned msg_len);

// A percentage on stderr, when on (the caller's terminal test), from any
// thread: "\rWHAT:  42%", then "\rWHAT: done".
struct Progress {
    bool on = false;
    std::atomic<uint64_t> done{0};
    std::atomic<int> shown{-1};
    uint64_t total = 1;
    const char *what = "";
    void step()
    {
        if (!on)
            return;
        int pct = int(100 * (done.fetch_add(1) + 1) / total);
        int old = shown.load();
        if (pct > old && shown.compare_exchange_strong(old, pct))
            std::fprintf(stderr, "\r%s: %3d%%", what, pct);
    }
    void finish()
    {
        if (on)
            std::fprintf(stderr, "\r%s: done\n", what);
    }
};

} // namespace sdft_vdb

#endif
