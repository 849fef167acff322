// A symmetric 3x3 block, stored as its six distinct values: the unit of the implicit solver's matrices (a spring's
// Jacobian block, a particle's diagonal block) at two thirds of a full block's memory traffic.
#pragma once
#include <cstddef>

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
  // The same columns from block `first` on.
  Sym3Columns shifted(std::ptrdiff_t first) const {
    Sym3Columns from = *this;
    for (double*& column : from.v) column += first;
    return from;
  }
};

// u[k] = W_k d[k] for the first n blocks of w, d and u packed 3-vectors: the product of the run kernels
// (spring_runs.cpp, pair_block_matrix.cpp), inlined into their vectorised loops.
inline void multiplyBlocks(const Sym3Columns& w, int n, const double* __restrict d, double* __restrict u) {
  const double* __restrict xx = w.v[0];
  const double* __restrict yy = w.v[1];
  const double* __restrict zz = w.v[2];
  const double* __restrict xy = w.v[3];
  const double* __restrict xz = w.v[4];
  const double* __restrict yz = w.v[5];
  for (int k = 0; k < n; ++k) {
    const double dx = d[3 * k], dy = d[3 * k + 1], dz = d[3 * k + 2];
    u[3 * k] = xx[k] * dx + xy[k] * dy + xz[k] * dz;
    u[3 * k + 1] = xy[k] * dx + yy[k] * dy + yz[k] * dz;
    u[3 * k + 2] = xz[k] * dx + yz[k] * dy + zz[k] * dz;
  }
}

}  // namespace wobble
