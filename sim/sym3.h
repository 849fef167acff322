// A symmetric 3x3 block, stored as its six distinct values: the unit of the implicit solver's matrices (a spring's
// Jacobian block, a particle's diagonal block) at two thirds of a full block's memory traffic.
#pragma once
#include "sim/types.h"

namespace wobble {

struct Sym3 {
  double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;

  static Sym3 identity(double s) { return {s, s, s, 0, 0, 0}; }
  static Sym3 outer(const Vec3& d) {  // d d^T
    return {d.x() * d.x(), d.y() * d.y(), d.z() * d.z(), d.x() * d.y(), d.x() * d.z(), d.y() * d.z()};
  }
  static Sym3 fromDense(const Eigen::Matrix3d& m) { return {m(0, 0), m(1, 1), m(2, 2), m(0, 1), m(0, 2), m(1, 2)}; }
  Eigen::Matrix3d dense() const {
    Eigen::Matrix3d m;
    m << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    return m;
  }
  Vec3 operator*(const Vec3& v) const {
    return {xx * v.x() + xy * v.y() + xz * v.z(), xy * v.x() + yy * v.y() + yz * v.z(),
            xz * v.x() + yz * v.y() + zz * v.z()};
  }
  Sym3& operator+=(const Sym3& o) {
    xx += o.xx, yy += o.yy, zz += o.zz, xy += o.xy, xz += o.xz, yz += o.yz;
    return *this;
  }
  friend Sym3 operator*(double s, const Sym3& m) {
    return {s * m.xx, s * m.yy, s * m.zz, s * m.xy, s * m.xz, s * m.yz};
  }
  friend Sym3 operator+(Sym3 a, const Sym3& b) { return a += b; }
};

// Many Sym3 stored as six arrays, one per value (xx, yy, zz, xy, xz, yz): a loop over consecutive blocks reads each
// value contiguously, which vectorises (an array of Sym3 would be read with a stride of six).
struct Sym3Columns {
  double* v[6] = {};
  Sym3 get(std::size_t i) const { return {v[0][i], v[1][i], v[2][i], v[3][i], v[4][i], v[5][i]}; }
  void set(std::size_t i, const Sym3& m) const {
    v[0][i] = m.xx, v[1][i] = m.yy, v[2][i] = m.zz, v[3][i] = m.xy, v[4][i] = m.xz, v[5][i] = m.yz;
  }
};

}  // namespace wobble
