// Shutter: when a frame's motion blur poses the scene (camera.shutter; render/scene.h "Motion blur").
// The shutter of frame k, at time t_k, is open over [t_k - shutter / fps, t_k]: it closes at the frame's own time,
// so a run renders frame k right after simulating to it, with no step simulated ahead (Blender's motion blur
// position "end"; `wobble blend` sets it). The scene is posed at kShutterPoses evenly spaced instants over it, the
// last the frame itself; Embree interpolates linearly between them. Frame 1 (t = 0, nothing before it) is still.
//   ShutterRecorder: the poses of a run, from the simulation's own steps (no second simulation): the state at each
//     instant is blended linearly between the ends of the step that spans it (a step, dt, is far shorter than a frame).
//   blendSurfaces: the poses of a render from an OBJ sequence, blended linearly from the frame before to this one.
#pragma once
#include <span>
#include <vector>

#include <Eigen/Core>

#include "app/scene/scene_file.h"
#include "sim/surface.h"

namespace wobble {

constexpr int kShutterPoses = 4;

// The instants of frame k's poses, open to close: one (t_k) when the shutter is 0 or k is 1.
std::vector<double> shutterTimes(const SceneFile& scene, int frame);

// How far a moving camera travels while frame k's shutter is open: the shutter's fraction of its move from frame
// k - 1's position (`before`) to frame k's (`at`); the renderer moves the eye back along it over the shutter
// (render::CameraParams::shutter_motion).
Eigen::Vector3f shutterMotion(const SceneFile& scene, const Eigen::Vector3f& before, const Eigen::Vector3f& at);

class ShutterRecorder {
 public:
  // x0: the state at t = 0.
  ShutterRecorder(const SceneFile& scene, const VecX& x0);
  // Before simulating up to frame k (frames in order).
  void begin(int frame);
  // After every simulation step (Simulation::observeSteps).
  void step(double t, const VecX& x);
  // After simulating up to frame k, whose state is x: the state at each of shutterTimes(k) (the last is x).
  std::vector<VecX> states(const VecX& x) const;

 private:
  const SceneFile& scene_;
  std::vector<double> times_;
  std::vector<VecX> states_;
  std::vector<char> filled_;
  double t_prev_ = 0;
  VecX x_prev_;
};

// Every body's surfaces at each of frame k's shutter instants, blended linearly in time from `before` (frame k - 1)
// to `after` (frame k): poses[j][body], the last `after` itself. Vertex normals are blended and renormalised.
std::vector<std::vector<SurfaceFrame>> blendSurfaces(const SceneFile& scene, int frame,
                                                     std::span<const SurfaceFrame> before,
                                                     std::span<const SurfaceFrame> after);

// Every body's surfaces at each of the states (poses[j][body]).
std::vector<std::vector<SurfaceFrame>> surfacesOf(const SceneFile& scene, std::span<const VecX> states);

}  // namespace wobble
