// Pinhole camera: orthonormal basis from position/look_at/up, the film plane, ray differentials (see camera.h).
#include "render/camera.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace wobble::render {

Camera::Camera(const CameraParams& p) : params_(p) {
  if (p.width <= 0 || p.height <= 0)
    throw std::invalid_argument("camera: resolution must be positive, got " + std::to_string(p.width) + "x" +
                                std::to_string(p.height));
  if (!(p.vfov_deg > 0 && p.vfov_deg < 180))
    throw std::invalid_argument("camera: vertical field of view must be in (0, 180) degrees, got " +
                                std::to_string(p.vfov_deg));
  const Eigen::Vector3f view = p.look_at - p.position;
  if (!view.allFinite() || view.norm() < 1e-12f)
    throw std::invalid_argument("camera: look_at must differ from position");
  forward_ = view.normalized();
  const Eigen::Vector3f side = forward_.cross(p.up);
  if (!side.allFinite() || side.norm() < 1e-6f * p.up.norm() || p.up.norm() == 0)
    throw std::invalid_argument("camera: up must not be parallel to the view direction");
  right_ = side.normalized();
  up_ = right_.cross(forward_);
  if (!(p.aperture >= 0 && std::isfinite(p.aperture)) || !(p.focus >= 0 && std::isfinite(p.focus)))
    throw std::invalid_argument("camera: aperture and focus must be finite and >= 0");
  focus_ = p.focus > 0 ? p.focus : view.norm();
  tan_half_y_ = std::tan(0.5f * p.vfov_deg * std::numbers::pi_v<float> / 180.0f);
  tan_half_x_ = tan_half_y_ * static_cast<float>(p.width) / static_cast<float>(p.height);
  corner_ = forward_ - tan_half_x_ * right_ + tan_half_y_ * up_;
  step_x_ = (2.0f * tan_half_x_ / static_cast<float>(p.width)) * right_;
  step_y_ = (-2.0f * tan_half_y_ / static_cast<float>(p.height)) * up_;
}

Ray Camera::ray(float x, float y, const Eigen::Vector2f& lens) const {
  Ray r = ray(x, y);
  if (params_.aperture <= 0) return r;
  // Shirley and Chiu's concentric map of the square to the disc (area-preserving, low distortion).
  const Eigen::Vector2f o = 2.0f * lens.array() - 1.0f;
  Eigen::Vector2f d = Eigen::Vector2f::Zero();
  if (o.x() != 0 || o.y() != 0) {
    const float quarter = std::numbers::pi_v<float> / 4;
    const bool wide = std::abs(o.x()) > std::abs(o.y());
    const float radius = wide ? o.x() : o.y();
    const float theta = wide ? quarter * (o.y() / o.x()) : 2 * quarter - quarter * (o.x() / o.y());
    d = radius * Eigen::Vector2f(std::cos(theta), std::sin(theta));
  }
  const Eigen::Vector3f focal_point = r.origin + (focus_ / r.direction.dot(forward_)) * r.direction;
  r.origin += params_.aperture * (d.x() * right_ + d.y() * up_);
  r.direction = (focal_point - r.origin).normalized();
  return r;
}

void Camera::differentials(const Eigen::Vector3f& d, Eigen::Vector3f& ddx, Eigen::Vector3f& ddy) const {
  // d = v / |v| with v = forward + sx right + sy up, so |v| = 1 / (d . forward); the derivative of v / |v| along
  // dv is (dv - d (d . dv)) / |v|.
  const float inv_length = d.dot(forward_);
  ddx = (step_x_ - d * d.dot(step_x_)) * inv_length;
  ddy = (step_y_ - d * d.dot(step_y_)) * inv_length;
}

Eigen::Vector2f Camera::screenMotion(const Eigen::Vector3f& p, const Eigen::Vector3f& velocity, float time) const {
  // From the eye at ray time t (camera.h: position - (1 - t) shutter_motion) to the point then.
  const auto film = [&](float t, Eigen::Vector2f& at) {
    const Eigen::Vector3f v = p + (t - time) * velocity - params_.position + (1 - t) * params_.shutter_motion;
    const float z = v.dot(forward_);
    if (!(z > 0)) return false;
    at = Eigen::Vector2f((v.dot(right_) / z + tan_half_x_) / (2 * tan_half_x_) * static_cast<float>(params_.width),
                         (tan_half_y_ - v.dot(up_) / z) / (2 * tan_half_y_) * static_cast<float>(params_.height));
    return true;
  };
  Eigen::Vector2f open, close;
  if (!film(0, open) || !film(1, close)) return Eigen::Vector2f::Zero();
  return close - open;
}

}  // namespace wobble::render
