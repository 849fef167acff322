// Ray: origin, unit direction, the parametric interval [tnear, tfar] in which hits count, and the instant it is
// traced at: time in [0, 1] across the shutter, 0 at its opening (motion blur, scene.h; 0 when nothing moves).
#pragma once
#include <limits>

#include <Eigen/Core>

namespace wobble::render {

struct Ray {
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();
  Eigen::Vector3f direction = Eigen::Vector3f::UnitZ();  // unit length
  float tnear = 0;
  float tfar = std::numeric_limits<float>::infinity();
  float time = 0;

  Eigen::Vector3f at(float t) const { return origin + t * direction; }
};

}  // namespace wobble::render
