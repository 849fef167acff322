#include "app/run/sequence_poser.h"

#include <algorithm>

#include "app/run/shutter.h"

namespace wobble {

SequencePoser::SequencePoser(const SceneFile& scene) : scene_(scene), rig_(scene) {}

void SequencePoser::observe(int frame, std::span<const SurfaceFrame> surfaces) {
  camera_before_ = rig_.params();
  if (rig_.followedBody() >= 0) rig_.observe(frame, surfaces[rig_.followedBody()]);
  const bool complete = frame_ > 0 && std::none_of(current_.begin(), current_.end(),
                                                   [](const SurfaceFrame& s) { return s.positions.empty(); });
  previous_frame_ = complete ? frame_ : -1;
  previous_ = std::move(current_);
  current_.assign(surfaces.begin(), surfaces.end());
  frame_ = frame;
}

PosedFrame SequencePoser::posed() const {
  PosedFrame p{frame_, shutterTimes(scene_, frame_), {}, rig_.params()};
  if (p.motionBlur() && previous_frame_ == frame_ - 1) {
    p.poses = blendSurfaces(scene_, frame_, previous_, current_);
    p.camera.shutter_motion = shutterMotion(scene_, camera_before_.position, p.camera.position);
  } else {
    p.times = {scene_.frameTime(frame_)};
    p.poses = {current_};
  }
  return p;
}

}  // namespace wobble
