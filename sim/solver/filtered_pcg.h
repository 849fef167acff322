// Baraff & Witkin's modified preconditioned conjugate gradients: solves A x = b on the subspace a ParticleFilter S
// leaves free, with x's removed part (I - S) x held at its starting value (a contact's prescribed normal velocity
// change, 0 on pinned particles). Preconditioner: block-Jacobi, the inverse of each particle's filtered 3x3 diagonal
// block; two_level adds the coarse correction of coarse_correction.h (fewer iterations on large stiff systems, for a
// setup every kCoarseRefresh solves and a small sparse solve per iteration; the sum is symmetric positive definite).
// Stops when the residual's 2-norm |S (b - A x)| is at most tolerance times that of the filtered right-hand side S (b -
// A (I - S) x0) (Eigen's ConjugateGradient rule), or at the caller's absolute_tolerance if that is looser (the error
// rule of backward_euler.cpp), or after max_iterations. Every vector operation runs over particle
// chunks and every sum in chunk order (parallel.h), each chunk's in fixed lanes (pcg_kernels.h), the coarse solve's
// two dissected parts each in one order (coarse_correction.h): the same bytes whatever the thread count. Buffers are
// kept between solves.
// Mixed precision: for a tolerance of at least kSingleTolerance (the default 1e-3 is), when the solve before took at
// least kSingleIterations iterations, the iterations run in float on the matrix's float copy (SinglePairBlockMatrix),
// solving for the correction of x from the double residual S (b - A x), and that residual is then recomputed in
// double; while it is above the tolerance, another round of float iterations follows (iterative refinement). The
// tolerance thus holds for the double system, and the float rounds read half the bytes of a double iteration (the
// solve is bound by memory traffic). Tighter tolerances iterate in double throughout.
#pragma once
#include <vector>

#include "sim/solver/coarse_correction.h"
#include "sim/solver/pair_block_matrix.h"
#include "sim/solver/particle_filter.h"

namespace wobble {

struct PcgResult {
  int iterations = 0;
  int rounds = 0;            // rounds of float iterations (iterative refinement); 0 when the iterations ran in double
  bool by_absolute = false;  // stopped by absolute_tolerance above tolerance times the right-hand side's norm
  double relative_residual = 0;  // |S (b - A x)| / |S (b - A (I - S) x0)| at the end; 0 when that rhs is 0
};

// A two-level solve sets the coarse level up afresh when the one before it did not use it, when the matrix's contact
// stencils have changed since (StencilCouplings::generation: backward Euler's active set changes between the solves of
// a step, and a pair just pressed is a stiff coupling the kept factorization lacks), when a particle's kind of
// constraint in the filter has (a particle that has just met the floor, or left it: a factorization kept across such
// a change preconditions a system it no longer matches), or after it has served this many solves. In between, it keeps
// the last factorization: the sum stays symmetric positive definite (any SPD coarse matrix does), only a little less
// sharp as the system drifts. Every third solve balances the few CG iterations a kept factorization adds against the
// fills and factorizations it saves (docs/performance.md).
inline constexpr int kCoarseRefresh = 3;

// Tolerances at least this loose run their iterations in float (iterative refinement); tighter ones in double. Float
// iterations reduce the residual by about 1e-5 a round before rounding stalls them.
inline constexpr double kSingleTolerance = 1e-5;
// ... when the solve before took at least this many iterations: the float copy of the matrix and the residual's
// recomputation cost about three double iterations, which a float iteration repays at about 0.4 each (a 256 x 256
// cloth at dt 1e-4 needs 0 or 1 iterations a step; the stiff cloth 23). The first solve iterates in double.
inline constexpr int kSingleIterations = 8;

// For studies of the preconditioner (bench/preconditioner_study.cpp): when set, every solve first hands its system
// (the matrix, the filter, b and the starting x, the relative tolerance) to this function. Not for the simulator.
using PcgSystemTap = void (*)(const PairBlockMatrix& a, const ParticleFilter& s, const VecX& b, const VecX& x,
                              double tolerance);
void setPcgSystemTap(PcgSystemTap tap);

class FilteredPcg {
 public:
  // x: the starting guess on input (its removed part is kept), the solution on output. absolute_tolerance: the solve
  // also stops once |S (b - A x)| is at most this (a bound on its error, from the caller).
  PcgResult solve(const PairBlockMatrix& a, const ParticleFilter& s, const VecX& b, VecX& x, double tolerance,
                  int max_iterations, bool parallel, bool two_level, double absolute_tolerance = 0);
  const CoarseCorrection& coarse() const { return coarse_; }
  // The last solve's residual S (b - A x) at its end (recomputed in double after float rounds; the recurrence's in
  // double iterations), 0 where its filtered right-hand side was.
  const VecX& residual() const { return r_; }

 private:
  // One precision's buffers: the direction c, the product q, the block-Jacobi inverse (6 values a particle: Sym3's
  // xx, yy, zz, xy, xz, yz); in float also x (the correction) and r.
  template <class T>
  struct Iterates {
    std::vector<T> x, r, c, q, inverse;
  };

  void setUpPreconditioner(const PairBlockMatrix& a, const ParticleFilter& s, bool parallel);
  // r = S (b - A x) in double into r_; returns |r|^2.
  double residual(const PairBlockMatrix& a, const ParticleFilter& s, const VecX& b, const VecX& x, bool parallel);
  // CG iterations from x (3 n values) with its filtered residual in r (|r|^2 = r_norm2, updated) until |r|^2 <
  // threshold or max_iterations; returns the iterations.
  template <class T, class Matrix>
  int iterate(const Matrix& a, const ParticleFilter& s, T* x, T* r, Iterates<T>& it, double& r_norm2, double threshold,
              int max_iterations, bool parallel, bool two_level);

  CoarseCorrection coarse_;
  bool single_pays_ = false;  // the last solve took at least kSingleIterations
  int coarse_uses_ = 0;       // two-level solves since the coarse level was set up; 0 when the last solve had none
  long coarse_stencils_ = 0;  // the stencils' generation the coarse level was set up with
  std::vector<std::uint8_t> coarse_kinds_;  // the filter's kinds the coarse level was set up with
  std::vector<Sym3> diagonal_;
  std::vector<int> constrained_;  // the particles S filters (not free), in order
  Iterates<double> double_;
  Iterates<float> single_;
  SinglePairBlockMatrix single_matrix_;
  VecX r_, q_, z_;
  std::vector<double> sums_;
};

}  // namespace wobble
