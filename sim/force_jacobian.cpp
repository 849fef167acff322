#include "force_jacobian.h"

#include <algorithm>

namespace wobble {
namespace {

// The four 3x3 blocks of one spring: +B on (a, a) and (b, b), -B on (a, b) and (b, a).
void addPairBlocks(int a, int b, const Eigen::Matrix3d& block, Triplets& out) {
  const int ra = 3 * a, rb = 3 * b;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const double value = block(r, c);
      out.emplace_back(ra + r, ra + c, value);
      out.emplace_back(rb + r, rb + c, value);
      out.emplace_back(ra + r, rb + c, -value);
      out.emplace_back(rb + r, ra + c, -value);
    }
}

}  // namespace

void addSpringJacobians(const Springs& s, const VecX& x, Triplets& dfdx, Triplets& dfdv) {
  const std::size_t n = s.size();
  for (std::size_t i = 0; i < n; ++i) {
    const int a = s.a[i], b = s.b[i];
    const Vec3 delta = particle(x, a) - particle(x, b);
    const double len = delta.norm();
    if (len == 0.0) continue;  // as in addSpringForces: no direction, no force, no derivative
    const Vec3 d = delta / len;
    const Eigen::Matrix3d ddt = d * d.transpose();
    const double transverse = std::max(0.0, 1.0 - s.rest[i] / len);
    addPairBlocks(a, b, -s.ks[i] * (ddt + transverse * (Eigen::Matrix3d::Identity() - ddt)), dfdx);
    if (s.kd[i] != 0.0) addPairBlocks(a, b, -s.kd[i] * ddt, dfdv);
  }
}

void addDragJacobian(const VecX& drag, Triplets& dfdv) {
  for (Eigen::Index i = 0; i < drag.size(); ++i)
    if (drag[i] != 0.0)
      for (int k = 0; k < 3; ++k) dfdv.emplace_back(3 * i + k, 3 * i + k, -drag[i]);
}

}  // namespace wobble
