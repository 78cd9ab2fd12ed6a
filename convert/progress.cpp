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

bool Progress::wasInterrupted(int percent)
{
    if (percent >= 0)
        report(percent);
    return false;
}

void Progress::report(int percent)
{
    percent = percent < 0 ? 0 : percent > 100 ? 100 : percent;
    progress_bar_show(&mBar, mLabel, mFrom + (mTo - mFrom) * percent / 100);
}

void Progress::finish() { progress_bar_clear(&mBar); }

} // namespace mesh2sdf
