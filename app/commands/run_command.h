// `wobble run`: load a scene, simulate it, write the OBJ sequence of every body and OUT/run.json.
#pragma once
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/scene/render_overrides.h"
#include "app/scene/scene_file.h"
#include "app/study/error_estimate.h"
#include "sim/simulation.h"

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

struct RunReport {
  std::filesystem::path out;
  int first_frame = 0, last_frame = 0, frames_written = 0;
  long steps = 0;
  double simulated_time = 0, energy_start = 0, energy_end = 0, max_speed = 0;
  double seconds_simulate = 0, seconds_export = 0, seconds_render = 0;
  int frames_rendered = 0;
  int frames_skipped = 0;                      // --skip-existing: already there with the same picture key
  std::optional<std::filesystem::path> video;  // OUT/<scene>.mp4 when encoded
  std::optional<BlowUp> blow_up;
  std::string blow_up_message;
  double collider_work = 0;               // J, work done on the bodies by moving colliders (Simulation::colliderWork)
  std::optional<EnergyGain> energy_gain;  // the run's energy check failed: it stopped there (docs/energy.md)
  std::string energy_gain_message;
  std::optional<ErrorEstimate> error_estimate;  // with RunOptions::estimate_error
  bool interrupted = false;  // SIGINT/SIGTERM: stopped after the last complete frame, no video (interrupt.h)
  int files_cleared = 0;     // of an earlier run in the folder (output_folder.h)
};

// The scene a run of `options` simulates: the file with --set, then the keys the flags set (--integrator, --dt,
// --pc2, the render flags), in that order; `overrides` (when given) receives that list, as run.json records it.
// Throws InputError.
SceneFile loadRunScene(const RunOptions& options, std::vector<std::string>* overrides = nullptr);

// Throws InputError for bad input before anything is written, and when another run holds OUT. Clears an earlier
// run's files from OUT first. A blow-up, an energy gain (Simulation::energyGain) or an interrupt stops the run at
// once: the frames written so far stay, and the report (and run.json) says so.
RunReport runScene(const RunOptions& options);

// The 1-based inclusive frame range of "A:B" or "A" within [1, count]; throws InputError naming what is allowed.
std::pair<int, int> parseFrameRange(const std::string& text, int count);
// The same within [first, last], which `why` explains in the message ("the run wrote frames 5:40").
std::pair<int, int> parseFrameRange(const std::string& text, int first, int last, const std::string& why);

}  // namespace wobble
