// PictureKey: what a rendered frame records about how it was made, so that `--skip-existing` can tell a frame
// rendered before with the same settings from a stale one, and `wobble video` can refuse to join frames of
// different settings. Two digests (io/content_hash.h), stored in each PNG's text chunks and each EXR's header:
//   settings (kSettingsName): one per scene as read: the wobble program itself (another build may draw otherwise),
//     the scene text after overrides without the keys that only choose outputs (SceneFile::picture_text: camera,
//     resolution, render settings, looks, colliders, frame rate, the bodies), and the bytes of every texture file and
//     of the environment map;
//   frame (kFrameName): the settings, the frame number (it seeds the noise), that frame's camera (a follow camera
//     depends on the earlier frames) and every body's surface as the renderer gets it (at every instant of a
//     motion-blurred shutter): from the simulation in
//     `wobble run`, from the OBJ files in `wobble render` (so an edited or re-simulated mesh renders again).
// Left out because they do not change a picture: the thread count, the output folder, --frames, --video, EXR or not.
#pragma once
#include <map>
#include <span>
#include <string>

#include "app/scene/scene_file.h"
#include "render/camera.h"
#include "sim/surface.h"

namespace wobble {

class PictureKey {
 public:
  static constexpr const char* kSettingsName = "wobble-settings";
  static constexpr const char* kFrameName = "wobble-frame";

  explicit PictureKey(const SceneFile& scene);  // reads the program and the texture files: once per command

  const std::string& settings() const { return settings_; }
  std::string frame(int frame, const render::CameraParams& camera, std::span<const SurfaceFrame> surfaces) const;
  // A frame's text chunks (PNG) or attributes (EXR): both digests under their names.
  std::map<std::string, std::string> text(const std::string& frame_key) const;

 private:
  std::string settings_;
};

}  // namespace wobble
