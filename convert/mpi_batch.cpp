// mesh2sdf --batch under mpirun (see mpi_batch.h).
//
// How work is handed out: each rank other than 0 sends rank 0 the row of
// the mesh it just converted (nothing, the first time), which doubles as
// its request for the next; rank 0 answers with the index of the next mesh
// in largest-first order, or -1 when none is left. Rank 0 converts too, on
// a thread of its own, so that its main thread, the only one to call MPI
// (MPI_THREAD_FUNNELED), answers a request within a millisecond instead of
// after its own mesh; a one-sided MPI_Fetch_and_op counter would save that
// thread, but Open MPI moves a passive-target operation over TCP only when
// the target calls into MPI, so a rank would then wait for rank 0's mesh
// anyway, and the rows would still need rank 0 to receive them. One short
// message each way per mesh, against seconds of conversion.
#include "mpi_batch.h"

#include "batch.h"
#include "interrupt.h"

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

namespace mesh2sdf
{

namespace
{

constexpr int kTagRow = 1;  // rank > 0 to 0: a row (or nothing), and a request for work
constexpr int kTagWork = 2; // rank 0 to the asker: an index into the plan's entries, or -1

// A row on the wire: its index, status, JSON and text, one a line (the
// JSON has no newline; the text is the rest).
std::string packRow(long index, const BatchRow &row)
{
    return std::to_string(index) + "\n" + std::to_string(int(row.status)) + "\n" + row.json + "\n" + row.text;
}

bool unpackRow(const std::string &msg, long &index, BatchRow &row)
{
    const size_t a = msg.find('\n'), b = msg.find('\n', a + 1), c = msg.find('\n', b + 1);
    if (c == std::string::npos)
        return false;
    index = std::atol(msg.c_str());
    row.status = RowStatus(std::atoi(msg.c_str() + a + 1));
    row.json = msg.substr(b + 1, c - b - 1);
    row.text = msg.substr(c + 1);
    return true;
}

// Rank 0's own conversion, one mesh at a time, on its own thread.
class OwnJob
{
  public:
    ~OwnJob()
    {
        if (mThread.joinable())
            mThread.join();
    }
    bool busy() const { return mIndex >= 0; }
    bool finished() const { return mDone.load(std::memory_order_acquire); }
    void start(const Options &opt, const BatchEntry &entry, long index)
    {
        mIndex = index;
        mDone = false;
        mThread = std::thread([this, &opt, &entry] {
            mRow = convertEntry(opt, entry);
            mDone.store(true, std::memory_order_release);
        });
    }
    long collect(BatchRow &row)
    {
        mThread.join();
        row = mRow;
        const long index = mIndex;
        mIndex = -1;
        return index;
    }

  private:
    std::thread mThread;
    std::atomic<bool> mDone{false};
    BatchRow mRow;
    long mIndex = -1;
};

// The pending meshes, largest file first (ties in LIST's order): the long
// ones start early instead of keeping one rank busy at the end.
std::vector<size_t> largestFirst(const BatchPlan &plan)
{
    std::vector<size_t> order = plan.pending;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return plan.entries[a].bytes > plan.entries[b].bytes; });
    return order;
}

// Rank 0: hands out the meshes, converts its share, writes the report.
int serve(const Options &opt, BatchPlan &plan, int ranks)
{
    BatchSink sink(opt, plan);
    std::string error;
    std::vector<size_t> order = largestFirst(plan);
    if (!sink.start(error))
        order.clear(); // only stop the others
    size_t next = 0;
    int working = ranks - 1;
    OwnJob own;
    while (working > 0 || own.busy() || next < order.size()) {
        bool idle = true;
        if (interruptSignal()) // mpirun passes SIGINT and SIGTERM on (and SIGKILL soon after): no new work
            next = order.size();
        if (!own.busy() && next < order.size()) {
            own.start(opt, plan.entries[order[next]], long(order[next]));
            ++next;
        }
        BatchRow row;
        if (own.busy() && own.finished()) {
            const long index = own.collect(row);
            if (error.empty() && !sink.add(size_t(index), row, error))
                next = order.size();
            idle = false;
        }
        int asked = 0;
        MPI_Status status;
        MPI_Iprobe(MPI_ANY_SOURCE, kTagRow, MPI_COMM_WORLD, &asked, &status);
        if (asked) {
            int size = 0;
            MPI_Get_count(&status, MPI_CHAR, &size);
            std::string msg(size_t(size), '\0');
            MPI_Recv(&msg[0], size, MPI_CHAR, status.MPI_SOURCE, kTagRow, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            long index = -1;
            if (size > 0 && unpackRow(msg, index, row) && index >= 0 && size_t(index) < plan.entries.size() &&
                error.empty() && !sink.add(size_t(index), row, error))
                next = order.size();
            long work = next < order.size() ? long(order[next++]) : -1;
            working -= work < 0;
            MPI_Send(&work, 1, MPI_LONG, status.MPI_SOURCE, kTagWork, MPI_COMM_WORLD);
            idle = false;
        }
        if (idle)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (!error.empty()) {
        std::fprintf(stderr, "mesh2sdf: %s\n", error.c_str());
        return 1;
    }
    const int status = sink.finish();
    return interruptSignal() ? batchInterrupted() : status;
}

// A rank other than 0: converts what rank 0 hands it until told to stop.
int work(const Options &opt, const BatchPlan &plan)
{
    std::string msg; // the last row, empty at first
    for (;;) {
        MPI_Send(msg.data(), int(msg.size()), MPI_CHAR, 0, kTagRow, MPI_COMM_WORLD);
        long index = -1;
        MPI_Recv(&index, 1, MPI_LONG, 0, kTagWork, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (index < 0 || size_t(index) >= plan.entries.size())
            return 0;
        msg = packRow(index, convertEntry(opt, plan.entries[size_t(index)]));
    }
}

struct MpiSession {
    MpiSession()
    {
        int provided = 0;
        MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        MPI_Comm_size(MPI_COMM_WORLD, &size);
    }
    ~MpiSession() { MPI_Finalize(); }
    int rank = 0, size = 1;
};

} // namespace

bool mpiLaunched() { return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr; }

int runMpiBatch(const Options &opt)
{
    MpiSession mpi;
    BatchPlan plan;
    std::string error;
    // Every rank reads LIST alike; all go on only if all could (no rank
    // left waiting for one that gave up), and the error is said once.
    int ok = planBatch(opt, mpi.rank == 0, plan, error) ? 1 : 0, allOk = 0, rootOk = ok;
    MPI_Allreduce(&ok, &allOk, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    MPI_Bcast(&rootOk, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!allOk) {
        if (!ok && (mpi.rank == 0 || rootOk))
            std::fprintf(stderr, "mesh2sdf: rank %d: %s\n", mpi.rank, error.c_str());
        return 1;
    }
    return mpi.rank == 0 ? serve(opt, plan, mpi.size) : work(opt, plan);
}

} // namespace mesh2sdf
