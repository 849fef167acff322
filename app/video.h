// encodeVideo: a numbered PNG sequence to an MP4 with ffmpeg (H.264 libx264, yuv420p, at the scene's frame rate).
// yuv420p needs even dimensions, so an odd width or height loses its last column or row. The video is written under
// a temporary name and renamed into place. ffmpeg is an external program (setup.sh installs it): when it is not on
// PATH, encodeVideo says so on stderr and returns nothing: the frames stay, and the run still succeeds. When wobble
// is interrupted (interrupt.h) ffmpeg is ended, its partial file removed, and nothing is returned.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

namespace wobble {

// frames_dir/<name>_NNNN.png for NNNN = first..last. Throws std::runtime_error if ffmpeg runs and fails.
std::optional<std::filesystem::path> encodeVideo(const std::filesystem::path& frames_dir, const std::string& name,
                                                 int first, int last, double fps, const std::filesystem::path& mp4);

}  // namespace wobble
