// FrameView: one frame of a scene, ready to render: the scene simulated from t = 0 up to frame K (the follow camera
// observing every frame on the way, as in a run), its render scene updated to that frame (posed over its shutter when
// camera.shutter > 0, as a run: shutter.h), and the camera there.
// For studies and benchmarks that look at a single frame (`wobble study render`, bench/frame_bench.cpp).
#pragma once
#include "app/scene/scene_file.h"
#include "app/view/render_scene.h"
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
