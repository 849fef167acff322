// RunRecord: what later commands read back from a run's OUT/run.json (written by app/commands/run_command.cpp): the
// scene file and the overrides the run applied, the frames it wrote and their rate, and the files it carried
// (carried_scene.h). `wobble blend` and `wobble render OUT` rebuild the scene from it (loadRecordedScene); `wobble
// video` and `wobble frames` take the scene's name, the frame range and the rate.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "app/output/carried_scene.h"

namespace wobble {

struct RunRecord {
  // The run's carried scene, OUT/scene/<scene>.toml (run.json names it relative to OUT); for a folder of a wobble
  // that carried nothing (no `carried` in run.json), the scene file as that run named it.
  std::filesystem::path scene;
  std::vector<CarriedFile> carried;  // the scene copy first; empty for such an older folder
  std::vector<std::string> overrides;
  int first_frame = 0, last_frame = 0;  // the frames written (a run that blew up stops early)
  double fps = 0;

  std::string sceneName() const { return scene.stem().string(); }  // as SceneFile::name: names the frames and video
  std::string framesText() const;                                  // "the run wrote frames A:B", for messages
};

// Throws InputError naming the file when OUT has no run.json (the message ends with `missing`, e.g. how to make
// one), when it is not a wobble run.json, or when the run wrote no frame.
RunRecord readRunRecord(const std::filesystem::path& out, const std::string& missing);

// The scene the run simulated: run.scene with the run's overrides, then `sets` and `flags` (a re-render's own), after
// checkCarriedFiles. Throws InputError.
SceneFile loadRecordedScene(const std::filesystem::path& out, const RunRecord& run,
                            const std::vector<std::string>& sets = {}, const SceneFlags& flags = {});

}  // namespace wobble
