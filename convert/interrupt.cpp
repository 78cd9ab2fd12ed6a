// mesh2sdf — SIGINT and SIGTERM (see interrupt.h).
#include "interrupt.h"

#include <csignal>
#include <cstring>
#include <signal.h>

namespace mesh2sdf
{

namespace
{

volatile std::sig_atomic_t gSignal = 0;

extern "C" void onInterrupt(int signal) { gSignal = signal; }

} // namespace

void catchInterrupts()
{
    struct sigaction action;
    std::memset(&action, 0, sizeof action);
    action.sa_handler = onInterrupt;
    sigemptyset(&action.sa_mask);
    // Reads and waits go on (the progress reports stop the work), and the
    // handler is reset once it ran: a second Ctrl-C ends a run that does
    // not get to a progress report soon enough.
    action.sa_flags = SA_RESTART | SA_RESETHAND;
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

int interruptSignal() { return gSignal; }

std::string interruptReason() { return gSignal == SIGINT ? "interrupted by SIGINT" : "interrupted by SIGTERM"; }

int interruptStatus() { return 128 + int(gSignal); }

} // namespace mesh2sdf
