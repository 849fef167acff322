// A run folder stands alone: `wobble run` carries the scene as resolved and every file it reads into OUT/scene/, so
// `wobble render OUT`, `wobble blend OUT`, `wobble video OUT` and `wobble frames OUT` work from any directory, after
// the folder has moved and after the project it was made from is gone.
//
//   OUT/scene/<scene>.toml           the scene after --set and the flags (scene.text), each file key pointing at its
//                                    carried copy: the same scene, the same name, the same pictures
//   OUT/scene/files/<hash>/<name>    each texture, model and environment map, content-addressed (the first 16 hex
//                                    digits of its XXH3 hash; the file name kept, as an MTL names it)
//
// run.json lists them (`carried`): path relative to OUT, content hash, and where it came from. A command that reads
// the scene back checks every carried file first (checkCarriedFiles) and refuses, naming the file, one that is missing
// or altered: nothing is written from a scene that is not the run's.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "app/scene/scene_file.h"

namespace wobble {

struct CarriedFile {
  std::string path;    // relative to OUT, '/'-separated: "scene/jelly_slope.toml", "scene/files/0123.../cat.png"
  std::string hash;    // io::ContentHash of its bytes, 32 hex digits
  std::string source;  // the file it was copied from, as the run named it (the scene itself: its file as given)
};

// Writes OUT/scene/ for `scene` (OUT exists), replacing an earlier run's; returns the scene file first, then the
// files. Throws std::runtime_error naming a file that cannot be read or written.
std::vector<CarriedFile> carryScene(const SceneFile& scene, const std::filesystem::path& out);

// Every carried file is there with its bytes. Throws InputError naming the first that is missing or altered.
void checkCarriedFiles(const std::filesystem::path& out, const std::vector<CarriedFile>& files);

// The bytes carryScene would write: the scene text and the files (for the disk budget).
std::uintmax_t carriedBytes(const SceneFile& scene);

}  // namespace wobble
