// Ray: origin, unit direction and the parametric interval [tnear, tfar] in which hits count.
#pragma once
#include <limits>

#include <Eigen/Core>

namespace wobble::render {

struct Ray {
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();
  Eigen::Vector3f direction = Eigen::Vector3f::UnitZ();  // unit length
  float tnear = 0;
  float tfar = std::numeric_limits<float>::infinity();

  Eigen::Vector3f at(float t) const { return origin + t * direction; }
};

}  // namespace wobble::render
