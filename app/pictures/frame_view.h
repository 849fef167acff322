// FrameView: one frame of a scene, ready to render: the scene run from t = 0 up to frame K (RunDriver, as
// `wobble run` does: the follow camera sees every frame on the way), its render scene updated to that frame (posed
// over its shutter when camera.shutter > 0: shutter.h), and the camera there.
// For studies and benchmarks that look at a single frame (`wobble study render`, bench/frame_bench.cpp).
#pragma once
#include "app/pictures/render_scene.h"
#include "app/scene/scene_file.h"
#include "render/camera.h"

namespace wobble {

struct FrameView {
  RenderScene scene;
  render::CameraParams camera;
  bool motion_blur = false;  // render with RenderSettings::motion_blur
};

// Throws InputError if the simulation blows up before the frame.
FrameView simulateTo(const SceneFile& scene, int frame);

}  // namespace wobble
