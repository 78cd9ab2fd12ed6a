// sdftrace — what the C++ seam's translation units share (with the grid
// file writer, src/gridfile/grid_file.h). Internal header; its symbols are
// hidden in libsdftrace_vdb.
#ifndef SDFTRACE_VDB_INTERNAL_H
#define SDFTRACE_VDB_INTERNAL_H

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <new>
#include <string>

#include <nanovdb/util/GridHandle.h>
#include <openvdb/openvdb.h>

#include "fail.h"
#include "grid_file.h" /* nano_handle, write_grid: sdftrace_gridfile */
#include "isolated_read.h"
#include "sdftrace/vdb.h"
#include "seam.h"

// sdft_vdb_open and sdft_vdb_bounds once their arguments are checked
// (vdb_open.c).
extern "C" SDFT_INTERNAL sdft_error vdb_open_checked(const char *path, const char *name, const sdft_grid_options *o,
                                                     sdft_grid **out, char *msg, size_t msg_len);
extern "C" SDFT_INTERNAL sdft_error vdb_bounds_checked(const char *path, const char *name, sdft_aabb *box, char *msg,
                                                       size_t msg_len);

namespace sdft_vdb
{

// Writes one line to msg; returns code.
inline sdft_error fail(char *msg, size_t msg_len, sdft_error code, const std::string &line)
{
    return fail_with(msg, msg_len, code, "%s", line.c_str());
}

// The seams' one guard (src/common/seam.h): no exception leaves an
// extern "C" function.
using seam::guarded;

// A read of a `.vdb` file through OpenVDB: fills out (when it succeeds)
// and returns a code, with one line in msg otherwise.
using IsolatedRead = std::function<sdft_error(void *out, char *msg, size_t msg_len)>;

// Runs `read` of `path` in a forked child under a time and an address-space
// limit (vdb_isolate.cpp), with `extra` (NULL: none; isolated_read.h): its
// code, message and out_size bytes of out, or SDFT_EFORMAT with one line
// when the child crashed, was killed or ran past the time limit, or
// SDFT_ECANCELED when extra's watch stopped it.
sdft_error read_isolated(const char *path, void *out, size_t out_size, const IsolatedRead &read, char *msg,
                         size_t msg_len, const isolated_extra *extra = nullptr);

// In read_isolated's child, where no thread pool survives fork: body(i)
// for every i < n on `threads` threads of the child's own, the calling one
// among them, each taking the next i. The first exception a body throws
// is thrown again here, once every thread has stopped.
void run_in_threads(int threads, uint64_t n, const std::function<void(uint64_t)> &body);

// Address space each of run_in_threads' threads may take: its stack and a
// malloc arena (read_isolated's limit grows by this per thread).
constexpr double thread_bytes = double(72u << 20);

// What reading a `.vdb` grid has taken so far, for the grid's phases
// (sdft_grid_options.read_ms, read_serial_ms): when it began (seconds_now)
// and how much of it ran on one thread.
struct ReadTimes {
    double start = 0.0, serial_ms = 0.0;
};
double seconds_now(); // the steady clock, which the reader process shares

// NanoVDB copy of a float grid, leaves stored as `quant`, as an sdft_grid.
sdft_error to_nano(const openvdb::FloatGrid &grid, sdft_quant quant, sdft_grid **out, char *msg, size_t msg_len,
                   const ReadTimes *times = nullptr);

// A delay-loaded float grid (read from `path`) streamed into a NanoVDB grid
// of float or Fp16 leaves (vdb_stream.cpp); the grid's leaves are deleted
// as they are copied. With `defer`, only laid out: the NanoVDB grid keeps
// the OpenVDB grid and copies each leaf when first read. progress may be
// NULL.
sdft_error stream_to_nano(openvdb::FloatGrid::Ptr grid, const char *path, sdft_quant quant, sdft_defer defer,
                          sdft_progress_fn progress, void *progress_user, sdft_grid **out, char *msg, size_t msg_len,
                          const ReadTimes *times = nullptr);

// The child's side of loading a `.vdb` grid whole (vdb_load.cpp): `grid`,
// delay-loaded from `path`, streamed into the NanoVDB grid of float or
// Fp16 leaves (quant) that place(size) gives room for (NULL: no room,
// SDFT_ENOMEM), as stream_to_nano lays it out, leaves on `threads` threads
// (run_in_threads); progress counts its leaves. Its size in *size.
struct Progress;
sdft_error stream_into(openvdb::FloatGrid &grid, const char *path, sdft_quant quant, int threads, Progress &progress,
                       const std::function<void *(uint64_t)> &place, uint64_t *size, char *msg, size_t msg_len);

// The caller's progress callback (sdftrace/vdb.h), called about once per
// percent, one call at a time, with a fraction that never decreases; and
// its answer, to stop. step(n) from any thread, once per batch of n units.
struct Progress {
    sdft_progress_fn fn = nullptr;
    void *user = nullptr;
    uint64_t total = 1;
    std::atomic<uint64_t> done{0};
    std::atomic<int> shown{-1};
    std::atomic<bool> stop{false};
    std::mutex call;

    // n more units of work done (one call per batch: threads share the count).
    void step(uint64_t n = 1)
    {
        const uint64_t now = done.fetch_add(n) + n;
        if (!fn || stop)
            return;
        const int pct = int(100 * now / total);
        int old = shown.load();
        if (pct <= old || !shown.compare_exchange_strong(old, pct))
            return;
        std::lock_guard<std::mutex> lock(call);
        if (!stop && shown.load() == pct && fn(user, float(pct) / 100.0f) != 0)
            stop = true; // no call after the one that said stop
    }
};

} // namespace sdft_vdb

#endif
