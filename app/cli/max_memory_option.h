// --max-memory SIZE on the commands that load scenes: the memory budget a scene's estimate must keep
// (scene_limits.h), e.g. 8GB or 512MB; the default is half of physical memory.
#pragma once
#include <CLI/CLI.hpp>

namespace wobble {

void addMaxMemoryOption(CLI::App& cmd);

}  // namespace wobble
