#include "app/run/shutter.h"

#include <algorithm>

namespace wobble {

std::vector<double> shutterTimes(const SceneFile& scene, int frame) {
  const double t = scene.frameTime(frame), shutter = scene.render.camera.shutter;
  if (shutter <= 0 || frame <= 1) return {t};
  const double open = shutter * (t - scene.frameTime(frame - 1));
  std::vector<double> times;
  for (int j = 0; j < kShutterPoses; ++j)
    times.push_back(j == kShutterPoses - 1 ? t : t - open * double(kShutterPoses - 1 - j) / (kShutterPoses - 1));
  return times;
}

Eigen::Vector3f shutterMotion(const SceneFile& scene, const Eigen::Vector3f& before, const Eigen::Vector3f& at) {
  return float(scene.render.camera.shutter) * (at - before);
}

ShutterRecorder::ShutterRecorder(const SceneFile& scene, const VecX& x0) : scene_(scene), x_prev_(x0) {}

void ShutterRecorder::begin(int frame) {
  times_ = shutterTimes(scene_, frame);
  states_.assign(times_.size(), VecX());
  filled_.assign(times_.size(), 0);
  // Instants at or before the last step's end (a full shutter opens at the previous frame): its state.
  for (std::size_t j = 0; j < times_.size(); ++j)
    if (times_[j] <= t_prev_) states_[j] = x_prev_, filled_[j] = 1;
}

void ShutterRecorder::step(double t, const VecX& x) {
  for (std::size_t j = 0; j < times_.size(); ++j)
    if (!filled_[j] && times_[j] <= t) {
      const double w = t > t_prev_ ? std::clamp((times_[j] - t_prev_) / (t - t_prev_), 0.0, 1.0) : 1.0;
      states_[j] = (1 - w) * x_prev_ + w * x;
      filled_[j] = 1;
    }
  t_prev_ = t;
  x_prev_ = x;
}

std::vector<VecX> ShutterRecorder::states(const VecX& x) const {
  std::vector<VecX> states = states_;
  for (std::size_t j = 0; j < states.size(); ++j)
    if (!filled_[j] || j + 1 == states.size()) states[j] = x;  // the frame itself, exactly
  return states;
}

std::vector<std::vector<SurfaceFrame>> surfacesOf(const SceneFile& scene, std::span<const VecX> states) {
  std::vector<std::vector<SurfaceFrame>> poses;
  for (const VecX& x : states) {
    poses.emplace_back();
    for (const BodySlot& slot : scene.system->bodies())
      poses.back().push_back(evaluateSurface(slot.body.surface, x, slot.first));
  }
  return poses;
}

std::vector<std::vector<SurfaceFrame>> blendSurfaces(const SceneFile& scene, int frame,
                                                     std::span<const SurfaceFrame> before,
                                                     std::span<const SurfaceFrame> after) {
  const std::vector<double> times = shutterTimes(scene, frame);
  const double t0 = scene.frameTime(frame - 1), t1 = scene.frameTime(frame);
  std::vector<std::vector<SurfaceFrame>> poses;
  for (std::size_t j = 0; j < times.size(); ++j) {
    if (j + 1 == times.size()) {
      poses.emplace_back(after.begin(), after.end());
      break;
    }
    const float w = static_cast<float>((times[j] - t0) / (t1 - t0));
    std::vector<SurfaceFrame> pose(after.size());
    for (std::size_t b = 0; b < after.size(); ++b) {
      const SurfaceFrame &a = before[b], &c = after[b];
      pose[b].positions.resize(c.positions.size());
      for (std::size_t i = 0; i < c.positions.size(); ++i)
        pose[b].positions[i] = (1 - w) * a.positions[i] + w * c.positions[i];
      pose[b].normals.resize(c.normals.size());
      for (std::size_t i = 0; i < c.normals.size(); ++i) {
        const Eigen::Vector3f n = (1 - w) * a.normals[i] + w * c.normals[i];
        pose[b].normals[i] = n.norm() > 0 ? Eigen::Vector3f(n.normalized()) : c.normals[i];
      }
    }
    poses.push_back(std::move(pose));
  }
  return poses;
}

}  // namespace wobble
