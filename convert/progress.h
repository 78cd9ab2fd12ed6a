// mesh2sdf — progress on stderr through OpenVDB's interrupter interface.
// The conversion runs in stages; each stage maps its own 0..100 % onto a
// slice of the overall bar. Drawn by sdftrace's one progress bar
// (src/common/progress_bar.h), only when stderr is a terminal.
#ifndef MESH2SDF_PROGRESS_H
#define MESH2SDF_PROGRESS_H

#include <openvdb/util/NullInterrupter.h>

#include "progress_bar.h"

namespace mesh2sdf
{

class Progress final : public openvdb::util::NullInterrupter
{
  public:
    /// enabled: draw at all (false for --quiet); the bar is also off when
    /// stderr is not a terminal.
    explicit Progress(bool enabled);
    ~Progress() override;

    /// Begins a stage that covers [from, to] percent of the whole run.
    void stage(const char *label, int from, int to);
    /// Reports `percent` of the current stage. Safe from any thread.
    void report(int percent);
    /// Clears the bar's line.
    void finish();

    // openvdb::util::NullInterrupter
    void start(const char *name = nullptr) override;
    void end() override {}
    bool wasInterrupted(int percent = -1) override;

  private:
    progress_bar mBar;
    const char *mLabel = "";
    int mFrom = 0, mTo = 100;
};

} // namespace mesh2sdf

#endif
