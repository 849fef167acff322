// `wobble render OUT` (or `wobble render MESH_DIR --scene SCENE`): renders an existing OBJ sequence (a run's OUT/mesh)
// without simulating again, so frames can be re-rendered with other settings or rendered in pieces (--frames A:B).
// Without --scene, the scene is the one the run carried (run_record.h: OUT/scene, checked against run.json), so a run
// folder renders from any directory, wherever it has moved; MESH_DIR may then be OUT itself. Bodies come from the
// OBJ files (obj_sequence_reader.h); colliders from the scene at each frame's time; output as `wobble run`'s
// (frame_output.h), into the folder that holds MESH_DIR unless --out says otherwise. Pieces of one sequence may render
// into one folder at the same time (output_folder.h: a shared hold), each its own --frames; a piece makes no video
// unless --video asks (`wobble video` joins the pieces).
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/scene/scene_flags.h"

namespace wobble {

struct RenderCommandOptions {
  std::filesystem::path mesh_dir;              // OUT/mesh, or (without scene) OUT
  std::optional<std::filesystem::path> scene;  // default: the scene the run in MESH_DIR's folder carried
  std::optional<std::string> frames;           // "A:B" or "A"; default: every frame MESH_DIR holds
  std::optional<std::filesystem::path> out;    // default: MESH_DIR's parent
  std::vector<std::string> sets;               // KEY=VALUE scene overrides, as for `wobble run`
  RenderFlags render;
  bool skip_existing = false;  // keep frames already rendered with the same settings (frame_output.h)
};

struct RenderCommandReport {
  std::filesystem::path out;
  int first_frame = 0, last_frame = 0, frames_rendered = 0;
  int frames_skipped = 0;  // --skip-existing: already there with the same picture key
  double seconds = 0;
  std::optional<std::filesystem::path> video;
  bool piece_without_video = false;  // the scene asks for a video, but --frames renders a piece (and no --video)
};

// Throws InputError (bad input, nothing written): a bad scene or flag, a missing MESH_DIR or frame file, an OBJ that
// does not match the scene's bodies, no run.json without --scene, a carried file missing or altered.
RenderCommandReport renderSequence(const RenderCommandOptions& options);

}  // namespace wobble
