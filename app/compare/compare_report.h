// OUT/compare.md of `wobble compare`: what a report needs beside the video. A table with a row per variant
// (integrator, dt, steps, simulated time, the outcome in the stability study's words: stable, lost-shape, blew-up
// and when, the largest spring strain, the `--estimate-error` figure when asked, and the run times side by side:
// simulation time, its cost per step against the cheapest, wall time), the video's layout, and each variant as the
// plain `wobble run` that gives its folder.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace wobble {

struct CompareRow {
  std::string folder;  // the variant's subfolder of OUT
  std::string label;   // as on its tile
  std::string integrator;
  double dt = 0;
  long steps = 0;
  double simulated_time = 0;
  double simulate_seconds = 0;  // the run's own simulation time (run.json)
  double wall_seconds = 0;      // runScene, from start to run.json (export included)
  std::optional<double> blow_up_time;
  long blow_up_step = 0;
  double max_strain = 0;                  // over the frames reached
  std::optional<double> lost_shape_time;  // first frame over the bound
  std::optional<double> estimated_error;  // --estimate-error: the largest, m
  std::string estimate_note;              // its failure, if any
  std::string command;                    // the plain `wobble run` of the variant
};

struct CompareSummary {
  std::string scene;              // file
  std::vector<std::string> vary;  // the --vary flags as given
  std::string common;             // the run flags every variant shares
  double strain_bound = 0;
  bool estimate_error = false;
  int jobs = 1;     // variants run at once
  int threads = 1;  // hardware threads
  int pieces = 0;   // gathered from farm pieces: their count (jobs and threads are then the most in any piece)
  // Pictures: empty when not rendered.
  std::string video;   // "compare.mp4 (1280 x 720, 300 frames at 30 fps)" or why there is none
  std::string layout;  // "2 x 2 tiles of 640 x 360"
  std::vector<CompareRow> rows;
};

std::string compareMarkdown(const CompareSummary& summary);

}  // namespace wobble
