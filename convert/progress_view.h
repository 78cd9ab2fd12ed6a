// mesh2sdf — its progress bar (src/common/progress_bar.h) fed by the
// library's progress callbacks: each call into the library is a stage,
// mapped onto its own slice of one bar. The same callbacks stop the
// library's work when the run is interrupted.
#ifndef MESH2SDF_PROGRESS_VIEW_H
#define MESH2SDF_PROGRESS_VIEW_H

#include <atomic>

#include "interrupt.h"
#include "progress_bar.h"

namespace mesh2sdf
{

class ProgressView
{
  public:
    /// Draws when `enabled` (not --quiet, not --json) and stderr is a terminal.
    explicit ProgressView(bool enabled) { progress_bar_init(&mBar, enabled ? 1 : 0); }
    ~ProgressView() { finish(); }
    ProgressView(const ProgressView &) = delete;
    ProgressView &operator=(const ProgressView &) = delete;

    /// The next call's reports cover [from, to] percent, labelled `label`
    /// until the library names its stages. Draws nothing yet.
    void stage(const char *label, int from, int to) { mLabel = label, mFrom = from, mTo = to; }
    /// Shows `done` (0..1) of the current stage: for the program's own stages.
    void show(float done) { report(this, done); }
    /// An sdft_progress_fn for the library: `user` is the ProgressView.
    /// Asks the library to stop once SIGINT or SIGTERM came (interrupt.h).
    static int report(void *user, float done)
    {
        ProgressView &v = *static_cast<ProgressView *>(user);
        progress_bar_show(&v.mBar, v.mLabel.load(), v.mFrom + int(float(v.mTo - v.mFrom) * done));
        return interruptSignal() != 0;
    }
    /// An sdft_mesh_stage_fn for the library: the label of what follows.
    static void named(void *user, const char *stage) { static_cast<ProgressView *>(user)->mLabel = stage; }
    /// Clears the bar's line.
    void finish() { progress_bar_clear(&mBar); }

  private:
    progress_bar mBar;
    std::atomic<const char *> mLabel{""};
    std::atomic<int> mFrom{0}, mTo{100};
};

} // namespace mesh2sdf

#endif
