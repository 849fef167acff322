#include "sim/solver/pair_block_matrix.h"

#include <algorithm>
#include <type_traits>

#include "sim/solver/parallel.h"

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
  for (const StencilBlock& coupling : stencils_) {
    const WeightedStencil& s = coupling.stencil;
    for (int i = 0; i < s.size; ++i)
      if (s.w[i] != 0) out[s.particle[i]] += (s.w[i] * s.w[i]) * coupling.block;
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

}  // namespace

// Stencils below this many are multiplied on one thread: a product's two passes cost a few microseconds of
// scheduling each, more than a few hundred stencils' work.
constexpr int kParallelStencils = 1024;

void StencilCouplings::index() const {
  int particles = 0;
  std::size_t entries = 0;
  for (const StencilBlock& b : blocks_)
    for (int i = 0; i < b.stencil.size; ++i)
      if (b.stencil.w[i] != 0) particles = std::max(particles, b.stencil.particle[i] + 1), ++entries;
  // Counting sort by particle: each particle's entries keep the stencils' order.
  std::vector<int> count(particles + 1, 0);
  for (const StencilBlock& b : blocks_)
    for (int i = 0; i < b.stencil.size; ++i)
      if (b.stencil.w[i] != 0) ++count[b.stencil.particle[i] + 1];
  touched_.clear();
  first_.assign(1, 0);
  std::vector<int> row(particles, -1);
  for (int p = 0; p < particles; ++p)
    if (count[p + 1] > 0) {
      row[p] = int(touched_.size());
      touched_.push_back(p);
      first_.push_back(first_.back() + count[p + 1]);
    }
  entry_stencil_.resize(entries);
  double_.entry_weight.resize(entries);
  std::vector<int> next(first_.begin(), first_.end() - 1);
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    const WeightedStencil& s = blocks_[k].stencil;
    for (int i = 0; i < s.size; ++i)
      if (s.w[i] != 0) {
        const int e = next[row[s.particle[i]]]++;
        entry_stencil_[e] = int(k);
        double_.entry_weight[e] = s.w[i];
      }
  }
  packed_first_.assign(1, 0);
  packed_particle_.clear();
  double_.packed_weight.clear();
  double_.packed_block.clear();
  for (const StencilBlock& b : blocks_) {
    const Sym3& m = b.block;
    double_.packed_block.insert(double_.packed_block.end(), {m.xx, m.yy, m.zz, m.xy, m.xz, m.yz});
    for (int i = 0; i < b.stencil.size; ++i)
      if (b.stencil.w[i] != 0) {
        packed_particle_.push_back(b.stencil.particle[i]);
        double_.packed_weight.push_back(b.stencil.w[i]);
      }
    packed_first_.push_back(int(packed_particle_.size()));
  }
  double_.u.resize(3 * blocks_.size());
  single_.entry_weight.assign(double_.entry_weight.begin(), double_.entry_weight.end());
  single_.packed_weight.assign(double_.packed_weight.begin(), double_.packed_weight.end());
  single_.packed_block.assign(double_.packed_block.begin(), double_.packed_block.end());
  single_.u.resize(3 * blocks_.size());
  indexed_ = true;
}

template <class S>
void StencilCouplings::products(Values<S>& v, const S* x, S* y, bool parallel) const {
  const int stencils = int(blocks_.size()), rows = int(touched_.size());
  S* u_all = v.u.data();
  forEachChunk(stencils, parallel, [&](int begin, int end) {
    for (int k = begin; k < end; ++k) {
      S d0 = 0, d1 = 0, d2 = 0;
      for (int j = packed_first_[k]; j < packed_first_[k + 1]; ++j) {
        const S* xj = x + 3 * packed_particle_[j];
        const S w = v.packed_weight[j];
        d0 += w * xj[0], d1 += w * xj[1], d2 += w * xj[2];
      }
      const S* b = &v.packed_block[6 * k];  // xx, yy, zz, xy, xz, yz
      S* u = u_all + 3 * k;
      u[0] = b[0] * d0 + b[3] * d1 + b[4] * d2;
      u[1] = b[3] * d0 + b[1] * d1 + b[5] * d2;
      u[2] = b[4] * d0 + b[5] * d1 + b[2] * d2;
    }
  });
  forEachChunk(rows, parallel, [&](int begin, int end) {
    for (int r = begin; r < end; ++r) {
      S* yp = y + 3 * touched_[r];
      for (int e = first_[r]; e < first_[r + 1]; ++e) {
        const S w = v.entry_weight[e];
        const S* u = u_all + 3 * entry_stencil_[e];
        yp[0] += w * u[0], yp[1] += w * u[1], yp[2] += w * u[2];
      }
    }
  });
}

template <class T>
void StencilCouplings::addProducts(const T* x, T* y, bool parallel) const {
  if (blocks_.empty()) return;
  if (!indexed_) index();
  // Threads pay only for many stencils; the bytes are the same either way.
  parallel = parallel && int(blocks_.size()) >= kParallelStencils;
  if constexpr (std::is_same_v<T, float>) products(single_, x, y, parallel);
  else products(double_, x, y, parallel);
}

template void StencilCouplings::addProducts<double>(const double*, double*, bool) const;
template void StencilCouplings::addProducts<float>(const float*, float*, bool) const;

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
