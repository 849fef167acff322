#include "sim/solver/pair_block_matrix.h"

#include <algorithm>

namespace wobble {

void PairBlockMatrix::reset(const PairSchedule& pattern) {
  pattern_ = &pattern;
  self_.assign(pattern.particles(), 0.0);
  pair_.assign(4 * pattern.size(), 0.0);
}

namespace {

// The pairs (a0 + k, b0 + k), k < length, with blocks w (from its first pair on): each block a I + w w^T added to both
// particles' diagonal blocks, as Sym3's six values in a row (da, db: the first particles' blocks; they may overlap:
// all of da's adds come first). Computed a chunk at a time into a buffer, then added in two plain loops, as the
// product below. The same clones and bits rule.
__attribute__((target_clones("avx512f", "avx2", "default"))) void addRunDiagonal(const PairBlockColumns w, int length,
                                                                                 double* da, double* db) {
  constexpr int kChunk = 128;
  alignas(64) double m[6 * kChunk];
  for (int c = 0; c < length; c += kChunk) {
    const int n = std::min(kChunk, length - c);
    const double* __restrict a = w.v[0] + c;
    const double* __restrict wx = w.v[1] + c;
    const double* __restrict wy = w.v[2] + c;
    const double* __restrict wz = w.v[3] + c;
    for (int k = 0; k < n; ++k) {  // Sym3's order: xx, yy, zz, xy, xz, yz (the values of BlockColumns::get)
      m[6 * k] = a[k] + wx[k] * wx[k];
      m[6 * k + 1] = a[k] + wy[k] * wy[k];
      m[6 * k + 2] = a[k] + wz[k] * wz[k];
      m[6 * k + 3] = wx[k] * wy[k];
      m[6 * k + 4] = wx[k] * wz[k];
      m[6 * k + 5] = wy[k] * wz[k];
    }
    double* y0 = da + 6 * c;
    for (int j = 0; j < 6 * n; ++j) y0[j] += m[j];
    double* y1 = db + 6 * c;
    for (int j = 0; j < 6 * n; ++j) y1[j] += m[j];
  }
}

}  // namespace

void PairBlockMatrix::diagonal(std::vector<Sym3>& out, bool parallel) const {
  out.resize(self_.size());
  const int* a = pattern_->a().data();
  const int* b = pattern_->b().data();
  const PairBlockColumns w = columns();
  double* blocks = &out.data()->xx;  // Sym3s as six doubles each
  const auto addPairs = [&](std::span<const PairRun> runs) {
    splitRuns(
        runs,
        [&](const PairRun& run) {
          addRunDiagonal(w.shifted(run.first), run.length, blocks + 6 * run.a, blocks + 6 * (run.a + run.offset));
        },
        [&](int begin, int end) {
          for (int e = begin; e < end; ++e) {
            const Sym3 m = w.get(e);
            out[a[e]] += m;
            out[b[e]] += m;
          }
        });
  };
  // One pass: each block's self part, then its pairs; then the pairs between blocks.
  pattern_->runByBlocks(
      parallel,
      [&](int begin, int end, std::span<const PairRun> runs) {
        for (int p = begin; p < end; ++p) out[p] = Sym3::identity(self_[p]);
        addPairs(runs);
      },
      addPairs);
  for (const StencilBlock& b : stencils_) {
    const WeightedStencil& s = b.stencil;
    for (int i = 0; i < s.size; ++i)
      if (s.w[i] != 0) out[s.particle[i]] += (s.w[i] * s.w[i]) * b.block;
  }
}

namespace {

// y = self x on particles [begin, end). Raw pointers: through the vectors, every store into y would make the compiler
// reload them.
template <class T>
void multiplySelfOf(const T* self, const T* x, T* y, int begin, int end) {
  for (int p = begin; p < end; ++p) {
    y[3 * p] = self[p] * x[3 * p];
    y[3 * p + 1] = self[p] * x[3 * p + 1];
    y[3 * p + 2] = self[p] * x[3 * p + 2];
  }
}

// The pairs (xa + k, xb + k), k < length, with blocks w (by value, from its first pair on): u = w_k (xa[k] - xb[k]) is
// added to ya[k] and subtracted from yb[k] (which may overlap: all of ya's adds come first). Clones for AVX-512, AVX2
// and the baseline, compiled without FMA contraction (CMakeLists.txt): every clone gives the same bits.
template <class T>
__attribute__((target_clones("avx512f", "avx2", "default"))) void addRunProducts(const BlockColumns<T> w,
                                                                                 const T* __restrict xa,
                                                                                 const T* __restrict xb, int length,
                                                                                 T* ya, T* yb) {
  constexpr int kChunk = 128;  // at most 3 KB a buffer: they stay in L1 between the passes
  alignas(64) T d[3 * kChunk], u[3 * kChunk];
  for (int c = 0; c < length; c += kChunk) {
    const int n = std::min(kChunk, length - c);
    const T *x0 = xa + 3 * c, *x1 = xb + 3 * c;
    for (int j = 0; j < 3 * n; ++j) d[j] = x0[j] - x1[j];
    multiplyBlocks(w.shifted(c), n, d, u);
    T* y0 = ya + 3 * c;
    for (int j = 0; j < 3 * n; ++j) y0[j] += u[j];
    T* y1 = yb + 3 * c;
    for (int j = 0; j < 3 * n; ++j) y1[j] -= u[j];
  }
}

// The same product for pairs [begin, end), one at a time: the short runs.
template <class T>
void addPairProducts(const int* a, const int* b, const BlockColumns<T> w, const T* xs, T* ys, int begin, int end) {
  for (int e = begin; e < end; ++e) {  // plain scalars: Eigen's 3-vectors mix packets and scalars here
    const T* xa = xs + 3 * a[e];
    const T* xb = xs + 3 * b[e];
    const T dx = xa[0] - xb[0], dy = xa[1] - xb[1], dz = xa[2] - xb[2];
    const T s = w.v[0][e], wx = w.v[1][e], wy = w.v[2][e], wz = w.v[3][e];
    const T t = wx * dx + wy * dy + wz * dz;  // the same operations as multiplyBlocks (sym3.h)
    const T ux = s * dx + t * wx;
    const T uy = s * dy + t * wy;
    const T uz = s * dz + t * wz;
    T* ya = ys + 3 * a[e];
    T* yb = ys + 3 * b[e];
    ya[0] += ux, ya[1] += uy, ya[2] += uz;
    yb[0] -= ux, yb[1] -= uy, yb[2] -= uz;
  }
}

// y += the pair blocks' part of A x over a task's runs: long runs by the vectorised kernel, the rest pair by pair.
template <class T>
void addTaskProducts(const PairSchedule& pattern, const BlockColumns<T> w, const T* xs, T* ys,
                     std::span<const PairRun> runs) {
  const int* a = pattern.a().data();
  const int* b = pattern.b().data();
  splitRuns(
      runs,
      [&](const PairRun& run) {
        const int ia = 3 * run.a, ib = 3 * (run.a + run.offset);
        addRunProducts(w.shifted(run.first), xs + ia, xs + ib, run.length, ys + ia, ys + ib);
      },
      [&](int begin, int end) { addPairProducts(a, b, w, xs, ys, begin, end); });
}

// y += the stencils' part of A x: u = B sum_j w_j x_j, y_i += w_i u (in double, rounded into T).
template <class T>
void addStencilProductsOf(const std::vector<StencilBlock>& stencils, const T* x, T* y) {
  for (const StencilBlock& b : stencils) {
    const WeightedStencil& s = b.stencil;
    Vec3 d = Vec3::Zero();
    for (int j = 0; j < s.size; ++j)
      if (s.w[j] != 0) d += s.w[j] * Vec3(x[3 * s.particle[j]], x[3 * s.particle[j] + 1], x[3 * s.particle[j] + 2]);
    const Vec3 u = b.block * d;
    for (int i = 0; i < s.size; ++i)
      if (s.w[i] != 0)
        for (int k = 0; k < 3; ++k) y[3 * s.particle[i] + k] += T(s.w[i] * u[k]);
  }
}

}  // namespace

void PairBlockMatrix::addStencilProducts(const double* x, double* y) const { addStencilProductsOf(stencils_, x, y); }

void SinglePairBlockMatrix::addStencilProducts(const float* x, float* y) const {
  if (stencils_) addStencilProductsOf(*stencils_, x, y);
}

void PairBlockMatrix::multiplySelf(const double* x, double* y, int begin, int end) const {
  multiplySelfOf(self_.data(), x, y, begin, end);
}

void PairBlockMatrix::addPairProducts(const double* x, double* y, std::span<const PairRun> runs) const {
  addTaskProducts(*pattern_, columns(), x, y, runs);
}

void PairBlockMatrix::multiply(const VecX& x, VecX& y, bool parallel) const {
  y.resize(x.size());
  multiplyFused(*this, x.data(), y.data(), parallel, [](int, int) {});
}

void SinglePairBlockMatrix::reserve(const PairBlockMatrix& a) {
  self_.resize(a.self_.size());
  pair_.resize(a.pair_.size());
}

void SinglePairBlockMatrix::assign(const PairBlockMatrix& a, bool parallel) {
  pattern_ = a.pattern_;
  stencils_ = &a.stencils_;
  reserve(a);
  const int n = static_cast<int>(self_.size());
  const std::size_t pairs = pair_.size() / 4;
  forEachChunk(n, parallel, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) self_[p] = static_cast<float>(a.self_[p]);
    // The pair values in the same share: pairs [pairs * begin / n, pairs * end / n) of each column.
    const std::size_t first = pairs * begin / n, last = pairs * end / n;
    for (std::size_t c = 0; c < 4; ++c)
      for (std::size_t e = first; e < last; ++e) pair_[c * pairs + e] = static_cast<float>(a.pair_[c * pairs + e]);
  });
}

void SinglePairBlockMatrix::multiplySelf(const float* x, float* y, int begin, int end) const {
  multiplySelfOf(self_.data(), x, y, begin, end);
}

void SinglePairBlockMatrix::addPairProducts(const float* x, float* y, std::span<const PairRun> runs) const {
  float* data = const_cast<float*>(pair_.data());
  const std::size_t n = pair_.size() / 4;
  addTaskProducts(*pattern_, BlockColumns<float>{{data, data + n, data + 2 * n, data + 3 * n}}, x, y, runs);
}

}  // namespace wobble
