#include "app/run/run_driver.h"

#include <stdexcept>

namespace wobble {

RunDriver::RunDriver(const SceneFile& scene, bool watched)
    : scene_(&scene),
      system_(*scene.system),
      sim_(system_, makeIntegrator(scene.integrator, scene.integrator_options), scene.dt) {
  if (!watched) return;
  rig_.emplace(scene);
  camera_before_ = rig_->params();
  if (scene.render.camera.shutter > 0) {  // the steps' states are kept only for an open shutter
    shutter_.emplace(scene, sim_.x());
    sim_.observeSteps([this](double t, const VecX& x) { shutter_->step(t, x); });
  }
}

RunDriver::RunDriver(MassSpringSystem& system, const std::string& integrator, const IntegratorOptions& options,
                     double dt)
    : system_(system), sim_(system, makeIntegrator(integrator, options), dt) {}

std::optional<BlowUp> RunDriver::next() {
  if (!scene_) throw std::logic_error("RunDriver::next: a bare system has no frames");
  const int frame = frame_ + 1;
  if (shutter_) shutter_->begin(frame);
  if (auto blow_up = sim_.advanceTo(scene_->frameTime(frame))) return blow_up;
  frame_ = frame;
  evaluated_.assign(system_.bodies().size(), 0);
  surfaces_.resize(system_.bodies().size());
  if (rig_) {
    camera_before_ = rig_->params();
    if (rig_->followedBody() >= 0) rig_->observe(frame, surface(rig_->followedBody()));
  }
  return std::nullopt;
}

const SurfaceFrame& RunDriver::surface(std::size_t body) {
  if (!evaluated_[body]) {
    const BodySlot& slot = system_.bodies()[body];
    surfaces_[body] = evaluateSurface(slot.body.surface, sim_.x(), slot.first);
    evaluated_[body] = 1;
  }
  return surfaces_[body];
}

const std::vector<SurfaceFrame>& RunDriver::surfaces() {
  for (std::size_t b = 0; b < surfaces_.size(); ++b) surface(b);
  return surfaces_;
}

PosedFrame RunDriver::posed() {
  if (!rig_ || frame_ == 0) throw std::logic_error("RunDriver::posed: a watched run at a frame");
  PosedFrame p{frame_, shutterTimes(*scene_, frame_), {}, rig_->params()};
  if (p.motionBlur()) {  // an open shutter, past frame 1: the recorder's states at its instants, the last this frame
    const std::vector<VecX> states = shutter_->states(sim_.x());
    p.poses = surfacesOf(*scene_, std::span(states).first(states.size() - 1));
    p.camera.shutter_motion = shutterMotion(*scene_, camera_before_.position, p.camera.position);
  }
  p.poses.push_back(surfaces());
  return p;
}

}  // namespace wobble
