// RunRecord: what later commands read back from a run's OUT/run.json (written by app/commands/run_command.cpp): the
// scene file and the overrides the run applied, the frames it wrote and their rate. `wobble blend` rebuilds the
// scene from it; `wobble video` and `wobble frames` take the scene's name, the frame range and the rate.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace wobble {

struct RunRecord {
  std::filesystem::path scene;
  std::vector<std::string> overrides;
  int first_frame = 0, last_frame = 0;  // the frames written (a run that blew up stops early)
  double fps = 0;

  std::string sceneName() const { return scene.stem().string(); }  // as SceneFile::name: names the frames and video
  std::string framesText() const;                                  // "the run wrote frames A:B", for messages
};

// Throws InputError naming the file when OUT has no run.json (the message ends with `missing`, e.g. how to make
// one), when it is not a wobble run.json, or when the run wrote no frame.
RunRecord readRunRecord(const std::filesystem::path& out, const std::string& missing);

}  // namespace wobble
