// External programs wobble calls (ffmpeg for video, gnuplot for plots): found on PATH and run without a shell, so
// arguments need no quoting.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace wobble {

// The executable file `program` names: itself when it contains a '/', else the first match on PATH; or nothing.
std::optional<std::filesystem::path> findProgram(const std::string& program);

// Runs args[0] (a path) with args and waits for it; ends it (SIGTERM) when wobble is interrupted (interrupt.h). Its
// stdout and stderr go to `log` when given. Returns its exit status (-1 when a signal ended it). Throws
// std::runtime_error naming the program when it cannot be started.
int runProgram(const std::vector<std::string>& args, const std::optional<std::filesystem::path>& log = std::nullopt);

// A program started with a pipe to its standard input, for data made while it runs (video frames). It runs in its
// own process group, so a Ctrl-C on the terminal reaches wobble only, which then ends it (or lets it finish).
struct PipedProgram {
  int pid = -1;
  int input = -1;  // write end of the child's stdin
};
// Throws std::runtime_error naming the program when it cannot be started.
PipedProgram startPiped(const std::vector<std::string>& args);
// Waits for a started program as runProgram does (ending it with SIGTERM if wobble is interrupted); returns its exit
// status, -1 when a signal ended it.
int waitProgram(int pid, const std::string& name);

}  // namespace wobble
