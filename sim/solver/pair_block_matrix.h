// The implicit solver's matrix, in the shape of pairwise forces' Jacobians: A = blockdiag(self_p I) plus, for every
// pair e = (a, b) of a PairSchedule, W_e on the diagonal blocks (a, a) and (b, b) and -W_e on (a, b) and (b, a).
// The pattern is the schedule's, fixed per topology; each step refills the values in place (symmetric 3x3 blocks;
// the W_e = a_e I + w_e w_e^T by value in four arrays, so that the product reads a run of pairs contiguously).
#pragma once
#include <array>
#include <vector>

#include "sim/solver/pair_schedule.h"
#include "sim/solver/stencil.h"
#include "sim/solver/sym3.h"

namespace wobble {

// A coupling outside the pattern, among the particles of a stencil (each once): it adds w_i w_j B to block (p_i, p_j)
// for every i, j (B symmetric positive semidefinite), the Jacobian of a force along the relative position sum w_i x_i
// (contact between bodies inside backward Euler's solve, sim/integrators/backward_euler.cpp). A weight of 0 leaves its
// particle out.
struct StencilBlock {
  WeightedStencil stencil;
  Sym3 block;
};

// The stencil couplings of a matrix (few next to the pattern's pairs, changing from solve to solve; empty unless
// bodies touch), and their part of a product y += sum_k W_k^T B_k W_k x on threads: first u_k = B_k sum_j w_j x_j for
// every stencil (each on its own), then each particle gathers its w_i u_k in stencil order, through an index from
// particle to its stencils built once after the couplings change. Every particle's terms come in the order the
// one-thread loop over stencils adds them, so the bytes are the same whatever the threads.
class StencilCouplings {
 public:
  void clear() {
    if (!blocks_.empty()) ++generation_;
    blocks_.clear();
    indexed_ = false;
  }
  void push_back(const StencilBlock& b) {
    blocks_.push_back(b);
    ++generation_;
    indexed_ = false;
  }
  // Counts the changes (the coarse level's refresh, filtered_pcg.h): the same number means the same couplings (a clear
  // of none is no change, so a system that never has any always reads 0).
  long generation() const { return generation_; }
  bool empty() const { return blocks_.empty(); }
  std::size_t size() const { return blocks_.size(); }
  std::vector<StencilBlock>::const_iterator begin() const { return blocks_.begin(); }
  std::vector<StencilBlock>::const_iterator end() const { return blocks_.end(); }
  // y += the couplings' part of A x (T: double, or float throughout, from float copies of the weights and blocks).
  template <class T>
  void addProducts(const T* x, T* y, bool parallel) const;

 private:
  // The values a product reads, in the precision it runs in (double; float for the CG's inner iterations, whose
  // springs' blocks are float too: half the memory traffic, which is what the product waits on).
  template <class S>
  struct Values {
    std::vector<S> entry_weight;   // per entry of the gather index
    std::vector<S> packed_weight;  // per packed particle
    std::vector<S> packed_block;   // stencil k's block: xx, yy, zz, xy, xz, yz at 6 k (contiguous)
    std::vector<S> u;              // u_k, three values a stencil: scratch of the product
  };
  void index() const;
  template <class S>
  void products(Values<S>& values, const S* x, S* y, bool parallel) const;  // values: the mutable double_ or single_
  std::vector<StencilBlock> blocks_;
  long generation_ = 0;
  // The gather index (mutable: built on the first product after a change): the touched particles, and per particle
  // its entries [first_[r], first_[r + 1]) of (stencil, weight) in stencil order.
  mutable bool indexed_ = false;
  mutable std::vector<int> touched_, first_, entry_stencil_;
  // The stencils packed for the first pass (a WeightedStencil holds up to 32 particles, most hold 4): stencil k's
  // particles and weights [packed_first_[k], packed_first_[k + 1]), weights of 0 left out.
  mutable std::vector<int> packed_first_, packed_particle_;
  mutable Values<double> double_;
  mutable Values<float> single_;
};

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

  // The stencil couplings (few, changing from step to step; empty unless bodies touch): kept until cleared, through
  // every refill of self and pair.
  StencilCouplings& stencils() { return stencils_; }
  const StencilCouplings& stencils() const { return stencils_; }

  // The diagonal blocks A_pp = self_p I + sum of W_e over the pairs at p, plus the stencils' w_i^2 B (for block-Jacobi
  // preconditioning).
  void diagonal(std::vector<Sym3>& out, bool parallel) const;
  // y = A x (multiplyFused below, with nothing fused).
  void multiply(const VecX& x, VecX& y, bool parallel) const;
  // y = self x on particles [begin, end): the first part of the product.
  void multiplySelf(const double* x, double* y, int begin, int end) const;
  // y += the pair blocks' part of A x over runs of pairs (a task of the schedule, after multiplySelf on its particles).
  void addPairProducts(const double* x, double* y, std::span<const PairRun> runs) const;
  // y += the stencils' part of A x (StencilCouplings): after the rest of the product.
  void addStencilProducts(const double* x, double* y, bool parallel) const { stencils_.addProducts(x, y, parallel); }

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
  StencilCouplings stencils_;
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
  void addStencilProducts(const float* x, float* y, bool parallel) const {
    if (stencils_) stencils_->addProducts(x, y, parallel);
  }

 private:
  const PairSchedule* pattern_ = nullptr;
  std::vector<float> self_, pair_;
  const StencilCouplings* stencils_ = nullptr;  // the double matrix's (assign)
};

// y = A x for either matrix, in one pass over the schedule (PairSchedule::runByBlocks): on each block of particles,
// before(begin, end), then the self part, then the block's own pairs, all by one task; then the pairs between blocks.
// before() is per-particle work that produces x there (the CG's direction update), fused into the product instead of
// a loop and a wait of its own. The bytes are those of the unfused product: each particle's terms come in one order.
// The stencils (if any) come last.
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
  a.addStencilProducts(x, y, parallel);
}

}  // namespace wobble
