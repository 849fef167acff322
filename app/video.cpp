#include "video.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <vector>

extern char** environ;

namespace fs = std::filesystem;

namespace wobble {

std::optional<fs::path> findOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / program;
    if (::access(candidate.c_str(), X_OK) == 0 && fs::is_regular_file(candidate)) return candidate;
  }
  return std::nullopt;
}

std::optional<fs::path> encodeVideo(const fs::path& frames_dir, const std::string& name, int first, int last,
                                    double fps, const fs::path& mp4) {
  const auto ffmpeg = findOnPath("ffmpeg");
  if (!ffmpeg) {
    std::fprintf(stderr, "wobble: ffmpeg not found on PATH: no video; the frames are in %s (install ffmpeg, "
                         "e.g. ./setup.sh, and rerun with `wobble render`)\n", frames_dir.c_str());
    return std::nullopt;
  }
  std::ostringstream rate;
  rate.precision(17);
  rate << fps;
  std::string temp_name = mp4.filename().string();  // appended piecewise: GCC 12 warns falsely (-Wrestrict)
  temp_name.insert(0, 1, '.');
  temp_name += ".partial";
  const fs::path temp = mp4.parent_path() / temp_name;
  // Arguments passed directly (no shell), so paths need no quoting.
  std::vector<std::string> args = {ffmpeg->string(), "-nostdin", "-y", "-loglevel", "error",
                                   "-framerate", rate.str(), "-start_number", std::to_string(first),
                                   "-i", (frames_dir / (name + "_%04d.png")).string(),
                                   "-frames:v", std::to_string(last - first + 1),
                                   "-vf", "crop=trunc(iw/2)*2:trunc(ih/2)*2", "-c:v", "libx264",
                                   "-pix_fmt", "yuv420p", "-r", rate.str(), "-f", "mp4", temp.string()};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (const int e = posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ); e != 0)
    throw std::runtime_error("cannot start " + ffmpeg->string() + ": " + std::to_string(e));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error("waiting for ffmpeg failed");
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    fs::remove(temp);
    throw std::runtime_error("ffmpeg failed encoding " + mp4.string() + " (exit status " +
                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
  }
  fs::rename(temp, mp4);
  return mp4;
}

}  // namespace wobble
