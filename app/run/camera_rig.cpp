#include "app/run/camera_rig.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

namespace wobble {
namespace {

// Bounding box of the bodies at t = 0 and the colliders that have an extent (Collider::bounds: planes are left out).
Eigen::AlignedBox3d actionBox(const SceneFile& scene) {
  Eigen::AlignedBox3d box;
  for (const BodySlot& slot : scene.system->bodies())
    for (int i = 0; i < slot.body.particleCount(); ++i) box.extend(Vec3(slot.body.x.segment<3>(3 * i)));
  for (const auto& c : scene.system->colliders())
    if (const auto bounds = c->bounds(0)) box.extend(*bounds);
  return box;
}

}  // namespace

Vec3 centroid(const SurfaceFrame& surface) {
  Vec3 sum = Vec3::Zero();
  for (const auto& p : surface.positions) sum += p.cast<double>();
  return surface.positions.empty() ? sum : Vec3(sum / double(surface.positions.size()));
}

CameraRig::CameraRig(const SceneFile& scene) {
  const CameraConfig& c = scene.render.camera;
  up_ = c.up;
  fov_deg_ = c.fov_deg;
  aperture_ = c.aperture;
  focus_ = c.focus;
  focus_follow_ = c.focus_follow;
  width_ = c.resolution[0];
  height_ = c.resolution[1];
  const Eigen::AlignedBox3d box = actionBox(scene);
  look_at_ = c.look_at.value_or(box.center());
  if (c.position) {
    position_ = *c.position;
  } else {
    const double radius = std::max(0.5 * box.diagonal().norm(), 1.0);
    const double distance = 1.1 * radius / std::sin(0.5 * fov_deg_ * M_PI / 180);
    position_ = look_at_ + distance * Vec3(0.35, 0.45, 1).normalized();
  }
  if (!c.follow.empty()) {
    const auto& bodies = scene.system->bodies();
    for (std::size_t b = 0; b < bodies.size(); ++b)
      if (bodies[b].body.name == c.follow) followed_ = static_cast<int>(b);
    const Body& body = bodies[followed_].body;
    first_ = centroid(evaluateSurface(body.surface, body.x, 0));
    alpha_ = c.follow_smoothing > 0 ? 1 - std::exp(-1 / (scene.fps * c.follow_smoothing)) : 1;
  }
}

void CameraRig::observe(int frame, const SurfaceFrame& followed) {
  if (followed_ < 0) return;
  if (last_frame_ > 0 && frame != last_frame_ + 1)
    throw std::logic_error("CameraRig::observe: frame " + std::to_string(frame) + " after " +
                           std::to_string(last_frame_));
  const Vec3 c = centroid(followed);
  if (last_frame_ == 0 || frame == 1) {
    last_frame_ = frame;
    s1_ = s2_ = c;
    return;
  }
  last_frame_ = frame;
  s1_ += alpha_ * (c - s1_);
  s2_ += alpha_ * (s1_ - s2_);
}

void CameraRig::observe(int frame, const MassSpringSystem& system, const VecX& x) {
  if (followed_ < 0) return;
  const BodySlot& slot = system.bodies()[followed_];
  observe(frame, evaluateSurface(slot.body.surface, x, slot.first));
}

render::CameraParams CameraRig::params() const {
  // Double smoothing: 2 s1 - s2 cancels the lag of a single exponential average at constant velocity.
  const Vec3 shift = followed_ >= 0 && last_frame_ > 0 ? Vec3(2 * s1_ - s2_ - first_) : Vec3::Zero();
  render::CameraParams p;
  p.position = (position_ + shift).cast<float>();
  p.look_at = (look_at_ + shift).cast<float>();
  p.up = up_.cast<float>();
  p.vfov_deg = static_cast<float>(fov_deg_);
  p.width = width_;
  p.height = height_;
  p.aperture = static_cast<float>(aperture_);
  p.focus = static_cast<float>(focus_);
  if (focus_follow_ && followed_ >= 0) {
    // body - position - shift = first_ - position_: the same at every frame and every instant of the shutter.
    const Vec3 body = last_frame_ > 0 ? Vec3(2 * s1_ - s2_) : first_;
    const double along = (body - position_ - shift).dot((look_at_ - position_).normalized());
    p.focus = static_cast<float>(std::max(along, 1e-3));
  }
  return p;
}

}  // namespace wobble
