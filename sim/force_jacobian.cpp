#include "sim/force_jacobian.h"

#include <algorithm>

namespace wobble {
namespace {

// The stiffness and damping blocks of spring i at x, Kx = -dFa/dxa and Kv = -dFa/dva (header); false when its
// endpoints coincide (no direction: no force, no derivative).
bool springBlocks(const Springs& s, std::size_t i, const VecX& x, Sym3& kx, Sym3& kv) {
  const Vec3 delta = particle(x, s.a[i]) - particle(x, s.b[i]);
  const double len = delta.norm();
  if (len == 0.0) return false;
  const Sym3 ddt = Sym3::outer(delta / len);
  const double transverse = std::max(0.0, 1.0 - s.rest[i] / len);
  kx = s.ks[i] * ((1.0 - transverse) * ddt + Sym3::identity(transverse));
  kv = s.kd[i] * ddt;
  return true;
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
    Sym3 kx, kv;
    if (!springBlocks(s, i, x, kx, kv)) continue;
    addPairBlocks(s.a[i], s.b[i], -kx.dense(), dfdx);
    if (s.kd[i] != 0.0) addPairBlocks(s.a[i], s.b[i], -kv.dense(), dfdv);
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
    Sym3 kx, kv;
    if (!springBlocks(s, i, x, kx, kv)) {
      blocks.set(i, 0.0, Vec3::Zero());
      continue;
    }
    const Vec3 delta = particle(x, s.a[i]) - particle(x, s.b[i]);
    const double len = delta.norm();
    const double transverse = std::max(0.0, 1.0 - s.rest[i] / len);
    blocks.set(i, cx * (s.ks[i] * transverse),
               std::sqrt(cx * (s.ks[i] * (1.0 - transverse)) + cv * s.kd[i]) * (delta / len));
    if (kw) {  // dF/dx w: -Kx (wa - wb) on a, the opposite on b
      const Vec3 u = kx * (particle(*w, s.a[i]) - particle(*w, s.b[i]));
      particle(*kw, s.a[i]) -= u;
      particle(*kw, s.b[i]) += u;
    }
  }
}

}  // namespace wobble
