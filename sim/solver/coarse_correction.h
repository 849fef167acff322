// The coarse level of the implicit solver's two-level preconditioner: particles grouped into aggregates (a particle
// and its pair neighbours, greedily, once per topology), one 3-vector of unknowns per aggregate (Z: the aggregate's
// particles move together), the Galerkin matrix Z^T S A S Z of the filtered system refilled every setup and factorized
// by a sparse LDLT of 3 x 3 blocks (block_ldlt.h). Added to block-Jacobi (filtered_pcg.h) it corrects the smooth modes
// that block-Jacobi leaves to the conjugate gradients: S Z (Z^T S A S Z)^-1 Z^T S is symmetric positive semidefinite,
// so the sum stays a valid PCG preconditioner (smoothed-aggregation's coarse space without the smoothing: Vanek,
// Mandel & Brezina 1996). The Galerkin matrix includes A's contact stencils (StencilCouplings): a stencil of block B
// adds M_I B M_J to coarse block (I, J) for every two of its aggregates (I = J too), M_I = sum of w_i S_(p_i) over its
// particles in aggregate I. Without them the coarse level takes the layers of a pressed cloth for free to move
// across each other and its corrections there overshoot: more CG iterations than block-Jacobi alone. The pattern
// holds the pairs of aggregates the springs join, plus those stencils have joined (kept, so that contact coming and
// going over the same places extends it once); a stencil joining a pair not in it rebuilds the coarse pattern
// (dissection, fill order, symbolic factorization), and a rebuild that finds most of the stencils' pairs unused by the
// stencils at hand drops those (contact that has moved on would otherwise fill the factor).
// The aggregates are ordered by one level of nested dissection (two parts of the aggregate graph with no edge between
// them, fill-reducing (AMD) order within each, then the separator), so the factorization and the triangular solves run
// the two parts on two threads when parallel, each part's arithmetic in one fixed order, and the separator's sums part
// 0 then part 1; the stencils are added one after the other in their order: the same bytes whatever the thread count.
#pragma once
#include <map>
#include <utility>
#include <vector>

#include "sim/solver/block_ldlt.h"
#include "sim/solver/pair_block_matrix.h"
#include "sim/solver/particle_filter.h"

namespace wobble {

class CoarseCorrection {
 public:
  // The aggregates (when the pattern is new), the coarse pattern (extended when a's stencils need it) and the
  // factorized coarse matrix of S A S.
  void setUp(const PairBlockMatrix& a, const ParticleFilter& s, bool parallel = false);
  // Whether the aggregates were built for a's pattern (setUp has run on it), so that solve() may be used with it.
  bool fits(const PairBlockMatrix& a) const;
  // u = (Z^T S A S Z)^-1 Z^T r for a filtered r (S r = r, 3 values a particle); the correction of particle p is then
  // S_p u(aggregate(p)). A float r (the CG's inner iterations) is restricted into doubles; the solve is in double.
  void solve(const double* r, bool parallel = false);
  void solve(const float* r, bool parallel = false);
  void solve(const VecX& r, bool parallel = false) { solve(r.data(), parallel); }
  const double* corrections() const { return u_.data(); }      // u, 3 values per aggregate
  const int* aggregates() const { return aggregate_.data(); }  // per particle: its aggregate
  int aggregateCount() const { return aggregates_; }
  // How many times the aggregates and the coarse pattern were built (once per topology).
  int patternSetups() const { return pattern_setups_; }
  // How many times the coarse pattern was built: with the aggregates, and again when stencils join aggregates it does
  // not.
  int coarsePatterns() const { return coarse_patterns_; }
  // Pairs of aggregates in the coarse pattern for stencils alone (no spring joins them).
  int stencilPairs() const { return stencil_pairs_; }
  // How many times the coarse matrix was filled and factorized.
  int factorizations() const { return factorizations_; }

 private:
  void buildAggregates(const PairSchedule& pattern);  // and the springs' coarse pairs
  void buildCoarsePattern();                          // from coarse_pairs_: dissection, fill order, BlockLdlt::analyze
  int pairBlock(int i, int j) const;                  // block (I, J) of a pair I < J; -1 when not in the pattern
  // Groups each stencil's particles by aggregate (group_*) and adds to coarse_pairs_ the pairs of aggregates it joins
  // that are not there yet; whether any was added.
  bool coverStencils(const StencilCouplings& stencils);
  // Their Galerkin blocks M_I B M_J, into blocks_ (after coverStencils and the pattern's rebuild if it added pairs).
  void addStencils(const StencilCouplings& stencils, const ParticleFilter& s);
  template <class T>
  void solveFor(const T* r, bool parallel);
  template <class T>
  void restrict(const T* r, int k);  // Z^T r of part k's aggregates into y_ (the factor's order)

  const PairSchedule* pattern_ = nullptr;
  std::size_t pattern_pairs_ = 0;
  int pattern_setups_ = 0, coarse_patterns_ = 0, factorizations_ = 0;
  int aggregates_ = 0;
  std::vector<int> aggregate_;  // per particle
  // The coarse pattern's pairs of aggregates (I < J): those the springs join, then those stencils joined
  // (stencil_pairs_ of them, since the aggregates were built or the last rebuild that dropped the unused), each with
  // its block (I, J); (J, I) follows. Per aggregate I, its pairs (J, block) with J > I in [neighbour_start_[I],
  // neighbour_start_[I + 1]).
  std::map<std::pair<int, int>, int> coarse_pairs_;
  int spring_blocks_ = 0;  // blocks [0, spring_blocks_): the aggregates' and the springs' pairs'; then stencils'
  int stencil_pairs_ = 0;
  int used_stencil_pairs_ = 0;           // of those, how many the last coverStencils found in use
  std::vector<char> stencil_pair_used_;  // per stencil pair (block (spring_blocks_ + 2 k)): in use (coverStencils)
  std::vector<int> neighbour_start_;
  std::vector<std::pair<int, int>> neighbours_;
  // Per stencil k (coverStencils): its aggregates [group_start_[k], group_start_[k + 1]) with their summed weights,
  // and per pair of them (x < y, in order) the block of (min, max); scratch of setUp.
  std::vector<int> group_start_, group_aggregate_, group_pair_block_;
  std::vector<double> group_weight_;
  // Per pair (schedule order): its block between two aggregates (I < J: index of (I, J); (J, I) follows), or -1
  // when both particles are in one aggregate; whether its a is in J (the pair runs against the block's order).
  std::vector<int> pair_block_;
  std::vector<char> pair_flipped_;
  std::vector<Eigen::Matrix3d> blocks_;      // aggregates' diagonal blocks, then (I, J) and (J, I) pairs
  std::vector<int> lower_block_;             // per lower block of the factor (BlockLdlt::lower): its block here
  std::vector<int> column_;                  // per aggregate: its block column of the factor (fill-reducing order)
  std::vector<Eigen::Matrix3d> gram_;        // per aggregate: Z^T S Z's block (filters only)
  std::vector<int> size_;                    // particles per aggregate
  std::vector<int> member_start_, members_;  // per aggregate: its particles, in order
  std::vector<int> part_aggregates_[3];      // aggregates of part 0, part 1 and the separator
  BlockLdlt ldlt_;
  VecX y_, u_;
};

}  // namespace wobble
