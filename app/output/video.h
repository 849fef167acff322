// encodeVideo: a numbered PNG sequence to an MP4 with ffmpeg (H.264 libx264, yuv420p, at the scene's frame rate).
// yuv420p needs even dimensions, so an odd width or height loses its last column or row. The video is written under
// a temporary name and renamed into place. ffmpeg is an external program (setup.sh installs it): when it is not on
// PATH, encodeVideo says so on stderr and returns nothing: the frames stay, and the run still succeeds. When wobble
// is interrupted (interrupt.h) ffmpeg is ended, its partial file removed, and nothing is returned.
//
// VideoStream: the same video made while the frames are: each frame's pixels go to ffmpeg's standard input as they
// are written, so the MP4 is done with the last frame, and the PNGs are not decoded again. Same encoder settings, so
// the same video as encodeVideo of the frames.
#pragma once
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "image/image.h"

namespace wobble {

// frames_dir/<name>_NNNN.png for NNNN = first..last. Throws std::runtime_error if ffmpeg runs and fails.
std::optional<std::filesystem::path> encodeVideo(const std::filesystem::path& frames_dir, const std::string& name,
                                                 int first, int last, double fps, const std::filesystem::path& mp4);

class VideoStream {
 public:
  // Starts ffmpeg on `mp4` (under a temporary name) for frames of width x height; nothing when ffmpeg is not on PATH
  // (said on stderr, as encodeVideo). Throws std::runtime_error when it cannot be started.
  static std::unique_ptr<VideoStream> open(const std::filesystem::path& mp4, int width, int height, double fps);
  ~VideoStream();  // not finished (an error, an interrupt): ends ffmpeg and removes its partial file
  VideoStream(const VideoStream&) = delete;
  VideoStream& operator=(const VideoStream&) = delete;

  // The next frame (RGB, the size given to open). If ffmpeg has stopped reading, nothing: finish() reports it.
  void write(const image::Image8& frame);
  // Ends the input, waits for ffmpeg and renames the video into place; returns its path. Nothing when wobble was
  // interrupted (the partial file is removed). Throws std::runtime_error if ffmpeg failed.
  std::optional<std::filesystem::path> finish();

 private:
  VideoStream(std::filesystem::path mp4, std::filesystem::path temp, int pid, int input, int width, int height);
  void abandon();

  std::filesystem::path mp4_, temp_;
  int pid_ = -1, input_ = -1;
  int width_, height_;
};

}  // namespace wobble
