// Ctrl-C during a run: the first SIGINT or SIGTERM asks the run to stop at the next substep, keeping
// the frames completed before it (a resumable partial output); a second one ends the process at once.
#pragma once

namespace romp::run {

// The exit status of a command stopped this way (README "Exit codes"): 128 + SIGINT, as a shell reports it.
inline constexpr int kExitInterrupted = 130;

// Installs the handlers (idempotent).
void install_interrupt_handler();
bool interrupt_requested();

}  // namespace romp::run
