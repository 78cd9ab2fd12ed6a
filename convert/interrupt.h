// mesh2sdf — Ctrl-C and kill: SIGINT and SIGTERM ask the run to stop. The
// library's next progress report is refused (ProgressView), so the call
// in progress unwinds and removes its temporary files; the program then
// says so in one line and exits with 128 + the signal's number, leaving
// no file half-written and none of its temporary files behind. A second
// signal ends the process at once, as if there were no handler.
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

/// The exit status of an interrupted run: 128 + the signal's number.
int interruptStatus();

} // namespace mesh2sdf

#endif
