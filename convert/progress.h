// mesh2sdf — progress on stderr through OpenVDB's interrupter interface.
// The conversion runs in stages; each stage maps its own 0..100 % onto a
// slice of the overall bar. Drawn by sdftrace's one progress bar
// (src/common/progress_bar.h), only when stderr is a terminal.
#ifndef MESH2SDF_PROGRESS_H
#define MESH2SDF_PROGRESS_H

#include <openvdb/util/NullInterrupter.h>

#include <atomic>
#include <exception>
#include <mutex>

#include "progress_bar.h"

namespace mesh2sdf
{

/// Thrown by Progress::report when the listener asked to stop.
struct Cancelled : std::exception {
    const char *what() const noexcept override { return "canceled"; }
};

class Progress final : public openvdb::util::NullInterrupter
{
  public:
    /// enabled: draw at all (false for --quiet); the bar is also off when
    /// stderr is not a terminal.
    explicit Progress(bool enabled);
    ~Progress() override;

    /// Also tells `listener(user, done)` the whole run's progress, done in
    /// [0, 1] rising, one call at a time; when it returns non-zero, report
    /// throws Cancelled (out of TBB's loops to the caller) and
    /// wasInterrupted answers true. For the library (sdftrace/mesh.h).
    void listen(int (*listener)(void *, float), void *user);
    bool cancelled() const { return mCancelled; }

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
    int (*mListener)(void *, float) = nullptr;
    void *mUser = nullptr;
    std::mutex mListenerLock;
    int mHeard = -1; // the most the listener was told, percent (under the lock)
    std::atomic<bool> mCancelled{false};
};

} // namespace mesh2sdf

#endif
