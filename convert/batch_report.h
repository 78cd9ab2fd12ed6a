// mesh2sdf --batch — the report: one JSON object a line per mesh (its
// status, error, time, voxels and health counts, the files written), kept
// current as meshes finish and always whole: each version is written to a
// temporary file and renamed over the last, so an interrupted batch leaves
// a valid report for its rerun.
#ifndef MESH2SDF_BATCH_REPORT_H
#define MESH2SDF_BATCH_REPORT_H

#include "batch_list.h"
#include "job.h"
#include "text.h"

#include <chrono>
#include <string>
#include <unordered_map>
#include <vector>

namespace mesh2sdf
{

enum class RowStatus { Ok, Failed, Skipped };

/// One mesh's outcome: its report row, and a line for the terminal.
struct BatchRow {
    RowStatus status = RowStatus::Skipped;
    std::string json; // one line, no newline
    std::string text; // "ok MESH: ...", "failed MESH: ...", "skipped MESH: ..."
};

/// The row of a converted or failed mesh; `options`: the hash of its
/// output options (outputOptions in batch.h).
BatchRow jobRow(const BatchEntry &entry, const JobResult &r, const std::string &options);
/// Whether report row `row` says its mesh was converted (status ok) with
/// the output options whose hash is `options`.
bool rowMadeWith(const std::string &row, const std::string &options);
/// The row of a mesh whose outputs were all there already: its row from
/// the earlier report (`earlier`, kept as it was) or, without one, a row
/// with status "skipped".
BatchRow skippedRow(const BatchEntry &entry, const std::vector<std::string> &outputs, const std::string &earlier);

class BatchReport
{
  public:
    /// The report at `path` with one slot per mesh, in LIST's order.
    BatchReport(std::string path, size_t slots);

    /// Reads the rows an earlier run left at the path, if any; fails with
    /// one line only when the file is there and cannot be read.
    bool loadEarlier(std::string &error);
    /// The earlier run's row for the mesh LIST writes as `line`, or "".
    std::string earlier(const std::string &line) const;

    /// Fills a slot.
    void set(size_t slot, const std::string &json);
    /// Writes the filled slots, in order, if `now`, or if a slot changed and
    /// a second has passed since the last write (rewriting a long report after every small
    /// mesh would cost more than the meshes).
    bool write(bool now, std::string &error);

    const std::string &path() const { return mPath; }

  private:
    std::string mPath;
    std::vector<std::string> mRows;
    std::unordered_map<std::string, std::string> mEarlier; // by the escaped "mesh"
    std::chrono::steady_clock::time_point mWritten;
    bool mDirty = false;
};

} // namespace mesh2sdf

#endif
