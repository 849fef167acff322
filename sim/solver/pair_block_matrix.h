// The implicit solver's matrix, in the shape of pairwise forces' Jacobians: A = blockdiag(self_p I) plus, for every
// pair e = (a, b) of a PairSchedule, W_e on the diagonal blocks (a, a) and (b, b) and -W_e on (a, b) and (b, a).
// The pattern is the schedule's, fixed per topology; each step refills the values in place (symmetric 3x3 blocks;
// the W_e = a_e I + w_e w_e^T by value in four arrays, so that the product reads a run of pairs contiguously).
#pragma once
#include <vector>

#include "sim/solver/pair_schedule.h"
#include "sim/solver/sym3.h"

namespace wobble {

class PairBlockMatrix {
 public:
  // Sizes the blocks for a pattern (the schedule must outlive the matrix or the next reset).
  void reset(const PairSchedule& pattern);
  const PairSchedule* pattern() const { return pattern_; }
  // Whether the blocks are sized for pattern as it stands (a system may rebuild its schedule in place).
  bool fits(const PairSchedule& pattern) const {
    return pattern_ == &pattern && self_.size() == std::size_t(pattern.particles()) &&
           pair_.size() == 4 * pattern.size();
  }

  // Per particle its own block's weight: self_p I (mass and drag act equally in all directions; one number, not a
  // block, so the product reads a sixth of the bytes).
  std::vector<double>& self() { return self_; }
  // One block per pair, in schedule order, stored by value as a I + w w^T (PairBlockColumns).
  PairBlockColumns pair() { return columns(); }
  const std::vector<double>& self() const { return self_; }
  Sym3 pair(std::size_t e) const { return columns().get(e); }

  // The diagonal blocks A_pp = self_p I + sum of W_e over the pairs at p (for block-Jacobi preconditioning).
  void diagonal(std::vector<Sym3>& out, bool parallel) const;
  // y = A x (multiplyFused below, with nothing fused).
  void multiply(const VecX& x, VecX& y, bool parallel) const;
  // y = self x on particles [begin, end): the first part of the product.
  void multiplySelf(const double* x, double* y, int begin, int end) const;
  // y += the pair blocks' part of A x over runs of pairs (a task of the schedule, after multiplySelf on its particles).
  void addPairProducts(const double* x, double* y, std::span<const PairRun> runs) const;

 private:
  const PairSchedule* pattern_ = nullptr;
  // The four arrays of pair_. PairBlockColumns has no read-only form: const members only read through it.
  PairBlockColumns columns() const {
    double* data = const_cast<double*>(pair_.data());
    const std::size_t n = pair_.size() / 4;
    return {{data, data + n, data + 2 * n, data + 3 * n}};
  }

  std::vector<double> self_;
  std::vector<double> pair_;  // four arrays of pattern size (PairBlockColumns)
  friend class SinglePairBlockMatrix;
};

// A PairBlockMatrix's values rounded to float, on its pattern: the CG's inner iterations (filtered_pcg.h) multiply by
// it, reading half the bytes with twice the lanes of the double product.
class SinglePairBlockMatrix {
 public:
  // The values of a as they stand (again after every refill of a).
  void assign(const PairBlockMatrix& a, bool parallel);
  // Sized for a's pattern without values: so that a later assign allocates nothing.
  void reserve(const PairBlockMatrix& a);
  const PairSchedule* pattern() const { return pattern_; }
  void multiplySelf(const float* x, float* y, int begin, int end) const;
  void addPairProducts(const float* x, float* y, std::span<const PairRun> runs) const;

 private:
  const PairSchedule* pattern_ = nullptr;
  std::vector<float> self_, pair_;
};

// y = A x for either matrix, in one pass over the schedule (PairSchedule::runByBlocks): on each block of particles,
// before(begin, end), then the self part, then the block's own pairs, all by one task; then the pairs between blocks.
// before() is per-particle work that produces x there (the CG's direction update), fused into the product instead of
// a loop and a wait of its own. The bytes are those of the unfused product: each particle's terms come in one order.
template <class Matrix, class T, class Before>
void multiplyFused(const Matrix& a, const T* x, T* y, bool parallel, Before&& before) {
  a.pattern()->runByBlocks(
      parallel,
      [&](int begin, int end, std::span<const PairRun> runs) {
        before(begin, end);
        a.multiplySelf(x, y, begin, end);
        a.addPairProducts(x, y, runs);
      },
      [&](std::span<const PairRun> runs) { a.addPairProducts(x, y, runs); });
}

}  // namespace wobble
