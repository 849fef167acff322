// The rendering flags on a command line (CLI11): --render, --quality, --spp, --denoise, --resolution, --video, read
// into RenderFlags, whose typed settings loadScene lays over the scene (app/scene/scene_flags.h); and --skip-existing.
#pragma once
#include <CLI/CLI.hpp>

#include "app/scene/scene_flags.h"

namespace wobble {

void addRenderFlags(CLI::App& cmd, RenderFlags& flags);
// --skip-existing, for the commands that write frames (`run`, `render`).
void addSkipExistingFlag(CLI::App& cmd, bool& skip);

}  // namespace wobble
