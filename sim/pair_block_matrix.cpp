#include "sim/pair_block_matrix.h"

namespace wobble {

void PairBlockMatrix::reset(const PairSchedule& pattern) {
  pattern_ = &pattern;
  self_.assign(pattern.particles(), Sym3{});
  pair_.assign(pattern.size(), Sym3{});
}

void PairBlockMatrix::diagonal(std::vector<Sym3>& out, bool parallel) const {
  out = self_;
  const int* a = pattern_->a().data();
  const int* b = pattern_->b().data();
  pattern_->run(parallel, [&](int begin, int end) {
    for (int e = begin; e < end; ++e) {
      out[a[e]] += pair_[e];
      out[b[e]] += pair_[e];
    }
  });
}

// The loops take raw pointers first: through the vectors, every store into y would make the compiler reload them.
void PairBlockMatrix::multiplySelf(const VecX& x, VecX& y, int begin, int end) const {
  const double* xs = x.data();
  double* ys = y.data();
  const Sym3* self = self_.data();
  for (int p = begin; p < end; ++p) Vec3::Map(ys + 3 * p) = self[p] * Vec3::Map(xs + 3 * p);
}

void PairBlockMatrix::addPairProducts(const VecX& x, VecX& y, bool parallel) const {
  const int* a = pattern_->a().data();
  const int* b = pattern_->b().data();
  const Sym3* w = pair_.data();
  const double* xs = x.data();
  double* ys = y.data();
  pattern_->run(parallel, [=](int begin, int end) {
    for (int e = begin; e < end; ++e) {  // plain scalars: Eigen's 3-vectors mix packets and scalars here
      const double* xa = xs + 3 * a[e];
      const double* xb = xs + 3 * b[e];
      const double dx = xa[0] - xb[0], dy = xa[1] - xb[1], dz = xa[2] - xb[2];
      const Sym3& m = w[e];
      const double ux = m.xx * dx + m.xy * dy + m.xz * dz;
      const double uy = m.xy * dx + m.yy * dy + m.yz * dz;
      const double uz = m.xz * dx + m.yz * dy + m.zz * dz;
      double* ya = ys + 3 * a[e];
      double* yb = ys + 3 * b[e];
      ya[0] += ux, ya[1] += uy, ya[2] += uz;
      yb[0] -= ux, yb[1] -= uy, yb[2] -= uz;
    }
  });
}

void PairBlockMatrix::multiply(const VecX& x, VecX& y, bool parallel) const {
  y.resize(x.size());
  forEachChunk(pattern_->particles(), parallel, [&](int begin, int end) { multiplySelf(x, y, begin, end); });
  addPairProducts(x, y, parallel);
}

}  // namespace wobble
