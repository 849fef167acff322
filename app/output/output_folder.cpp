#include "app/output/output_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>
#include <system_error>
#include <vector>

#include "app/scene/input_error.h"
#include "io/writable_place.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

// The subfolders wobble writes into, and the folder itself.
std::vector<fs::path> outputDirs(const fs::path& out) { return {out, out / "mesh", out / "frames", out / "exr"}; }

// Removes the regular files of dir whose names match `name` and that `keep` (given the match) does not keep; returns
// how many, and collects match[1] into stems.
int removeMatching(const fs::path& dir, const std::regex& name, std::set<std::string>* stems = nullptr,
                   const std::function<bool(const std::smatch&)>& keep = {}) {
  std::error_code ec;
  int removed = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    std::smatch match;
    const std::string file = entry.path().filename().string();
    if (!entry.is_regular_file(ec) || !std::regex_match(file, match, name)) continue;
    if (stems && match.size() > 1) stems->insert(match[1].str());
    if (keep && keep(match)) continue;
    if (fs::remove(entry.path(), ec)) ++removed;
  }
  return removed;
}

// The pids holding a flock on the file open as fd, from /proc/locks (Linux; a holder on another NFS client is not
// there). Several when pieces of a split render share the folder.
std::vector<std::string> lockHolders(int fd) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) return {};
  char id[64];
  std::snprintf(id, sizeof id, "%02x:%02x:%lu", major(st.st_dev), minor(st.st_dev),
                static_cast<unsigned long>(st.st_ino));
  std::vector<std::string> pids;
  std::ifstream locks("/proc/locks");
  for (std::string line; std::getline(locks, line);) {  // "1: FLOCK  ADVISORY  READ 6000 fe:00:10953816 0 EOF"
    std::istringstream in(line);
    std::string number, type, advisory, mode, pid, where;
    if (in >> number >> type >> advisory >> mode >> pid >> where && type == "FLOCK" && where == id) pids.push_back(pid);
  }
  return pids;
}

}  // namespace

OutputFolder::OutputFolder(fs::path out, Access access) : out_(std::move(out)) {
  io::checkWritable(out_);  // the OS's reason, naming the folder
  fs::create_directories(out_);
  const fs::path lock = out_ / kLockName;
  fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(lock.string() + ": cannot open: " + std::strerror(errno));
  const bool exclusive = access == Access::exclusive;
  if (::flock(fd_, (exclusive ? LOCK_EX : LOCK_SH) | LOCK_NB) != 0) {
    const int error = errno;
    char holder[32] = {};
    const ssize_t n = ::pread(fd_, holder, sizeof holder - 1, 0);
    if (error != EWOULDBLOCK) {
      ::close(fd_);
      throw std::runtime_error(lock.string() + ": cannot lock: " + std::strerror(error));
    }
    std::vector<std::string> pids = lockHolders(fd_);
    ::close(fd_);
    if (pids.empty()) {  // the last holder's own word (lock file)
      pids.push_back(n > 0 ? std::string(holder) : "unknown");
      pids.back().erase(pids.back().find_last_not_of(' ') + 1);
    }
    std::string list;
    for (const std::string& pid : pids) list += (list.empty() ? "" : ", ") + pid;
    throw InputError(out_.string() + (pids.size() == 1 ? ": another wobble (pid " : ": other wobbles (pids ") + list +
                     ") " + (pids.size() == 1 ? "is" : "are") + " writing into this folder (holding " + lock.string() +
                     "); wait for " + (pids.size() == 1 ? "it" : "them") + " to finish or choose another --out");
  }
  // The holder's pid for that message, padded to a fixed width: shared holders overwrite it without truncating, so
  // the file always holds one whole pid.
  char pid[16];
  std::snprintf(pid, sizeof pid, "%-12d", int(::getpid()));
  if ((exclusive && ::ftruncate(fd_, 0) != 0) || ::pwrite(fd_, pid, 12, 0) != 12)
    throw std::runtime_error(lock.string() + ": cannot write: " + std::strerror(errno));
  if (!exclusive) return;
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

int OutputFolder::clearEarlierRun(const std::string& scene, std::pair<int, int> keep) const {
  std::set<std::string> scenes = {scene};
  // The sequence, and the point caches with their base meshes (names are identifiers: scene_limits.h).
  int removed = removeMatching(out_ / "mesh", std::regex(R"(.+_[0-9]{4,}\.(obj|mtl))"));
  removed += removeMatching(out_ / "mesh", std::regex(R"([A-Za-z0-9_-]+\.(obj|mtl|pc2))"));
  const auto kept = [&](const std::smatch& m) {
    if (m[1].str() != scene || m[2].length() > 9) return false;
    const int frame = std::stoi(m[2].str());
    return frame >= keep.first && frame <= keep.second;
  };
  removed += removeMatching(out_ / "frames", std::regex(R"((.+)_([0-9]{4,})\.png)"), &scenes, kept);
  removed += removeMatching(out_ / "exr", std::regex(R"((.+)_([0-9]{4,})\.exr)"), &scenes, kept);
  std::error_code ignored;
  for (const std::string& s : scenes)
    for (const char* extension : {".mp4", ".blend"}) removed += fs::remove(out_ / (s + extension), ignored) ? 1 : 0;
  return removed;
}

}  // namespace wobble
