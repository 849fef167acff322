// Baraff & Witkin's modified preconditioned conjugate gradients: solves A x = b on the subspace a ParticleFilter S
// leaves free, with x's removed part (I - S) x held at its starting value (a contact's prescribed normal velocity
// change, 0 on pinned particles). Preconditioner: block-Jacobi, the inverse of each particle's filtered 3x3 diagonal
// block; two_level adds the coarse correction of coarse_correction.h (fewer iterations on large stiff systems, for a
// setup every kCoarseRefresh solves and a small sparse solve per iteration; the sum is symmetric positive definite).
// Stops when the residual's 2-norm |S (b - A x)| is at most tolerance times that of the filtered right-hand side S (b -
// A (I - S) x0) (Eigen's ConjugateGradient rule), or after max_iterations. Every vector operation runs over particle
// chunks and every sum in chunk order (parallel.h), each chunk's in fixed lanes (pcg_kernels.h), the coarse solve's
// two dissected parts each in one order (coarse_correction.h): the same bytes whatever the thread count. Buffers are
// kept between solves.
#pragma once
#include <vector>

#include "sim/coarse_correction.h"
#include "sim/pair_block_matrix.h"
#include "sim/particle_filter.h"

namespace wobble {

struct PcgResult {
  int iterations = 0;
  double relative_residual = 0;  // |S (b - A x)| / |S (b - A (I - S) x0)| at the end; 0 when that rhs is 0
};

// A two-level solve sets the coarse level up afresh when the one before it did not use it, or after it has served
// this many solves. In between, it keeps the last factorization: the sum stays symmetric positive definite (any SPD
// coarse matrix does), only a little less sharp as the system drifts. Measured on the stiff cloth (README,
// Integrators): every second solve costs 0.6 more CG iterations a step (22.65 against 22.05) and saves half the
// coarse fills and factorizations, 9% of the step; every fourth, 24.7 iterations.
inline constexpr int kCoarseRefresh = 2;

class FilteredPcg {
 public:
  // x: the starting guess on input (its removed part is kept), the solution on output.
  PcgResult solve(const PairBlockMatrix& a, const ParticleFilter& s, const VecX& b, VecX& x, double tolerance,
                  int max_iterations, bool parallel, bool two_level);
  const CoarseCorrection& coarse() const { return coarse_; }

 private:
  void setUpPreconditioner(const PairBlockMatrix& a, const ParticleFilter& s, bool parallel);

  CoarseCorrection coarse_;
  int coarse_uses_ = 0;  // two-level solves since the coarse level was set up; 0 when the last solve had none
  std::vector<Sym3> diagonal_, inverse_;
  std::vector<int> constrained_;  // the particles S filters (not free), in order
  VecX r_, c_, q_, z_;
  std::vector<double> sums_;
};

}  // namespace wobble
