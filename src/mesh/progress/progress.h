// sdftrace — a long call's progress, told to the caller's callbacks
// (sdftrace/mesh.h: sdft_progress_fn, sdft_mesh_stage_fn) and to OpenVDB through
// its interrupter interface. The work runs in stages; each stage maps its
// own 0..100 % onto a slice of the call's whole. Draws nothing: the
// programs draw what they are told.
#ifndef SDFT_MESH_PROGRESS_PROGRESS_H
#define SDFT_MESH_PROGRESS_PROGRESS_H

#include <openvdb/util/NullInterrupter.h>

#include <atomic>
#include <exception>
#include <mutex>

#include "sdftrace/mesh.h"

namespace meshsdf
{

/// Thrown by Progress::report when the listener asked to stop.
struct Cancelled : std::exception {
    const char *what() const noexcept override { return "canceled"; }
};

class Progress final : public openvdb::util::NullInterrupter
{
  public:
    /// Tells `listener(user, done)` the whole call's progress, done in
    /// [0, 1] rising, one call at a time; when it returns non-zero, report
    /// throws Cancelled (out of TBB's loops to the caller) and
    /// wasInterrupted answers true. Tells `stages(user, label)` (when not
    /// NULL) each stage's label as it begins.
    Progress(sdft_progress_fn listener, sdft_mesh_stage_fn stages, void *user)
        : mListener(listener), mStages(stages), mUser(user)
    {
    }
    bool cancelled() const { return mCancelled; }

    /// Begins a stage that covers [from, to] percent of the whole run;
    /// `label` is a string literal.
    void stage(const char *label, int from, int to);
    /// Reports `percent` of the current stage. Safe from any thread.
    void report(int percent);
    /// Reports the whole call done, with no stage of its own.
    void done()
    {
        mFrom = 100;
        mTo = 100;
        report(0);
    }

    // openvdb::util::NullInterrupter
    void start(const char *name = nullptr) override;
    void end() override {}
    bool wasInterrupted(int percent = -1) override;

  private:
    std::atomic<int> mFrom{0}, mTo{100};
    sdft_progress_fn mListener;
    sdft_mesh_stage_fn mStages;
    void *mUser;
    std::mutex mListenerLock;
    int mHeard = -1; // the most the listener was told, percent (under the lock)
    std::atomic<bool> mCancelled{false};
};

} // namespace meshsdf

#endif
