// mesh2sdf — progress bar (see progress.h).
#include "progress.h"

#include <cstdio>
#include <unistd.h>

namespace mesh2sdf {

Progress::Progress(bool enabled) : mDraw(enabled && isatty(STDERR_FILENO)) {}

Progress::~Progress() { finish(); }

void Progress::stage(const char* label, int from, int to)
{
    mLabel = label;
    mFrom = from;
    mTo = to;
    report(0);
}

void Progress::start(const char*) {}

bool Progress::wasInterrupted(int percent)
{
    if (percent >= 0)
        report(percent);
    return false;
}

void Progress::report(int percent)
{
    if (!mDraw)
        return;
    if (percent < 0)
        percent = 0;
    if (percent > 100)
        percent = 100;
    const int overall = mFrom + (mTo - mFrom) * percent / 100;
    int shown = mShown.load();
    // Draw each overall percent once, from whichever thread gets there first.
    while (overall > shown) {
        if (mShown.compare_exchange_weak(shown, overall)) {
            constexpr int kWidth = 40;
            char bar[kWidth + 1];
            const int filled = overall * kWidth / 100;
            for (int i = 0; i < kWidth; ++i)
                bar[i] = i < filled ? '#' : '.';
            bar[kWidth] = '\0';
            std::fprintf(stderr, "\r[%s] %3d%% %-24s", bar, overall, mLabel);
            std::fflush(stderr);
            return;
        }
    }
}

void Progress::finish()
{
    if (mDraw && mShown.load() >= 0) {
        std::fprintf(stderr, "\r%*s\r", 80, "");
        std::fflush(stderr);
        mShown = -1;
    }
}

} // namespace mesh2sdf
