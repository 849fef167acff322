// A symmetric 3x3 block, stored as its six distinct values: the unit of the implicit solver's matrices (a particle's
// diagonal block, a spring's Jacobian block when read out) at two thirds of a full block's memory traffic. The pair
// blocks themselves are stored as a I + w w^T in four values (PairBlockColumns, below).
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
// Kernels read arrays of Sym3 as six doubles a block (pair_block_matrix.cpp, pcg_kernels.h).
static_assert(sizeof(Sym3) == 6 * sizeof(double), "Sym3 is six doubles in a row");

// Many blocks of the form a I + w w^T (a >= 0), stored as four arrays (a, wx, wy, wz), one per value: a loop over
// consecutive blocks reads each value contiguously and vectorises. Every pair block of the implicit solver's matrix
// has this form, since a spring's stiffness and damping act along its direction or equally in all directions
// (force_jacobian.h); four values instead of a Sym3's six cut the memory traffic of the solver's product, which
// streams the pair blocks from cache every CG iteration, by a third. T = float: the matrix's single-precision copy for
// the CG's inner iterations (filtered_pcg.h).
template <class T>
struct BlockColumns {
  T* v[4] = {};
  Sym3 get(std::size_t i) const {
    const double a = v[0][i], x = v[1][i], y = v[2][i], z = v[3][i];
    return {a + x * x, a + y * y, a + z * z, x * y, x * z, y * z};
  }
  void set(std::size_t i, double a, const Vec3& w) const {
    v[0][i] = a, v[1][i] = w.x(), v[2][i] = w.y(), v[3][i] = w.z();
  }
  // The same columns from block `first` on.
  BlockColumns shifted(std::ptrdiff_t first) const {
    BlockColumns from = *this;
    for (T*& column : from.v) column += first;
    return from;
  }
};
using PairBlockColumns = BlockColumns<double>;

// u[k] = (a_k I + w_k w_k^T) d[k] for the first n blocks of b, d and u packed 3-vectors: the product of the matrix's
// run kernel (pair_block_matrix.cpp), inlined into its vectorised loop.
template <class T>
inline void multiplyBlocks(const BlockColumns<T>& b, int n, const T* __restrict d, T* __restrict u) {
  const T* __restrict a = b.v[0];
  const T* __restrict wx = b.v[1];
  const T* __restrict wy = b.v[2];
  const T* __restrict wz = b.v[3];
  for (int k = 0; k < n; ++k) {
    const T dx = d[3 * k], dy = d[3 * k + 1], dz = d[3 * k + 2];
    const T t = wx[k] * dx + wy[k] * dy + wz[k] * dz;
    u[3 * k] = a[k] * dx + t * wx[k];
    u[3 * k + 1] = a[k] * dy + t * wy[k];
    u[3 * k + 2] = a[k] * dz + t * wz[k];
  }
}

}  // namespace wobble
