// Each subcommand of the wobble program registers itself on the CLI11 app from its own file; main() only lists them.
// A command's callback returns the process exit status through the shared int.
#pragma once
#include <CLI/CLI.hpp>

namespace wobble {

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

// kExitInterrupted or kExitTerminated when a signal stopped the command (interrupt.h), else `status`.
int exitStatusAfterSignals(int status);

void addRunCommand(CLI::App& app, int& status);
void addRenderCommand(CLI::App& app, int& status);  // render_cli.cpp
void addDiffCommand(CLI::App& app, int& status);    // diff_cli.cpp: sets status to idiff's exit code
void addBlendCommand(CLI::App& app, int& status);   // blend_cli.cpp
// `study accuracy` and `study stability` (app/study_cli.cpp).
void addStudyCommand(CLI::App& app, int& status);

}  // namespace wobble
