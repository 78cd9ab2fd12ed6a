// sdftrace — reading an untrusted `.vdb` file through OpenVDB in a child
// process, so that OpenVDB's reader failing on it becomes an error code and
// one line, never a crash or a hang of the caller.
//
// WHY. OpenVDB's reader trusts the file. Byte-mutated files crash it (and
// vdb_print) with segfaults and glibc heap corruption, fail its
// assertions (DelayedLoadMetadata::getMask: index < mMask.size()),
// allocate gigabytes for a metadata string whose length is corrupt, or
// make it loop for minutes on counts read past the end of the stream (the
// inputs are in tests/fuzz/regressions/vdb). A validator of the whole
// format (header, metadata, descriptors, the three node levels' masks and
// compressed values, blosc's internal offsets) would be a second reader
// to keep in step with OpenVDB's, and still not prove that blosc holds.
// A truncated file is caught before any of that, by a walk of the
// header and the grids' offsets (vdb_extent.c): past the end of the file
// OpenVDB reads uninitialized lengths, and would fail differently from
// one run to the next. Here a child reads the file with OpenVDB under a time limit and an
// address-space limit, and the caller uses OpenVDB on the file only once
// the child has finished; a crash, a signal, an allocation past the limit
// or a loop past the time limit kills the child alone, and the caller
// reports the file as corrupt. What the child reads is the caller's
// business (vdb_load.cpp): loaded whole, the child's read is the only one,
// its result a NanoVDB grid in memory the caller maps; else every leaf is
// decompressed once before the caller reads the file itself.
//
// THREADS. No thread pool survives fork() (TBB's and OpenMP's workers
// stay behind, and waiting on them hangs), so the child runs its parallel
// work on threads of its own (run_in_threads), each allowed thread_bytes
// more address space (a stack, a malloc arena).
//
// LIMITS (src/common/isolated_read.h): 10 s plus 1 s per 8 MiB of file;
// 256 MiB plus 64 bytes per byte of file (a leaf's 2 KiB of values come
// with at least its 64-byte value mask in the file), plus the threads'.
#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "isolated_read.h"
#include "vdb_extent.h"
#include "vdb_internal.h"

namespace sdft_vdb
{

namespace
{

struct Job {
    const char *path;
    size_t out_size;
    const IsolatedRead *read;
};

// The child's side: the read, and its answer on fd: the code, out_size
// bytes of result, the message.
int run_read(void *ctx, int fd)
{
    const Job &job = *static_cast<Job *>(ctx);
    std::vector<char> answer(sizeof(int32_t) + job.out_size + 1024, '\0');
    char *result = answer.data() + sizeof(int32_t), *msg = result + job.out_size;
    int32_t rc = guarded(job.path, msg, 1024, [&] { return (*job.read)(result, msg, 1024); });
    if (rc == SDFT_ENOMEM) // past the child's limit, which follows the file's size
        rc = fail_with(msg, 1024, SDFT_EFORMAT,
                       "%s: reading it takes more memory than a file of its size can hold: a corrupt .vdb file?",
                       job.path);
    std::memcpy(answer.data(), &rc, sizeof rc);
    return isolated_write_all(fd, answer.data(), sizeof rc + job.out_size + std::strlen(msg) + 1);
}

} // namespace

sdft_error read_isolated(const char *path, void *out, size_t out_size, const IsolatedRead &read, char *msg,
                         size_t msg_len, const isolated_extra *extra)
{
    char why[160];
    if (vdb_check_extent(path, why, sizeof why) != 0)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "cannot read %s: %s", path, why);
    openvdb::initialize(); // once, here, rather than in every child
    Job job{path, out_size, &read};
    char *answer = nullptr;
    size_t size = 0;
    const int ran = isolated_read_with(path, run_read, &job, extra, &answer, &size, why, sizeof why);
    if (ran == -2)
        return fail_with(msg, msg_len, SDFT_ECANCELED, "loading %s stopped by its progress callback", path);
    if (ran != 0)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "%s: OpenVDB's reader failed on it (%s): a corrupt .vdb file?",
                         path, why);
    std::unique_ptr<char, decltype(&std::free)> owned(answer, &std::free);
    int32_t rc;
    if (size <= sizeof rc + out_size || answer[size - 1] != '\0')
        return fail_with(msg, msg_len, SDFT_EINTERNAL, "%s: the reader process gave no answer", path);
    std::memcpy(&rc, answer, sizeof rc);
    if (rc != SDFT_OK)
        return fail_with(msg, msg_len, sdft_error(rc), "%s", answer + sizeof rc + out_size);
    if (out)
        std::memcpy(out, answer + sizeof rc, out_size);
    return SDFT_OK;
}

void run_in_threads(int threads, uint64_t n, const std::function<void(uint64_t)> &body)
{
    std::atomic<uint64_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr first;
    std::mutex first_lock;
    auto work = [&] {
        try {
            for (uint64_t i; !failed && (i = next.fetch_add(1)) < n;)
                body(i);
        } catch (...) {
            std::lock_guard<std::mutex> lock(first_lock);
            if (!first)
                first = std::current_exception();
            failed = true;
        }
    };
    std::vector<std::thread> pool;
    const uint64_t helpers = std::min<uint64_t>(threads > 1 ? uint64_t(threads) - 1 : 0, n > 1 ? n - 1 : 0);
    for (uint64_t t = 0; t < helpers; t++) {
        try {
            pool.emplace_back(work);
        } catch (const std::system_error &) { // no room for another thread: fewer do the work
            break;
        }
    }
    work();
    for (std::thread &t : pool)
        t.join();
    if (first)
        std::rethrow_exception(first);
}

} // namespace sdft_vdb
