// FrameOutput: renders frames while a run simulates (or from an OBJ sequence, render_command.cpp) and writes them:
// OUT/frames/<scene>_NNNN.png and, when asked, OUT/exr/<scene>_NNNN.exr (colour, albedo, normal, depth), each under a
// temporary name and renamed into place. Render settings come from the scene's [render] and [camera] tables.
// Determinism: the renderer's noise is seeded by the frame number, so a frame is the same bytes whoever renders it
// (a run, or `wobble render` of its OBJ sequence) and whatever the thread count.
// Every file records its picture key (picture_key.h). With skip_existing, a frame whose files are all there with
// the key this frame would get is not rendered again (a resumed or re-queued piece carries on where it stopped);
// the video still gets it, decoded from its PNG.
#pragma once
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "app/output/picture_key.h"
#include "app/output/video.h"
#include "app/pictures/render_scene.h"
#include "app/run/posed_frame.h"
#include "app/scene/scene_file.h"

namespace wobble {

class FrameOutput {
 public:
  // True when the scene asks for images (render.png or render.exr).
  static bool wanted(const SceneFile& scene);
  // Creates OUT/frames and/or OUT/exr; loads the textures.
  FrameOutput(const SceneFile& scene, std::filesystem::path out, bool skip_existing = false);

  // Renders a posed frame (a run's, RunDriver::posed; a sequence's, SequencePoser::posed) and writes its files.
  void frame(const PosedFrame& posed);

  // After the last frame: waits for the last files and for OUT/<scene>.mp4, encoded (when render.video is set) from
  // the frames as they were written (video.h: VideoStream). Returns the video's path, or nothing (not asked, no
  // frame, interrupted, or ffmpeg is missing: then it was said).
  std::optional<std::filesystem::path> finish();

  int framesRendered() const { return rendered_; }
  int framesSkipped() const { return skipped_; }  // kept: there already, with this frame's picture key
  static std::filesystem::path pngPath(const std::filesystem::path& out, const std::string& scene, int frame);
  static std::filesystem::path exrPath(const std::filesystem::path& out, const std::string& scene, int frame);

 private:
  void render(int frame, const render::CameraParams& camera, const std::string& key, bool motion_blur);
  bool existing(int frame, const std::string& key) const;  // every file the scene asks for, with this key
  void keep(int frame);                                    // an existing frame: only the video needs it
  void toVideo(const image::Image8& image);                // on the writer thread, frames in order

  const SceneFile& scene_;
  std::filesystem::path out_;
  RenderScene render_scene_;
  PictureKey key_;
  bool skip_existing_;
  int rendered_ = 0, skipped_ = 0;
  // A frame's files (tone mapping, PNG and EXR encoding: single-threaded) are written while the next frame is
  // simulated and rendered; at most one frame waits. get() rethrows a write error.
  std::future<void> writing_;
  std::unique_ptr<VideoStream> video_;  // opened with the first PNG written (its size), fed by the writer
  bool video_opened_ = false;
};

}  // namespace wobble
