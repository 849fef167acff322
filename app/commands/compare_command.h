// `wobble compare SCENE --vary KEY=V1,V2,... [--vary KEY2=...] [run flags]`: the same scene under several settings,
// side by side, for reports on integrators, time steps and stiffness.
//   1. Every variant (one per value, or per pair of values with two --vary: rows x columns) is checked before
//      anything is written, then run by runScene exactly as `wobble run ... --render none --out OUT/<variant>` would
//      (its own folder, run.json, OBJs; its pictures are its tiles), several at once (--jobs), each run on its own.
//   2. Unless --render none (or the scene renders nothing), the variants are rendered from their OBJs through one
//      camera, the first variant's that ran to the end (its follow camera, or the scene's fixed one), at the size of
//      a tile (grid_layout.h), labelled (tile_label.h) and tiled into OUT/frames/compare_NNNN.png and OUT/compare.mp4.
//      A variant that blew up keeps its last frame, frozen, with a red label.
//   3. OUT/compare.md: the numbers (compare_report.h).
// On a farm (app/study/farm_pieces.h): `piece` runs step 1 for that piece's variants only (each into its folder as
// above; what steps 2 and 3 need of it kept in OUT/pieces/compare/), resuming, while other pieces run beside it;
// `gather` runs no variant and makes steps 2 and 3 from every piece's: the frames, video and numbers of a one-machine
// run.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/commands/run_command.h"
#include "app/compare/grid_layout.h"
#include "app/study/farm_pieces.h"
#include "app/study/study_stability.h"

namespace wobble {

struct CompareOptions {
  RunOptions run;                            // the scene and the run flags every variant gets (run.out is unused)
  std::vector<std::string> vary;             // one or two KEY=V1,V2,...
  std::optional<std::filesystem::path> out;  // default out/compare-<scene name>
  int jobs = 0;                              // variants run at once; 0: one per hardware thread
  double strain_bound = kStrainBound;        // lost its shape above this strain (the stability study's)
  std::optional<Piece> piece;                // run only this piece's variants (no pictures, no compare.md)
  bool gather = false;                       // run no variant: pictures and compare.md from every piece's
};

struct CompareVariant {
  std::string folder;   // OUT's subfolder: "2_pc-euler"
  std::string label;    // "pc-euler, dt = 1.2e-3, ks = 5e4"
  std::string command;  // the plain `wobble run` that gives the same folder
  RunOptions run;
  RunReport report;
  double wall_seconds = 0;
  double max_strain = 0;                // over the frames the run reached
  std::optional<int> lost_shape_frame;  // the first frame over the strain bound
  double lost_shape_strain = 0;
};

struct CompareReport {
  std::filesystem::path out;
  std::vector<CompareVariant> variants;
  std::optional<GridLayout> grid;  // when rendered
  int first_frame = 0, last_frame = 0, frames_rendered = 0;
  std::optional<std::filesystem::path> video;
  double seconds_runs = 0, seconds_render = 0;
  int jobs = 1;              // runs at once (gathered: the most in any piece)
  int threads = 1;           // hardware threads (gathered: the most of any piece's machine)
  int pieces = 0;            // gathered from this many pieces (--gather), else 0
  bool interrupted = false;  // SIGINT/SIGTERM: stopped after the runs or a frame; no compare.md
  std::size_t piece_first = 0, piece_last = 0, variants_resumed = 0;  // a piece: its variants [first, last)
  std::size_t variant_count = 0;                                      // of the whole comparison
};

// Throws InputError (exit 2, nothing written) for a bad --vary, scene, flag or any variant's settings, and
// std::runtime_error when the labels' font is missing (before anything is written) or on an I/O error.
CompareReport runCompare(const CompareOptions& options);

}  // namespace wobble
