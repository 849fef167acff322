// Baraff & Witkin's modified preconditioned conjugate gradients: solves A x = b on the subspace a ParticleFilter S
// leaves free, with x's removed part (I - S) x held at its starting value (a contact's prescribed normal velocity
// change, 0 on pinned particles). Block-Jacobi (3x3) preconditioner on the filtered diagonal blocks. Stops when the
// residual's 2-norm |S (b - A x)| is at most tolerance times that of the filtered right-hand side S (b - A (I - S) x0)
// (Eigen's ConjugateGradient rule), or after max_iterations. Every vector operation runs over particle chunks and
// every sum in chunk order (parallel.h): the same bytes whatever the thread count. Buffers are kept between solves.
#pragma once
#include <vector>

#include "sim/pair_block_matrix.h"
#include "sim/particle_filter.h"

namespace wobble {

struct PcgResult {
  int iterations = 0;
  double relative_residual = 0;  // |S (b - A x)| / |S (b - A (I - S) x0)| at the end; 0 when that rhs is 0
};

class FilteredPcg {
 public:
  // x: the starting guess on input (its removed part is kept), the solution on output.
  PcgResult solve(const PairBlockMatrix& a, const ParticleFilter& s, const VecX& b, VecX& x, double tolerance,
                  int max_iterations, bool parallel);

 private:
  void setUpPreconditioner(const PairBlockMatrix& a, const ParticleFilter& s, bool parallel);

  std::vector<Sym3> diagonal_, inverse_;
  VecX r_, c_, q_, z_;
  std::vector<double> sums_;
  std::vector<Eigen::Vector2d> pair_sums_;
};

}  // namespace wobble
