#include "app/commands/video_command.h"

#include <map>

#include "app/commands/frame_range.h"
#include "app/commands/wall_clock.h"
#include "app/output/external_program.h"
#include "app/output/output_folder.h"
#include "app/output/picture_key.h"
#include "app/output/run_record.h"
#include "app/output/video.h"
#include "app/pictures/frame_output.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "image/image_header.h"
#include "image/png_io.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

// Sorted frame numbers as --frames ranges: "5 17:18 30:40"; at most `limit` ranges, then "...".
std::string rangesText(const std::vector<int>& frames, std::size_t limit = 12) {
  std::string text;
  std::size_t ranges = 0;
  for (std::size_t i = 0; i < frames.size();) {
    std::size_t j = i;
    while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
    if (++ranges > limit) return text + " ...";
    text += (text.empty() ? "" : " ") + std::to_string(frames[i]);
    if (j > i) text += ":" + std::to_string(frames[j]);
    i = j + 1;
  }
  return text;
}

// Frames grouped by a property (a size, a settings key), in order of their first frame, as one line each.
std::string groupsText(const std::map<std::string, std::vector<int>>& groups) {
  std::map<int, std::string> lines;
  for (const auto& [what, frames] : groups) lines[frames.front()] = "\n  frames " + rangesText(frames) + ": " + what;
  std::string text;
  for (const auto& [first, line] : lines) text += line;
  return text;
}

}  // namespace

VideoReport encodeFrames(const VideoOptions& options) {
  const fs::path& out = options.out;
  if (!fs::is_directory(out)) throw InputError(out.string() + ": no such folder (OUT is a run's output folder)");
  if (!options.sets.empty() && !options.scene) throw InputError("--set: needs --scene (the overrides of that scene)");
  std::string name;
  VideoReport report;
  if (options.scene) {
    const SceneFile scene = loadScene(*options.scene, options.sets);
    name = scene.name, report.fps = scene.fps;
    std::tie(report.first_frame, report.last_frame) =
        options.frames ? parseFrameRange(*options.frames, scene.frameCount()) : std::pair{1, scene.frameCount()};
  } else {
    const RunRecord run = readRunRecord(out, "; name the scene with --scene FILE");
    name = run.sceneName(), report.fps = run.fps;
    std::tie(report.first_frame, report.last_frame) =
        options.frames ? parseFrameRange(*options.frames, run.first_frame, run.last_frame, run.framesText())
                       : std::pair{run.first_frame, run.last_frame};
  }

  const OutputFolder folder(out);  // not while pieces still render into it
  const fs::path frames_dir = out / "frames";
  std::vector<int> missing;
  std::map<std::string, std::vector<int>> sizes, settings;
  for (int k = report.first_frame; k <= report.last_frame; ++k) {
    const fs::path png = FrameOutput::pngPath(out, name, k);
    std::string reason;
    const auto header = fs::is_regular_file(png) ? image::readImageHeader(png, reason) : std::nullopt;
    if (!header) {
      missing.push_back(k);
      continue;
    }
    sizes[std::to_string(header->width) + " x " + std::to_string(header->height)].push_back(k);
    const auto text = image::readPngText(png);
    const auto key = text.find(PictureKey::kSettingsName);
    settings[key == text.end() ? "no settings recorded (an older wobble's frames)" : "settings " + key->second]
        .push_back(k);
  }
  const int count = report.last_frame - report.first_frame + 1;
  if (!missing.empty())
    throw InputError(frames_dir.string() + ": " + std::to_string(missing.size()) + " of " + std::to_string(count) +
                     " frame(s) of " + name + " missing or unreadable (" + name + "_NNNN.png), as --frames: " +
                     rangesText(missing) + "; render them (wobble render " + out.string() +
                     " --frames A:B --skip-existing), then run "
                     "wobble video again");
  if (sizes.size() > 1)
    throw InputError(frames_dir.string() + ": the frames of " + name +
                     " differ in size (rendered with another "
                     "--resolution or --quality?); a video needs one size:" +
                     groupsText(sizes));
  if (settings.size() > 1 && !options.allow_mixed)
    throw InputError(frames_dir.string() + ": the frames of " + name +
                     " were rendered with different settings "
                     "(scene, --set, render flags, textures or wobble build):" +
                     groupsText(settings) +
                     "\nrender them again with one setting (--skip-existing keeps the right ones), or join them "
                     "anyway with --allow-mixed");

  if (!findProgram("ffmpeg"))
    throw std::runtime_error("ffmpeg not found on PATH: wobble video needs it (install ffmpeg, e.g. ./setup.sh)");
  const auto start = Clock::now();
  report.mp4 = encodeVideo(frames_dir, name, report.first_frame, report.last_frame, report.fps, out / (name + ".mp4"));
  report.seconds = secondsSince(start);
  return report;
}

}  // namespace wobble
