// `wobble video OUT`: the video of frames already rendered, in one piece or many (`wobble render --frames A:B` on
// several machines), without rendering again. Encodes OUT/frames/<scene>_NNNN.png into OUT/<scene>.mp4 with the
// encoder `run --video` uses (app/output/video.h), after checking every frame of the range: all there (else the
// missing ones, as --frames ranges), of one size, and rendered with one setting (the settings key each PNG carries,
// app/output/picture_key.h), unless allow_mixed. The scene's name, frame rate and range come from OUT/run.json, or
// from a scene file.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace wobble {

struct VideoOptions {
  std::filesystem::path out;
  std::optional<std::filesystem::path> scene;  // name, rate and frames from this scene instead of OUT/run.json
  std::vector<std::string> sets;               // overrides of that scene (as given to `wobble render`)
  std::optional<std::string> frames;           // "A:B": default the frames the run wrote, or all the scene's
  bool allow_mixed = false;                    // join frames of different settings
};

struct VideoReport {
  std::optional<std::filesystem::path> mp4;  // nothing when interrupted
  int first_frame = 0, last_frame = 0;
  double fps = 0;
  double seconds = 0;
};

// Throws InputError (exit 2, nothing written) for a folder without run.json and no --scene, missing frames, frames
// of different sizes or (without allow_mixed) settings, or a folder another wobble writes into; std::runtime_error
// when ffmpeg is not on PATH or fails.
VideoReport encodeFrames(const VideoOptions& options);

}  // namespace wobble
