// OutputFolder: a command's hold on its output folder (`--out`) while it writes there.
//
// The lock is OUT/.wobble.lock held with flock(2): the kernel releases it when the process ends however it ends, so a
// killed run leaves no stale lock; the file itself stays (removing it would race with the next run opening it).
// A second run on a held folder is refused at once (InputError: exit 2) naming the folder and the holders' pids
// (/proc/locks; else the pid the last holder wrote into the lock file).
// Holding the lock, temporary files that an earlier, killed run left behind are removed: no live writer owns them.
// Split rendering: `wobble render` pieces (each writing its own frames) hold the lock shared, so several render into
// one folder at once, while a run or `wobble video` (exclusive) is refused as long as one of them is there, and the
// other way round. A shared holder leaves temporary files alone (another piece's may be live); the next exclusive
// holder removes what killed pieces left.
#pragma once
#include <filesystem>
#include <string>
#include <utility>

namespace wobble {

class OutputFolder {
 public:
  enum class Access { exclusive, shared };
  // Creates `out` and takes its lock.
  explicit OutputFolder(std::filesystem::path out, Access access = Access::exclusive);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  // `wobble run` replaces whatever an earlier run left: removes the files with wobble's own output names
  // (mesh/<body>_NNNN.obj/.mtl, mesh/<body>.obj/.mtl/.pc2, frames/<scene>_NNNN.png, exr/<scene>_NNNN.exr, and
  // <scene>.mp4 and <scene>.blend of those scenes and of `scene`), nothing else, so the folder never mixes two runs
  // beside one run.json. Returns how many were removed. The scene's pictures (PNG, EXR) of frames keep.first to
  // keep.second stay: `wobble run --skip-existing` keeps those rendered with its settings.
  int clearEarlierRun(const std::string& scene, std::pair<int, int> keep = {1, 0}) const;

  static constexpr const char* kLockName = ".wobble.lock";

 private:
  std::filesystem::path out_;
  int fd_ = -1;
};

}  // namespace wobble
