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

// Runs args[0] (a path) with args and waits for it; ends it (SIGTERM) when wobble is interrupted (interrupt.h). Its stdout and stderr go to `log` when given. Returns its exit
// status (-1 when a signal ended it). Throws std::runtime_error naming the program when it cannot be started.
int runProgram(const std::vector<std::string>& args, const std::optional<std::filesystem::path>& log = std::nullopt);

}  // namespace wobble
