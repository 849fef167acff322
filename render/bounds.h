// Bounds: an axis-aligned box of points, and whether a ray can meet it (the slab test). The Scene keeps each shape's
// bounds, to answer rays that leave a shape and provably miss everything else without asking Embree (scene.h).
#pragma once
#include <limits>

#include <Eigen/Core>

#include "render/ray.h"

namespace wobble::render {

struct Bounds {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(-std::numeric_limits<float>::infinity());

  bool empty() const { return !(lo.array() <= hi.array()).all(); }
  void add(const Eigen::Vector3f& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // Grown on every side by `relative` of its largest coordinate's magnitude (at least of 1): room for the rounding
  // of the points it was built from and of the slab test.
  Bounds padded(float relative) const;
  // False only when the ray misses the box for t in [tnear, tfar] (boxes padded for rounding: see padded()).
  bool mayHit(const Ray& ray) const;
};

}  // namespace wobble::render
