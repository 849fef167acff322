// The options of a run (`wobble run`, and each variant of `wobble compare`) and the scene they make of the file.
#pragma once
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/scene/scene_file.h"
#include "app/scene/scene_flags.h"

namespace wobble {

struct RunOptions {
  std::filesystem::path scene = "scenes/jelly_slope.toml";
  std::optional<std::string> integrator;
  std::optional<double> dt;
  std::optional<std::string> frames;         // "A:B", 1-based and inclusive, or "A"
  std::optional<std::filesystem::path> out;  // default out/<scene name>
  std::vector<std::string> sets;             // KEY=VALUE overrides
  RenderFlags render;                        // --render, --spp, --resolution, --video (applied after --set)
  bool estimate_error = false;               // rerun at dt/2 in lock step and report the error (error_estimate.h)
  bool pc2 = false;                          // write the PC2 point cache (overrides output.pc2)
  bool progress = true;                      // the progress line on a terminal (`wobble compare` shows its own)
  // Called after the simulation reaches each frame's time, from frame 1 (also before the --frames range), with every
  // particle's position; not for the frame a blow-up stopped. `wobble compare` follows strain and camera with it.
  std::function<void(int frame, const VecX& x)> on_frame;
  bool skip_existing = false;  // keep frames already rendered with the same settings (frame_output.h)
  // Stop at the first frame whose energy check fails (docs/energy.md), as for a blow-up; false: record it and run on.
  bool stop_on_energy_gain = true;
};

// The scene a run of `options` simulates: the file with --set, then the settings of the flags that set keys
// (--integrator, --dt, --pc2, the rendering flags, in that order); `overrides` (when given) receives both as
// KEY=VALUE, as run.json records them. Throws InputError.
SceneFile loadRunScene(const RunOptions& options, std::vector<std::string>* overrides = nullptr);

}  // namespace wobble
