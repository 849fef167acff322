#include "sim/force_jacobian.h"

#include <algorithm>
#include <cmath>

namespace wobble {
namespace {

// Spring i's unit direction d (from b to a) and transverse share t = max(0, 1 - rest / length) at x; false when its
// endpoints coincide (no direction: no force, no derivative).
bool springGeometry(const Springs& s, std::size_t i, const VecX& x, Vec3& d, double& transverse) {
  const Vec3 delta = particle(x, s.a[i]) - particle(x, s.b[i]);
  const double len = delta.norm();
  if (len == 0.0) return false;
  d = delta / len;
  transverse = std::max(0.0, 1.0 - s.rest[i] / len);
  return true;
}

// Kx = -dFa/dxa = ks (t I + (1 - t) d d^T) (header).
Sym3 stiffnessBlock(double ks, const Vec3& d, double transverse) {
  return ks * ((1.0 - transverse) * Sym3::outer(d) + Sym3::identity(transverse));
}

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
  for (std::size_t i = 0; i < s.size(); ++i) {
    Vec3 d;
    double transverse;
    if (!springGeometry(s, i, x, d, transverse)) continue;
    addPairBlocks(s.a[i], s.b[i], -stiffnessBlock(s.ks[i], d, transverse).dense(), dfdx);
    if (s.kd[i] != 0.0) addPairBlocks(s.a[i], s.b[i], -(s.kd[i] * Sym3::outer(d)).dense(), dfdv);  // Kv = kd d d^T
  }
}

void addDragJacobian(const VecX& drag, Triplets& dfdv) {
  for (Eigen::Index i = 0; i < drag.size(); ++i)
    if (drag[i] != 0.0)
      for (int k = 0; k < 3; ++k) dfdv.emplace_back(3 * i + k, 3 * i + k, -drag[i]);
}

void fillSpringBlocks(const Springs& s, int begin, int end, const VecX& x, double cx, double cv,
                      PairBlockColumns blocks, const VecX* w, VecX* kw) {
  for (int i = begin; i < end; ++i) {
    Vec3 d;
    double transverse;
    if (!springGeometry(s, i, x, d, transverse)) {
      blocks.set(i, 0.0, Vec3::Zero());
      continue;
    }
    blocks.set(i, cx * (s.ks[i] * transverse), std::sqrt(cx * (s.ks[i] * (1.0 - transverse)) + cv * s.kd[i]) * d);
    if (kw) {  // dF/dx w: -Kx (wa - wb) on a, the opposite on b
      const Vec3 u = stiffnessBlock(s.ks[i], d, transverse) * (particle(*w, s.a[i]) - particle(*w, s.b[i]));
      particle(*kw, s.a[i]) -= u;
      particle(*kw, s.b[i]) += u;
    }
  }
}

}  // namespace wobble
