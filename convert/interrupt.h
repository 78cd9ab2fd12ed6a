// mesh2sdf — Ctrl-C and kill: SIGINT and SIGTERM ask the run to stop. The
// library's next progress report is refused (ProgressView), so the call
// in progress unwinds and removes its temporary files; the program then
// says so in one line and ends by the same signal (a shell sees 128 + its
// number), leaving no file half-written and none of its temporary files
// behind. A second signal ends the process at once, as if there were no
// handler. What has no progress reports (reading and orienting up to
// their end, writing) runs to its end first; --check-sign writes nothing
// and keeps the default actions.
#ifndef MESH2SDF_INTERRUPT_H
#define MESH2SDF_INTERRUPT_H

#include <string>

namespace mesh2sdf
{

/// Installs the handlers (once, at the start of main).
void catchInterrupts();

/// The signal that asked to stop, or 0. Safe from any thread.
int interruptSignal();

/// "interrupted by SIGTERM": for the one line the program then prints.
std::string interruptReason();

/// Ends an interrupted run by its signal (after its line was printed);
/// returns 128 + the signal's number should the signal not end it.
int endInterrupted();

} // namespace mesh2sdf

#endif
