#include "app/output/output_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <regex>
#include <set>
#include <system_error>
#include <vector>

#include "app/scene/input_error.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

// The subfolders wobble writes into, and the folder itself.
std::vector<fs::path> outputDirs(const fs::path& out) { return {out, out / "mesh", out / "frames", out / "exr"}; }

// Removes the regular files of dir whose names match `name`; returns how many, and collects match[1] into stems.
int removeMatching(const fs::path& dir, const std::regex& name, std::set<std::string>* stems = nullptr) {
  std::error_code ec;
  int removed = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    std::smatch match;
    const std::string file = entry.path().filename().string();
    if (!entry.is_regular_file(ec) || !std::regex_match(file, match, name)) continue;
    if (fs::remove(entry.path(), ec)) ++removed;
    if (stems && match.size() > 1) stems->insert(match[1].str());
  }
  return removed;
}

}  // namespace

OutputFolder::OutputFolder(fs::path out) : out_(std::move(out)) {
  fs::create_directories(out_);
  const fs::path lock = out_ / kLockName;
  fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(lock.string() + ": cannot open: " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    char holder[32] = {};
    const ssize_t n = ::pread(fd_, holder, sizeof holder - 1, 0);
    ::close(fd_);
    if (error != EWOULDBLOCK) throw std::runtime_error(lock.string() + ": cannot lock: " + std::strerror(error));
    throw InputError(out_.string() + ": another wobble (pid " + (n > 0 ? std::string(holder) : "unknown") +
                     ") is writing into this folder (it holds " + lock.string() +
                     "); wait for it to finish or choose another --out");
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) != ssize_t(pid.size()))
    throw std::runtime_error(lock.string() + ": cannot write: " + std::strerror(errno));
  // Temporary names are ".<name>.tmp<pid>-<n>" and ".<name>.partial<pid>-<n>" (io/atomic_file.h); older
  // versions left an empty mesh/.partial/.
  static const std::regex temporary(R"(\..+\.(tmp|partial)[0-9]+-[0-9]+)");
  for (const fs::path& dir : outputDirs(out_)) removeMatching(dir, temporary);
  std::error_code ignored;
  fs::remove(out_ / "mesh" / ".partial", ignored);  // only when empty
}

OutputFolder::~OutputFolder() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

int OutputFolder::clearEarlierRun(const std::string& scene) const {
  std::set<std::string> scenes = {scene};
  // The sequence, and the point caches with their base meshes (names are identifiers: scene_limits.h).
  int removed = removeMatching(out_ / "mesh", std::regex(R"(.+_[0-9]{4,}\.(obj|mtl))"));
  removed += removeMatching(out_ / "mesh", std::regex(R"([A-Za-z0-9_-]+\.(obj|mtl|pc2))"));
  removed += removeMatching(out_ / "frames", std::regex(R"((.+)_[0-9]{4,}\.png)"), &scenes);
  removed += removeMatching(out_ / "exr", std::regex(R"((.+)_[0-9]{4,}\.exr)"), &scenes);
  std::error_code ignored;
  for (const std::string& s : scenes)
    for (const char* extension : {".mp4", ".blend"}) removed += fs::remove(out_ / (s + extension), ignored) ? 1 : 0;
  return removed;
}

}  // namespace wobble
