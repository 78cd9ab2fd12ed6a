// mesh2sdf — SIGINT and SIGTERM (see interrupt.h).
#include "interrupt.h"

#include <atomic>
#include <csignal>
#include <cstring>
#include <signal.h>

namespace mesh2sdf
{

namespace
{

// Lock-free, so that the handler (on whichever thread the kernel picks) and
// the progress callbacks (on TBB's workers) may both touch it.
std::atomic<int> gSignal{0};
static_assert(std::atomic<int>::is_always_lock_free, "a signal handler needs a lock-free flag");

void handle(int signal, void (*handler)(int))
{
    struct sigaction action;
    std::memset(&action, 0, sizeof action);
    action.sa_handler = handler;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART; // reads and waits go on; the progress reports stop the work
    sigaction(signal, &action, nullptr);
}

// The first signal is kept; both go back to their default action, so that
// a second Ctrl-C (or a SIGTERM after a SIGINT) ends a run that does not
// get to a progress report soon enough. sigaction is async-signal-safe.
extern "C" void onInterrupt(int signal)
{
    int none = 0;
    gSignal.compare_exchange_strong(none, signal);
    handle(SIGINT, SIG_DFL);
    handle(SIGTERM, SIG_DFL);
}

} // namespace

void catchInterrupts()
{
    handle(SIGINT, onInterrupt);
    handle(SIGTERM, onInterrupt);
}

int interruptSignal() { return gSignal.load(); }

std::string interruptReason() { return gSignal == SIGINT ? "interrupted by SIGINT" : "interrupted by SIGTERM"; }

int endInterrupted()
{
    // Dying by the signal, not exiting with a status: a shell loop around
    // mesh2sdf then stops too, and a parent sees the signal.
    const int signal = gSignal.load();
    handle(signal, SIG_DFL);
    std::raise(signal);
    return 128 + signal;
}

} // namespace mesh2sdf
