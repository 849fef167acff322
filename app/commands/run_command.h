// `wobble run`: load a scene, simulate it, write the OBJ sequence of every body and OUT/run.json.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include "app/commands/run_scene.h"
#include "app/study/error_estimate.h"
#include "sim/simulation.h"

namespace wobble {

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

// Throws InputError for bad input before anything is written, and when another run holds OUT. Clears an earlier
// run's files from OUT first. A blow-up, an energy gain (Simulation::energyGain) or an interrupt stops the run at
// once: the frames written so far stay, and the report (and run.json) says so.
RunReport runScene(const RunOptions& options);

}  // namespace wobble
