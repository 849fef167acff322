// Each subcommand of the wobble program registers itself on the CLI11 app from its own file; main() only lists them.
// A command's callback returns the process exit status through the shared int.
#pragma once
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "app/output/interrupt.h"  // ExitStatus

namespace wobble {

void addRunCommand(CLI::App& app, int& status);
void addRenderCommand(CLI::App& app, int& status);  // render_cli.cpp
void addDiffCommand(CLI::App& app, int& status);    // diff_cli.cpp: sets status to idiff's exit code
// The command line with `wobble diff`'s idiff options in idiff's one-dash spelling (-fail 0.02) turned into the
// two-dash one CLI11 reads (--fail 0.02); other commands' unchanged. args[0] is the program.
std::vector<std::string> idiffSpelling(std::vector<std::string> args);
void addBlendCommand(CLI::App& app, int& status);    // blend_cli.cpp
void addCompareCommand(CLI::App& app, int& status);  // compare_cli.cpp
void addVideoCommand(CLI::App& app, int& status);    // video_cli.cpp
void addFramesCommand(CLI::App& app, int& status);   // frames_cli.cpp
// `study accuracy` and `study stability` (app/study_cli.cpp).
void addStudyCommand(CLI::App& app, int& status);

}  // namespace wobble
