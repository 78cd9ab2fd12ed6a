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
// Here the child reads the file the way the caller
// is about to (the same delayed loading, every leaf's values decompressed
// once) under a time limit and an address-space limit; only when it
// finishes does the caller read the file itself. A crash, a signal, an
// allocation past the limit or a loop past the time limit kills the child
// alone, and the caller reports the file as corrupt.
//
// COST. One more read of the chosen grid, serial, in a process that keeps
// one lower node's leaves (at most 128^3 values) at a time; the file's
// pages are in the page cache for the caller's read. The child uses no
// thread pool: TBB's and OpenMP's workers do not survive fork(), so
// nothing there may wait on them.
//
// LIMITS (src/common/isolated_read.h): 10 s plus 1 s per 8 MiB of file;
// 256 MiB plus 64 bytes per byte of file (a leaf's 2 KiB of values come
// with at least its 64-byte value mask in the file).
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "isolated_read.h"
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
                         size_t msg_len)
{
    openvdb::initialize(); // once, here, rather than in every child
    Job job{path, out_size, &read};
    char *answer = nullptr, why[128];
    size_t size = 0;
    if (isolated_read(path, run_read, &job, &answer, &size, why, sizeof why) != 0)
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

} // namespace sdft_vdb
