// sdftrace — a long call's progress (see progress.h).
#include "progress/progress.h"

namespace meshsdf
{

void Progress::stage(const char *label, int from, int to)
{
    if (mStages) {
        std::lock_guard<std::mutex> lock(mListenerLock);
        mStages(mUser, label);
    }
    mFrom = from;
    mTo = to;
    report(0);
}

void Progress::start(const char *) {}

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
    if (!mListener)
        return;
    percent = percent < 0 ? 0 : percent > 100 ? 100 : percent;
    const int from = mFrom, to = mTo;
    const int whole = from + (to - from) * percent / 100;
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

} // namespace meshsdf
