// mesh2sdf --batch LIST --out-dir DIR: every mesh of LIST (or of its shard,
// --shard K/N) converted into DIR by one process, or by every rank of an
// mpirun (mpi_batch.h). A mesh that fails is a row of the report, never the
// end of the batch; a mesh whose outputs are all in DIR is skipped, so a
// rerun resumes an interrupted batch (outputs are renamed into place whole,
// so one that is there is complete).
#ifndef MESH2SDF_BATCH_H
#define MESH2SDF_BATCH_H

#include "batch_list.h"
#include "batch_report.h"
#include "options.h"
#include "progress_view.h"

#include <chrono>
#include <memory>
#include <string>
#include <vector>

namespace mesh2sdf
{

/// Exit status of a batch in which some mesh failed (1 is bad usage, or a
/// batch that could not run at all).
constexpr int kBatchSomeFailed = 2;

/// Runs the batch `opt` describes; returns the exit status: 0 when every
/// mesh was converted or skipped, kBatchSomeFailed, or 1 with one line on
/// stderr when it could not run.
int runBatch(const Options &opt);

/// What a batch is to do: this shard's meshes in LIST's order, which of
/// them to convert, and the report (with the earlier run's rows).
struct BatchPlan {
    std::vector<BatchEntry> entries;
    std::vector<size_t> pending; // indices into entries, in LIST's order
    std::unique_ptr<BatchReport> report;
    std::string options; // the hash of the output options (outputOptions), as the rows record it
};

/// Reads LIST, takes the shard, creates DIR, removes what killed runs left
/// there and reads the earlier report; a mesh is pending unless all its
/// outputs are there and its earlier row records the same output options.
/// `withReport` false (an MPI rank other than 0) leaves DIR and the report
/// alone, and plans nothing pending (rank 0 hands out the work).
bool planBatch(const Options &opt, bool withReport, BatchPlan &plan, std::string &error);

/// The end of a batch SIGINT or SIGTERM stopped (interrupt.h): its line on
/// stderr, and the exit status.
int batchInterrupted();

/// One mesh of the batch converted into DIR (quietly) and its row.
BatchRow convertEntry(const Options &opt, const BatchEntry &entry);

/// The hash of the settings that change what a mesh's outputs hold (16 hex
/// digits), which each row records.
std::string outputOptions(const Options &opt);

/// Where the rows of a batch go as they come in, on the one process that
/// reports: the report (kept current), a line each on stdout (the row
/// itself with --json; none with --quiet), failures on stderr, and a
/// progress line on stderr counting meshes with the time left, estimated
/// from the bytes of mesh still to convert.
class BatchSink
{
  public:
    BatchSink(const Options &opt, BatchPlan &plan);
    /// The rows of the meshes that are not pending; writes the report.
    bool start(std::string &error);
    /// The row of entries[index]; rewrites the report now and then.
    bool add(size_t index, const BatchRow &row, std::string &error);
    /// Writes the report a last time and the summary; the exit status.
    int finish();

  private:
    void show(const BatchRow &row);
    void showProgress();

    const Options &mOpt;
    BatchPlan &mPlan;
    ProgressView mProgress;
    std::string mLabel;
    std::chrono::steady_clock::time_point mStart;
    size_t mConverted = 0, mFailed = 0, mSkipped = 0, mDone = 0;
    uint64_t mBytesDone = 0, mBytesTotal = 0;
};

} // namespace mesh2sdf

#endif
