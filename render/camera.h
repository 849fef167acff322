// Camera: a pinhole camera.
//
// Parameters (CameraParams):
//   position   eye point (world space)
//   look_at    point the optical axis passes through (must differ from position)
//   up         approximate up direction (not parallel to the view direction); the image's up is its part
//              orthogonal to the view direction
//   vfov_deg   vertical field of view in degrees, in (0, 180); the horizontal one follows from the aspect ratio
//   width, height   resolution in pixels (> 0)
//   aperture   lens radius (scene units, >= 0): 0 is a pinhole, everything sharp; larger blurs what is off the focus
//              plane (a thin lens, as pbrt's PerspectiveCamera: a point at depth z is spread over a disc of radius
//              aperture |1/focus - 1/z| on the film plane at distance 1)
//   focus      distance along the optical axis of the plane in focus (> 0); 0 = the look_at point's
//   shutter_motion  how far the eye moves while the shutter is open (motion blur, scene.h): `position` is where it is
//              at the shutter's closing (ray time 1), position - shutter_motion at its opening (time 0), in a straight
//              line between; the view turns no way (a follow camera only translates, camera_rig.h)
// Film coordinates: x to the right in [0, width], y downwards in [0, height]; pixel (i, j) covers
// [i, i+1] x [j, j+1], so its centre is (i + 0.5, j + 0.5).
#pragma once
#include <cmath>

#include <Eigen/Core>

#include "render/ray.h"

namespace wobble::render {

struct CameraParams {
  Eigen::Vector3f position{0, 2, 10};
  Eigen::Vector3f look_at{0, 0, 0};
  Eigen::Vector3f up{0, 1, 0};
  float vfov_deg = 40;
  int width = 640, height = 360;
  float aperture = 0, focus = 0;
  Eigen::Vector3f shutter_motion = Eigen::Vector3f::Zero();
};

class Camera {
 public:
  // Throws std::invalid_argument on a degenerate view or resolution.
  explicit Camera(const CameraParams& params);

  // Primary ray through film point (x, y) in pixels; unit direction, starting at the eye. Inline: one per sample.
  Ray ray(float x, float y) const {
    Ray r;
    r.origin = params_.position;
    r.direction = (corner_ + x * step_x_ + y * step_y_).normalized();
    return r;
  }

  // The same through the thin lens, at lens point u in [0, 1)^2 (concentric disc mapping); the pinhole's ray when
  // aperture is 0.
  Ray ray(float x, float y, const Eigen::Vector2f& lens) const;
  bool hasLens() const { return params_.aperture > 0; }
  // The ray traced at instant `time` in [0, 1] of the shutter: the eye moved back by (1 - time) shutter_motion.
  Ray atTime(Ray r, float time) const {
    r.origin -= (1 - time) * params_.shutter_motion;
    r.time = time;
    return r;
  }
  float focusDistance() const { return focus_; }

  // How the unit direction of the primary ray with unit direction d turns per pixel to the right (ddx) and down (ddy):
  // its ray differentials (the origin does not move: a pinhole), for texture filtering.
  void differentials(const Eigen::Vector3f& d, Eigen::Vector3f& ddx, Eigen::Vector3f& ddy) const;

  // Distance of p from the eye along the optical axis (the EXR depth channel).
  float depth(const Eigen::Vector3f& p) const { return (p - params_.position).dot(forward_); }
  // The radius in pixels of the disc a point at this depth (infinite: the sky) is spread over by the lens (its circle
  // of confusion, aperture |1/focus - 1/depth| on the film at distance 1); 0 for a pinhole.
  float blurRadius(float depth) const {
    const float inv = depth > 0 && std::isfinite(depth) ? 1.0f / depth : 0.0f;
    return params_.aperture * std::abs(1.0f / focus_ - inv) * static_cast<float>(params_.height) / (2 * tan_half_y_);
  }

  // How far, in pixels (x right, y down), the image of a point moves while the shutter is open: the point p, seen at
  // ray time `time`, moving by `velocity` per unit of ray time (SurfaceHit::dpdt), and the eye by shutter_motion.
  // Zero where the point is behind the eye at either end.
  Eigen::Vector2f screenMotion(const Eigen::Vector3f& p, const Eigen::Vector3f& velocity, float time) const;

  const CameraParams& params() const { return params_; }
  int width() const { return params_.width; }
  int height() const { return params_.height; }
  const Eigen::Vector3f& forward() const { return forward_; }
  const Eigen::Vector3f& right() const { return right_; }
  const Eigen::Vector3f& up() const { return up_; }

 private:
  CameraParams params_;
  Eigen::Vector3f forward_, right_, up_;  // orthonormal, right-handed: right = forward x up
  float tan_half_y_, tan_half_x_;
  float focus_ = 1;
  // The film plane at distance 1: its top-left corner and one pixel's step to the right and down.
  Eigen::Vector3f corner_, step_x_, step_y_;
};

}  // namespace wobble::render
