// CG iterations of the stiff cloth's backward-Euler system (stiff_cloth_bench's cloth, or SIDE x SIDE) under
// block-Jacobi and several two-level preconditioners built on the solver's own aggregates (coarse_correction.h), each
// with an exact coarse solve, at a few moments of the fall: a yardstick for the next preconditioner, not the solver.
// Matrices are plain Eigen sparse ones (slow, clear); the system is A^ = S A S + (I - S) with A = M - h df/dv - h^2
// df/dx, S the pinned filter, W = S Z the filtered aggregate translations, Q = W (W^T A^ W)^-1 W^T, B block-Jacobi.
// The right-hand side is a gravity impulse with 1% noise. Stops at relative residual 1e-3, the solver's default.
// Run: build/preconditioner_study [SIDE]
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "sim/bodies/cloth.h"
#include "sim/solver/coarse_correction.h"
#include "sim/force_jacobian.h"
#include "sim/integrators/integrator.h"
#include "sim/simulation.h"

namespace wobble {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Preconditioner = std::function<VecX(const VecX&)>;

struct FilteredSystem {
  SparseMatrix a;  // S A S + (I - S)
  SparseMatrix w;  // S Z
  VecX b;
};

// The backward-Euler matrix of a SIDE x SIDE stiff cloth at time t (fallen from rest with backward Euler at 1/60).
FilteredSystem stiffCloth(int side, double t, std::vector<int>& aggregates_out) {
  ClothParams p;
  p.nx = p.ny = side;
  p.ks = 1e5;
  p.pinned = clothPinSet("corners", p.nx, p.ny);
  MassSpringSystem system;
  system.addBody(buildCloth("cloth", p));
  const double h = 1.0 / 60;
  Simulation sim(system, makeIntegrator("backward-euler"), h);
  sim.advanceTo(t);
  const ForceJacobian& jacobian = *system.forceJacobian();
  PairBlockMatrix blocks;
  blocks.reset(jacobian.jacobianPattern());
  jacobian.fillJacobian(0, sim.x(), sim.v(), h * h, h, blocks, nullptr, nullptr);
  const int n = system.particleCount();
  for (int i = 0; i < n; ++i) blocks.self()[i] += jacobian.mass()[i];
  ParticleFilter filter;
  filter.reset(jacobian.inverseMass());
  CoarseCorrection coarse;
  coarse.setUp(blocks, filter);
  aggregates_out.assign(coarse.aggregates(), coarse.aggregates() + n);

  const auto free = [&](int i) { return filter.kind(i) != ParticleFilter::Held; };
  std::vector<Eigen::Triplet<double>> entries;
  const auto add = [&](int i, int j, const Eigen::Matrix3d& m) {
    if (!free(i) || !free(j)) return;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) entries.emplace_back(3 * i + r, 3 * j + c, m(r, c));
  };
  for (int i = 0; i < n; ++i) {
    add(i, i, blocks.self()[i] * Eigen::Matrix3d::Identity());
    if (!free(i))
      for (int k = 0; k < 3; ++k) entries.emplace_back(3 * i + k, 3 * i + k, 1.0);  // I - S
  }
  for (std::size_t e = 0; e < blocks.pattern()->size(); ++e) {
    const int i = blocks.pattern()->a()[e], j = blocks.pattern()->b()[e];
    const Eigen::Matrix3d m = blocks.pair(e).dense();
    add(i, i, m), add(j, j, m), add(i, j, -m), add(j, i, -m);
  }
  FilteredSystem out;
  out.a.resize(3 * n, 3 * n);
  out.a.setFromTriplets(entries.begin(), entries.end());
  std::vector<Eigen::Triplet<double>> columns;
  for (int i = 0; i < n; ++i)
    if (free(i))
      for (int k = 0; k < 3; ++k) columns.emplace_back(3 * i + k, 3 * aggregates_out[i] + k, 1.0);
  out.w.resize(3 * n, 3 * coarse.aggregateCount());
  out.w.setFromTriplets(columns.begin(), columns.end());
  std::mt19937 random(1);
  std::normal_distribution<double> normal;
  out.b.resize(3 * n);
  for (int i = 0; i < n; ++i)
    particle(out.b, i) =
        free(i) ? Vec3(0.01 * normal(random), -9.81 * h + 0.01 * normal(random), 0.01 * normal(random)) : Vec3::Zero();
  return out;
}

// Preconditioned CG from 0 to relative residual 1e-3; returns the iterations (2000: did not converge).
int iterations(const SparseMatrix& a, const VecX& b, const Preconditioner& precondition) {
  VecX x = VecX::Zero(b.size()), r = b, z = precondition(r), p = z;
  double rz = r.dot(z);
  int k = 0;
  for (; r.norm() > 1e-3 * b.norm() && k < 2000; ++k) {
    const VecX q = a * p;
    const double alpha = rz / p.dot(q);
    x += alpha * p;
    r -= alpha * q;
    z = precondition(r);
    const double next = r.dot(z);
    p = z + (next / rz) * p;
    rz = next;
  }
  return k;
}

}  // namespace
}  // namespace wobble

int main(int argc, char** argv) {
  using namespace wobble;
  const int side = argc > 1 ? std::atoi(argv[1]) : 100;
  std::printf("CG iterations to relative residual 1e-3, %d x %d cloth, ks 1e5, dt 1/60, exact coarse solves\n\n", side,
              side);
  std::printf(
      "| t (s) | block-Jacobi B | additive B + Q (the solver's) | B then Q: B + Q (I - A B) | balancing "
      "Q + (I - Q A) B (I - A Q) | V(1,1): B, Q, B |\n|---|---|---|---|---|---|\n");
  for (const double t : {0.1, 0.25, 0.5, 0.9}) {
    std::vector<int> aggregates;
    const FilteredSystem s = stiffCloth(side, t, aggregates);
    const SparseMatrix& a = s.a;
    const SparseMatrix coarse_matrix = s.w.transpose() * a * s.w;
    const Eigen::SimplicialLDLT<SparseMatrix> coarse(coarse_matrix);
    const auto q = [&](const VecX& r) { return VecX(s.w * coarse.solve(s.w.transpose() * r)); };
    const int n = int(s.b.size() / 3);
    std::vector<Eigen::Matrix3d> inverse(n);
    for (int i = 0; i < n; ++i) inverse[i] = Eigen::Matrix3d(a.block(3 * i, 3 * i, 3, 3)).inverse();
    const auto jacobi = [&](const VecX& r) {
      VecX z(r.size());
      for (int i = 0; i < n; ++i) particle(z, i) = inverse[i] * particle(r, i);
      return z;
    };
    const std::vector<Preconditioner> preconditioners = {
        jacobi,
        [&](const VecX& r) { return VecX(jacobi(r) + q(r)); },
        [&](const VecX& r) {
          const VecX z = jacobi(r);
          return VecX(z + q(r - a * z));
        },
        [&](const VecX& r) {
          const VecX c = q(r), y = jacobi(r - a * c);
          return VecX(c + y - q(a * y));
        },
        [&](const VecX& r) {
          const VecX z1 = jacobi(r), z2 = z1 + q(r - a * z1);
          return VecX(z2 + jacobi(r - a * z2));
        },
    };
    std::printf("| %.2f |", t);
    for (const Preconditioner& m : preconditioners) std::printf(" %d |", iterations(a, s.b, m));
    std::printf("\n");
  }
  std::printf(
      "\nA product with A costs about a CG iteration's product; B then Q needs one more per iteration, "
      "balancing and V(1,1) two (less where A Q's product runs over the aggregates' boundary pairs only).\n");
}
