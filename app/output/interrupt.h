// SIGINT and SIGTERM during `wobble run` / `wobble render`: the handler only records the signal; the frame loops
// check interrupted() between frames and stop there, so every file written is complete and run.json still says what
// the folder holds. An external program being waited for (ffmpeg) is ended (external_program.cpp).
#pragma once

namespace wobble {

// Installs the handlers (once; later calls do nothing).
void installInterruptHandlers();
// The signal that arrived (SIGINT or SIGTERM), or 0.
int interruptSignal();
inline bool interrupted() { return interruptSignal() != 0; }

// Exit statuses shared by every command.
// 128 + the signal for a run stopped by SIGINT (Ctrl-C) or SIGTERM, as a shell reports a process killed by it.
enum ExitStatus : int {
  kExitOk = 0,
  kExitError = 1,
  kExitBadInput = 2,
  kExitBlowUp = 3,
  kExitInterrupted = 130,
  kExitTerminated = 143
};

// kExitInterrupted or kExitTerminated when a signal stopped the command (above), else `status`.
int exitStatusAfterSignals(int status);

}  // namespace wobble
