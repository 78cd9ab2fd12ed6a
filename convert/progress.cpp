// mesh2sdf — progress bar (see progress.h).
#include "progress.h"

namespace mesh2sdf
{

Progress::Progress(bool enabled) { progress_bar_init(&mBar, enabled); }

Progress::~Progress() { finish(); }

void Progress::stage(const char *label, int from, int to)
{
    mLabel = label;
    mFrom = from;
    mTo = to;
    report(0);
}

void Progress::start(const char *) {}

void Progress::listen(int (*listener)(void *, float), void *user)
{
    mListener = listener;
    mUser = user;
}

bool Progress::wasInterrupted(int percent)
{
    if (percent >= 0 && !mCancelled) {
        try {
            report(percent);
        } catch (const Cancelled &) {
        }
    }
    return mCancelled;
}

void Progress::report(int percent)
{
    percent = percent < 0 ? 0 : percent > 100 ? 100 : percent;
    const int whole = mFrom + (mTo - mFrom) * percent / 100;
    progress_bar_show(&mBar, mLabel, whole);
    if (!mListener)
        return;
    if (!mCancelled) {
        std::lock_guard<std::mutex> lock(mListenerLock);
        if (whole > mHeard && !mCancelled) {
            mHeard = whole;
            if (mListener(mUser, float(whole) / 100.0f) != 0)
                mCancelled = true;
        }
    }
    if (mCancelled)
        throw Cancelled();
}

void Progress::finish() { progress_bar_clear(&mBar); }

} // namespace mesh2sdf
