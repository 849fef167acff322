// Padding and the slab test of an axis-aligned box (see bounds.h).
#include "render/bounds.h"

#include <algorithm>

namespace wobble::render {

Bounds padded(const Bounds& box, float relative) {
  if (box.isEmpty()) return box;
  const float scale = std::max({1.0f, box.min().cwiseAbs().maxCoeff(), box.max().cwiseAbs().maxCoeff()});
  const Eigen::Vector3f pad = Eigen::Vector3f::Constant(relative * scale);
  return Bounds(box.min() - pad, box.max() + pad);
}

bool mayHit(const Bounds& box, const Ray& ray) {
  if (box.isEmpty()) return false;
  const Eigen::Vector3f &lo = box.min(), &hi = box.max();
  float t0 = ray.tnear, t1 = ray.tfar;
  for (int a = 0; a < 3; ++a) {
    if (ray.direction[a] == 0) {  // parallel to this slab's planes: within it everywhere or nowhere
      if (ray.origin[a] < lo[a] || ray.origin[a] > hi[a]) return false;
      continue;
    }
    const float inv = 1.0f / ray.direction[a];
    float near = (lo[a] - ray.origin[a]) * inv, far = (hi[a] - ray.origin[a]) * inv;
    if (near > far) std::swap(near, far);
    if (near > t0) t0 = near;
    if (far < t1) t1 = far;
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace wobble::render
