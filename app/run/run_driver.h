// RunDriver: one simulated run, frame by frame. It holds the Simulation of a system and, for a run that is watched
// (pictures), the shutter's recorder (motion blur's poses from the steps, shutter.h) and the camera rig that sees
// every frame (camera_rig.h). `wobble run`, the frame views of `wobble study render`, the studies and the error
// estimate all step their systems through it; none builds a Simulation of its own.
//   A scene's run: next() simulates up to the next frame (1, 2, ...); surfaces() and posed() give that frame's
//   surfaces and, watched, its picture's poses and camera.
//   A bare system (the studies, the error estimate's half-step run): advanceTo(t) at the times they sample.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/run/camera_rig.h"
#include "app/run/posed_frame.h"
#include "app/run/shutter.h"
#include "app/scene/scene_file.h"
#include "sim/simulation.h"

namespace wobble {

class RunDriver {
 public:
  // The scene's system with its integrator, options and step. Watched: the camera rig sees every frame and, when the
  // camera's shutter is open (camera.shutter > 0), the recorder keeps the poses inside each frame's shutter.
  explicit RunDriver(const SceneFile& scene, bool watched = false);
  // A system with the integrator, options and step given: no frames, no camera.
  RunDriver(MassSpringSystem& system, const std::string& integrator, const IntegratorOptions& options, double dt);
  RunDriver(const RunDriver&) = delete;  // the simulation's step observer points at this driver
  RunDriver& operator=(const RunDriver&) = delete;

  // Simulates up to the next frame's time (a scene's run). On a blow-up, returns it and stays there: the frame is
  // not reached (frame() is still the one before).
  std::optional<BlowUp> next();
  // The last frame reached: 0 before next().
  int frame() const { return frame_; }
  // Simulates up to time t (times in order).
  std::optional<BlowUp> advanceTo(double t) { return sim_.advanceTo(t); }

  // Every body's surface at the frame reached (scene body order), evaluated once per frame.
  const std::vector<SurfaceFrame>& surfaces();
  // The frame reached as its picture shows it (watched only): posed over its shutter from the recorded steps when the
  // shutter is open and the frame is not the first, else still; the camera there, moved over the shutter.
  PosedFrame posed();

  const Simulation& simulation() const { return sim_; }
  const VecX& x() const { return sim_.x(); }
  const MassSpringSystem& system() const { return system_; }

 private:
  const SurfaceFrame& surface(std::size_t body);  // of the frame reached, evaluated on first use

  const SceneFile* scene_ = nullptr;  // nothing for a bare system
  MassSpringSystem& system_;
  Simulation sim_;
  std::optional<CameraRig> rig_;
  std::optional<ShutterRecorder> shutter_;
  render::CameraParams camera_before_;  // the camera at the frame before the one reached (its shutter's start)
  int frame_ = 0;
  std::vector<SurfaceFrame> surfaces_;  // of the frame reached, per body, as asked for (evaluated_)
  std::vector<char> evaluated_;
};

}  // namespace wobble
