#include "video.h"

#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "external_program.h"
#include "interrupt.h"
#include "render/atomic_file.h"

namespace fs = std::filesystem;

namespace wobble {

std::optional<fs::path> encodeVideo(const fs::path& frames_dir, const std::string& name, int first, int last,
                                    double fps, const fs::path& mp4) {
  const auto ffmpeg = findProgram("ffmpeg");
  if (!ffmpeg) {
    std::fprintf(stderr, "wobble: ffmpeg not found on PATH: no video; the frames are in %s (install ffmpeg, "
                         "e.g. ./setup.sh, and rerun with `wobble render`)\n", frames_dir.c_str());
    return std::nullopt;
  }
  std::ostringstream rate;
  rate.precision(17);
  rate << fps;
  const fs::path temp = render::temporarySibling(mp4, "partial");  // "-f mp4" below: the name needs no extension
  // Arguments passed directly (no shell), so paths need no quoting.
  const std::vector<std::string> args = {ffmpeg->string(), "-nostdin", "-y", "-loglevel", "error",
                                   "-framerate", rate.str(), "-start_number", std::to_string(first),
                                   "-i", (frames_dir / (name + "_%04d.png")).string(),
                                   "-frames:v", std::to_string(last - first + 1),
                                   "-vf", "crop=trunc(iw/2)*2:trunc(ih/2)*2", "-c:v", "libx264",
                                   "-preset", "veryfast", "-crf", "20", "-pix_fmt", "yuv420p", "-r", rate.str(), "-f", "mp4", temp.string()};
  const int status = runProgram(args);
  std::error_code ignored;
  if (interrupted()) {  // ffmpeg was ended (or saw the terminal's Ctrl-C itself): no video, no partial file
    fs::remove(temp, ignored);
    return std::nullopt;
  }
  if (status != 0) {
    fs::remove(temp, ignored);
    throw std::runtime_error("ffmpeg failed encoding " + mp4.string() + " (exit status " + std::to_string(status) +
                             ")");
  }
  fs::rename(temp, mp4);
  return mp4;
}

}  // namespace wobble
