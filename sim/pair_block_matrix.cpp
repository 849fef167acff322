#include "sim/pair_block_matrix.h"

#include <algorithm>

namespace wobble {

void PairBlockMatrix::reset(const PairSchedule& pattern) {
  pattern_ = &pattern;
  self_.assign(pattern.particles(), 0.0);
  pair_.assign(4 * pattern.size(), 0.0);
}

void PairBlockMatrix::diagonal(std::vector<Sym3>& out, bool parallel) const {
  out.resize(self_.size());
  for (std::size_t p = 0; p < self_.size(); ++p) out[p] = Sym3::identity(self_[p]);
  const int* a = pattern_->a().data();
  const int* b = pattern_->b().data();
  const PairBlockColumns w = columns();
  pattern_->run(parallel, [&](int begin, int end) {
    for (int e = begin; e < end; ++e) {
      const Sym3 m = w.get(e);
      out[a[e]] += m;
      out[b[e]] += m;
    }
  });
}

// The loops take raw pointers first: through the vectors, every store into y would make the compiler reload them.
void PairBlockMatrix::multiplySelf(const VecX& x, VecX& y, int begin, int end) const {
  const double* xs = x.data();
  double* ys = y.data();
  const double* self = self_.data();
  for (int p = begin; p < end; ++p) {
    ys[3 * p] = self[p] * xs[3 * p];
    ys[3 * p + 1] = self[p] * xs[3 * p + 1];
    ys[3 * p + 2] = self[p] * xs[3 * p + 2];
  }
}

namespace {

// The pairs (xa + k, xb + k), k < length, with blocks w (by value, from its first pair on): u = w_k (xa[k] - xb[k]) is
// added to ya[k] and subtracted from yb[k] (which may overlap: all of ya's adds come first). Clones for AVX-512, AVX2
// and the baseline, compiled without FMA contraction (CMakeLists.txt): every clone gives the same bits.
__attribute__((target_clones("avx512f", "avx2", "default"))) void addRunProducts(const PairBlockColumns w,
                                                                                 const double* __restrict xa,
                                                                                 const double* __restrict xb,
                                                                                 int length, double* ya, double* yb) {
  constexpr int kChunk = 128;  // 3 KB a buffer: they stay in L1 between the passes
  alignas(64) double d[3 * kChunk], u[3 * kChunk];
  for (int c = 0; c < length; c += kChunk) {
    const int n = std::min(kChunk, length - c);
    const double *x0 = xa + 3 * c, *x1 = xb + 3 * c;
    for (int j = 0; j < 3 * n; ++j) d[j] = x0[j] - x1[j];
    multiplyBlocks(w.shifted(c), n, d, u);
    double* y0 = ya + 3 * c;
    for (int j = 0; j < 3 * n; ++j) y0[j] += u[j];
    double* y1 = yb + 3 * c;
    for (int j = 0; j < 3 * n; ++j) y1[j] -= u[j];
  }
}

// The same product for pairs [begin, end), one at a time: the short runs.
void addPairProducts(const int* a, const int* b, const PairBlockColumns w, const double* xs, double* ys, int begin,
                     int end) {
  for (int e = begin; e < end; ++e) {  // plain scalars: Eigen's 3-vectors mix packets and scalars here
    const double* xa = xs + 3 * a[e];
    const double* xb = xs + 3 * b[e];
    const double dx = xa[0] - xb[0], dy = xa[1] - xb[1], dz = xa[2] - xb[2];
    const double s = w.v[0][e], wx = w.v[1][e], wy = w.v[2][e], wz = w.v[3][e];
    const double t = wx * dx + wy * dy + wz * dz;  // the same operations as multiplyBlocks (sym3.h)
    const double ux = s * dx + t * wx;
    const double uy = s * dy + t * wy;
    const double uz = s * dz + t * wz;
    double* ya = ys + 3 * a[e];
    double* yb = ys + 3 * b[e];
    ya[0] += ux, ya[1] += uy, ya[2] += uz;
    yb[0] -= ux, yb[1] -= uy, yb[2] -= uz;
  }
}

}  // namespace

void PairBlockMatrix::addPairProducts(const VecX& x, VecX& y, bool parallel) const {
  const int* a = pattern_->a().data();
  const int* b = pattern_->b().data();
  const PairBlockColumns w = columns();
  const double* xs = x.data();
  double* ys = y.data();
  pattern_->runByRuns(parallel, [=](std::span<const PairRun> runs) {
    splitRuns(
        runs,
        [&](const PairRun& run) {
          const int ia = 3 * run.a, ib = 3 * (run.a + run.offset);
          addRunProducts(w.shifted(run.first), xs + ia, xs + ib, run.length, ys + ia, ys + ib);
        },
        [&](int begin, int end) { wobble::addPairProducts(a, b, w, xs, ys, begin, end); });
  });
}

void PairBlockMatrix::multiply(const VecX& x, VecX& y, bool parallel) const {
  y.resize(x.size());
  forEachChunk(pattern_->particles(), parallel, [&](int begin, int end) { multiplySelf(x, y, begin, end); });
  addPairProducts(x, y, parallel);
}

}  // namespace wobble
