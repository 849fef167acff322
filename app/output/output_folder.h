// OutputFolder: a command's hold on its output folder (`--out`) while it writes there.
//
// The lock is OUT/.wobble.lock held with flock(2): the kernel releases it when the process ends however it ends, so a
// killed run leaves no stale lock; the file itself stays (removing it would race with the next run opening it).
// A second run on a held folder is refused at once (InputError: exit 2) naming the folder and the holder's pid.
// Holding the lock, temporary files that an earlier, killed run left behind are removed: no live writer owns them.
#pragma once
#include <filesystem>
#include <string>

namespace wobble {

class OutputFolder {
 public:
  // Creates `out` and takes its lock.
  explicit OutputFolder(std::filesystem::path out);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  // `wobble run` replaces whatever an earlier run left: removes the files with wobble's own output names
  // (mesh/<body>_NNNN.obj/.mtl, mesh/<body>.obj/.mtl/.pc2, frames/<scene>_NNNN.png, exr/<scene>_NNNN.exr, and
  // <scene>.mp4 and <scene>.blend of those scenes and of `scene`), nothing else, so the folder never mixes two runs
  // beside one run.json. Returns how many were removed.
  int clearEarlierRun(const std::string& scene) const;

  static constexpr const char* kLockName = ".wobble.lock";

 private:
  std::filesystem::path out_;
  int fd_ = -1;
};

}  // namespace wobble
