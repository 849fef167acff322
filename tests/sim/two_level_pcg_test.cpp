// The two-level preconditioner (coarse_correction.h inside filtered_pcg.h) against independent oracles: the filtered
// PCG's solution matches a dense LDLT solve of the filtered system (pinned particles and contact normals held); the
// coarse correction is exact on its own coarse space and symmetric positive semidefinite, its parts' solves on two
// threads give the same bytes; its pattern is built once;
// and on the stiff cloth it needs fewer CG iterations than block-Jacobi at the same tolerance, for the same answer.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstring>
#include <random>

#include <tbb/global_control.h>

#include "sim/bodies/cloth.h"
#include "sim/integrators/integrator.h"
#include "sim/simulation.h"
#include "sim/solver/filtered_pcg.h"
#include "sim/solver/parallel.h"
#include "tests/sim/cloth_on_sphere.h"
#include "tests/sim/folded_cloth.h"
#include "tests/sim/stiff_cloth.h"

namespace wobble {
namespace {

// A 12 x 12 cloth (ks 1e5), corners pinned, sagged for a few steps: the backward-Euler matrix at dt 1/60, with a
// contact filter on a few particles (normals not along an axis) besides the pinned ones.
struct SmallSystem {
  MassSpringSystem system;
  PairBlockMatrix a;
  ParticleFilter s;
  VecX b, z;
};

// several: besides, particles on two surfaces at once (a line left free) and on three (held), among them a whole
// row of the cloth, so that some aggregates have only a line of them free (particle_filter.h).
// stencils: contact couplings besides (StencilCouplings), between particles of distant aggregates that no spring
// joins, some filtered (addStencils below).
void addStencils(SmallSystem& sys);

std::unique_ptr<SmallSystem> smallSystem(bool several = false, bool stencils = false) {
  auto out = std::make_unique<SmallSystem>();
  ClothParams p;
  p.nx = p.ny = 12;
  p.ks = 1e5;
  p.pinned = clothPinSet("corners", p.nx, p.ny);
  out->system.addBody(buildCloth("cloth", p));
  const double h = 1.0 / 60;
  Simulation sim(out->system, makeIntegrator("backward-euler"), h);
  EXPECT_FALSE(sim.advanceTo(3 * h));
  const ForceJacobian& jacobian = *out->system.forceJacobian();
  out->a.reset(jacobian.jacobianPattern());
  jacobian.fillJacobian(0, sim.x(), sim.v(), h * h, h, out->a, nullptr, nullptr);
  const int n = out->system.particleCount();
  for (int i = 0; i < n; ++i) out->a.self()[i] += jacobian.mass()[i];
  out->s.reset(jacobian.inverseMass());
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  out->z.setZero(3 * n);
  for (int i : {13, 14, 40, 77, 100}) {  // contacts: a prescribed velocity change along a tilted normal
    const Vec3 dir = Vec3(0.3, 1, -0.2).normalized();
    out->s.constrain(i, dir);
    particle(out->z, i) = 0.1 * dir;
  }
  if (several) {
    const Vec3 n1 = Vec3(0.3, 1, -0.2).normalized(), n2 = Vec3(1, 0.2, 0.4).normalized();
    for (int i = 24; i < 48; ++i) {  // two rows: a line along n1 x n2
      out->s.constrain(i, n1);
      out->s.constrain(i, n2);
      particle(out->z, i) = 0.1 * n1 - 0.05 * n2;
    }
    for (int i : {14, 90, 91}) {  // three surfaces: held (14 was on n1's already)
      out->s.constrain(i, n1);
      out->s.constrain(i, n2);
      out->s.constrain(i, Vec3::UnitZ());
      particle(out->z, i) = Vec3(0.02, -0.03, 0.01);
    }
  }
  out->b.resize(3 * n);
  for (int i = 0; i < 3 * n; ++i) out->b[i] = normal(random);
  if (stencils) addStencils(*out);
  return out;
}

// Point-triangle stencils (w = 1, -a, -b, -c) between the cloth's opposite sides (no spring joins their aggregates),
// one with a contact-filtered point (13: along a normal), one with a particle on two surfaces (30: a line) and a held
// one (90) when the filter has them, one among neighbours, and a 12-particle stencil (a mesh jelly's embedded points)
// across the cloth; blocks k n n^T plus a tangential damper c (I - n n^T), of the size of the matrix's pair blocks.
void addStencils(SmallSystem& sys) {
  const auto block = [](const Vec3& n, double k, double c) {
    const Vec3 u = n.normalized();
    return Sym3::fromDense(k * u * u.transpose() + c * (Eigen::Matrix3d::Identity() - u * u.transpose()));
  };
  const auto triangle = [](int p, int q1, int q2, int q3, double a, double b) {
    WeightedStencil w;
    w.add(p, 1), w.add(q1, -a), w.add(q2, -b), w.add(q3, -(1 - a - b));
    return w;
  };
  StencilCouplings& s = sys.a.stencils();
  s.push_back({triangle(13, 130, 131, 118, 0.2, 0.3), block(Vec3(0.1, 1, 0.2), 3e3, 50)});
  s.push_back({triangle(30, 120, 121, 133, 0.5, 0.25), block(Vec3(-0.3, 1, 0.1), 1e3, 0)});
  s.push_back({triangle(90, 5, 6, 17, 0.6, 0.1), block(Vec3(0, 1, -0.4), 2e3, 20)});
  s.push_back({triangle(66, 67, 78, 79, 0.3, 0.3), block(Vec3(0.2, 1, 0), 1e3, 10)});
  s.push_back({triangle(1, 140, 100, 40, 0.3, 0.4), block(Vec3(0, 1, 0.3), 4e3, 0)});
  WeightedStencil wide;
  for (int i = 0; i < 6; ++i) wide.add(2 + 11 * i, 1.0 / 6), wide.add(137 - 11 * i, -1.0 / 6);
  s.push_back({wide, block(Vec3(0.3, 1, -0.1), 2e3, 30)});
}

Eigen::MatrixXd dense(const PairBlockMatrix& a) {
  const int n = a.pattern()->particles();
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int i = 0; i < n; ++i) m.block<3, 3>(3 * i, 3 * i) += a.self()[i] * Eigen::Matrix3d::Identity();
  for (std::size_t e = 0; e < a.pattern()->size(); ++e) {
    const int i = a.pattern()->a()[e], j = a.pattern()->b()[e];
    const Eigen::Matrix3d w = a.pair(e).dense();
    m.block<3, 3>(3 * i, 3 * i) += w;
    m.block<3, 3>(3 * j, 3 * j) += w;
    m.block<3, 3>(3 * i, 3 * j) -= w;
    m.block<3, 3>(3 * j, 3 * i) -= w;
  }
  // The stencils by their definition: w_i w_j B at (p_i, p_j).
  for (const StencilBlock& b : a.stencils())
    for (int i = 0; i < b.stencil.size; ++i)
      for (int j = 0; j < b.stencil.size; ++j)
        m.block<3, 3>(3 * b.stencil.particle[i], 3 * b.stencil.particle[j]) +=
            b.stencil.w[i] * b.stencil.w[j] * b.block.dense();
  return m;
}

// Z: per particle a unit 3 x 3 block in its aggregate's columns.
Eigen::MatrixXd prolongation(const CoarseCorrection& coarse, int n) {
  Eigen::MatrixXd z = Eigen::MatrixXd::Zero(3 * n, 3 * coarse.aggregateCount());
  for (int p = 0; p < n; ++p) z.block<3, 3>(3 * p, 3 * coarse.aggregates()[p]) = Eigen::Matrix3d::Identity();
  return z;
}

Eigen::MatrixXd filterMatrix(const ParticleFilter& s, int n) {
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) f.block<3, 1>(3 * i, 3 * i + k) = s.apply(i, Vec3::Unit(k));
  return f;
}

// The filtered PCG, with and without the coarse level, against a dense solve of the filtered system.
void expectDenseSolve(const SmallSystem& sys) {
  const int n = sys.system.particleCount();
  // The oracle: x = z + y, y in S's range, S (A (z + y) - b) = 0, i.e. (S A S + I - S) y = S (b - A z).
  const Eigen::MatrixXd a = dense(sys.a), s = filterMatrix(sys.s, n);
  const Eigen::MatrixXd i = Eigen::MatrixXd::Identity(3 * n, 3 * n);
  const VecX y = (s * a * s + i - s).ldlt().solve(s * (sys.b - a * sys.z));
  const VecX expected = sys.z + s * y;
  for (const bool two_level : {false, true}) {
    FilteredPcg pcg;
    VecX x = sys.z;
    const PcgResult r = pcg.solve(sys.a, sys.s, sys.b, x, 1e-12, 1000, false, two_level);
    EXPECT_LE(r.relative_residual, 1e-12);
    EXPECT_LT((x - expected).norm(), 1e-9 * expected.norm()) << "two_level " << two_level;
    EXPECT_GT(r.iterations, 1);
    EXPECT_LT(((i - s) * (x - sys.z)).norm(), 1e-15);  // the prescribed part kept
  }
}

TEST(TwoLevelPcg, MatchesADenseSolveOfTheFilteredSystem) { expectDenseSolve(*smallSystem()); }

// With contact stencils in the matrix (the coarse level then has blocks for them, some between aggregates no spring
// joins), on particles on one, two and three surfaces.
TEST(TwoLevelPcg, MatchesADenseSolveWithStencils) {
  const auto sys = smallSystem(true, true);
  ASSERT_EQ(sys->a.stencils().size(), 6u);
  expectDenseSolve(*sys);
}

// The same with particles on two and three surfaces at once: block-Jacobi's filtered blocks and the coarse level's
// filtered matrix of a line's and a held particle's filter.
TEST(TwoLevelPcg, MatchesADenseSolveWithParticlesOnSeveralSurfaces) {
  const auto sys = smallSystem(true);
  ASSERT_EQ(sys->s.kind(30), ParticleFilter::Line);
  ASSERT_EQ(sys->s.kind(90), ParticleFilter::Held);
  ASSERT_EQ(sys->s.kind(14), ParticleFilter::Held);
  expectDenseSolve(*sys);
}

// Tolerances from kSingleTolerance up iterate in float (iterative refinement) once a solve has taken
// kSingleIterations: the tolerance must still hold for the double system, measured here on the dense matrix, and the
// answer must be as close to the dense solve as the residual allows (|x - x*| <= |r| / smallest eigenvalue of the
// filtered system).
TEST(TwoLevelPcg, FloatIterationsMeetTheToleranceOfTheDoubleSystem) {
  const auto sys = smallSystem();
  const int n = sys->system.particleCount();
  const Eigen::MatrixXd a = dense(sys->a), s = filterMatrix(sys->s, n);
  const Eigen::MatrixXd i = Eigen::MatrixXd::Identity(3 * n, 3 * n);
  const Eigen::MatrixXd filtered = s * a * s + i - s;
  const VecX rhs = s * (sys->b - a * sys->z);
  const VecX expected = sys->z + s * filtered.ldlt().solve(rhs);
  const double smallest = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(filtered).eigenvalues().minCoeff();
  ASSERT_GT(smallest, 0);
  const VecX start = sys->z + s * VecX::Constant(3 * n, 0.01);  // a free part besides the prescribed z
  for (const double tolerance : {1e-3, kSingleTolerance})
    for (const bool two_level : {false, true}) {
      FilteredPcg pcg;
      VecX x = start;
      const PcgResult first = pcg.solve(sys->a, sys->s, sys->b, x, tolerance, 1000, false, two_level);
      EXPECT_EQ(first.rounds, 0);  // the first solve iterates in double
      ASSERT_GE(first.iterations, kSingleIterations);
      x = start;
      const PcgResult r = pcg.solve(sys->a, sys->s, sys->b, x, tolerance, 1000, false, two_level);
      const double residual = (s * (sys->b - a * x)).norm() / rhs.norm();
      EXPECT_GE(r.rounds, 1);
      EXPECT_LE(residual, tolerance) << "tolerance " << tolerance << ", two_level " << two_level;
      EXPECT_NEAR(r.relative_residual, residual, 1e-6 * tolerance);
      EXPECT_LE((x - expected).norm(), residual * rhs.norm() / smallest * (1 + 1e-9));
      EXPECT_LT(((i - s) * (x - sys->z)).norm(), 1e-15);  // the prescribed part kept
      // Tighter tolerances iterate in double.
      x = start;
      EXPECT_EQ(pcg.solve(sys->a, sys->s, sys->b, x, kSingleTolerance / 2, 1000, false, two_level).rounds, 0);
    }
}

// The coarse level is set up afresh every kCoarseRefresh two-level solves, after a block-Jacobi one and when a
// particle's kind of constraint changes (one more contact), and kept in between: a kept factorization of an older
// matrix is still a valid preconditioner, so a solve of a changed system (heavier masses, a contact's normal turned, a
// new right-hand side) still matches the dense oracle of the new system.
TEST(TwoLevelPcg, AKeptCoarseFactorizationStillSolvesAChangedSystem) {
  static_assert(kCoarseRefresh >= 2);
  const auto sys = smallSystem();
  const int n = sys->system.particleCount();
  const auto expected = [&] {
    const Eigen::MatrixXd a = dense(sys->a), s = filterMatrix(sys->s, n);
    const Eigen::MatrixXd i = Eigen::MatrixXd::Identity(3 * n, 3 * n);
    return VecX(sys->z + s * (s * a * s + i - s).ldlt().solve(s * (sys->b - a * sys->z)));
  };
  FilteredPcg pcg;
  const auto solve = [&](bool two_level) {
    VecX x = sys->z;
    const PcgResult r = pcg.solve(sys->a, sys->s, sys->b, x, 1e-12, 1000, false, two_level);
    EXPECT_LE(r.relative_residual, 1e-12);
    EXPECT_LT((x - expected()).norm(), 1e-9 * expected().norm());
  };
  solve(true);
  EXPECT_EQ(pcg.coarse().factorizations(), 1);
  for (int i = 0; i < n; ++i) sys->a.self()[i] += 2.0;  // the system changes, the kinds of constraint do not
  const int constrained = 40;                           // a contact of smallSystem
  ParticleFilter turned;
  turned.reset(VecX::Ones(n));
  for (int p = 0; p < n; ++p)
    if (sys->s.kind(p) == ParticleFilter::Held) turned.hold(p);
    else if (sys->s.kind(p) == ParticleFilter::Normal)
      turned.constrain(p, p == constrained ? Vec3(-0.1, 1, 0.3).normalized() : sys->s.normal(p));
  ASSERT_EQ(turned.kinds(), sys->s.kinds());
  ASSERT_GT((turned.normal(constrained) - sys->s.normal(constrained)).norm(), 0.1);
  sys->s = turned;
  sys->b *= -0.5;
  for (int k = 1; k < kCoarseRefresh; ++k) {
    solve(true);  // kept
    EXPECT_EQ(pcg.coarse().factorizations(), 1);
  }
  solve(true);  // refreshed
  EXPECT_EQ(pcg.coarse().factorizations(), 2);
  solve(false);
  solve(true);  // after a block-Jacobi solve: refreshed
  EXPECT_EQ(pcg.coarse().factorizations(), 3);
  const Vec3 normal = Vec3(-0.2, 1, 0.1).normalized();
  ASSERT_EQ(sys->s.kind(60), ParticleFilter::Free);
  sys->s.constrain(60, normal);  // one more contact
  particle(sys->z, 60) = -0.05 * normal;
  solve(true);  // a kind of constraint changed: refreshed
  EXPECT_EQ(pcg.coarse().factorizations(), 4);
  solve(true);  // kept
  EXPECT_EQ(pcg.coarse().factorizations(), 4);
  EXPECT_EQ(pcg.coarse().patternSetups(), 1);
}

// A change of the stencils (contact's active set between backward Euler's solves) sets the coarse level up afresh at
// the next two-level solve, before kCoarseRefresh: the new stencils' blocks would otherwise wait for it. The same
// stencils keep it; and each solve matches the dense oracle of the system as it stands.
TEST(TwoLevelPcg, AChangeOfTheStencilsRefreshesTheCoarseLevel) {
  static_assert(kCoarseRefresh >= 3);
  const auto sys = smallSystem(false, true);
  const int n = sys->system.particleCount();
  FilteredPcg pcg;
  const auto solve = [&] {
    const Eigen::MatrixXd a = dense(sys->a), s = filterMatrix(sys->s, n);
    const Eigen::MatrixXd i = Eigen::MatrixXd::Identity(3 * n, 3 * n);
    const VecX expected = sys->z + s * (s * a * s + i - s).ldlt().solve(s * (sys->b - a * sys->z));
    VecX x = sys->z;
    EXPECT_LE(pcg.solve(sys->a, sys->s, sys->b, x, 1e-12, 1000, false, true).relative_residual, 1e-12);
    EXPECT_LT((x - expected).norm(), 1e-9 * expected.norm());
  };
  solve();
  EXPECT_EQ(pcg.coarse().factorizations(), 1);
  solve();  // the same stencils: kept
  EXPECT_EQ(pcg.coarse().factorizations(), 1);
  const std::vector<StencilBlock> kept(sys->a.stencils().begin(), sys->a.stencils().end() - 1);
  sys->a.stencils().clear();  // one pair released
  for (const StencilBlock& b : kept) sys->a.stencils().push_back(b);
  solve();
  EXPECT_EQ(pcg.coarse().factorizations(), 2);
  sys->a.stencils().clear();  // none left
  solve();
  EXPECT_EQ(pcg.coarse().factorizations(), 3);
  solve();
  EXPECT_EQ(pcg.coarse().factorizations(), 3);
  EXPECT_EQ(pcg.coarse().coarsePatterns(), 2);  // the springs', extended once for the first stencils
  const int stencil_pairs = pcg.coarse().stencilPairs();
  ASSERT_GT(stencil_pairs, 2);
  // Contact elsewhere, between the cloth's two free corners: one pair of aggregates no spring joins, and the rebuild
  // it needs drops the pairs no stencil uses any more.
  const int* aggregate = pcg.coarse().aggregates();
  const int i = std::min(aggregate[11], aggregate[132]), j = std::max(aggregate[11], aggregate[132]);
  ASSERT_NE(i, j);
  const PairSchedule& springs = *sys->a.pattern();
  for (std::size_t e = 0; e < springs.size(); ++e)
    ASSERT_FALSE(std::minmax({aggregate[springs.a()[e]], aggregate[springs.b()[e]]}) == std::make_pair(i, j));
  WeightedStencil corners;
  corners.add(11, 1), corners.add(132, -1);
  sys->a.stencils().push_back({corners, Sym3::outer(Vec3(0, 2e3, 0))});
  solve();
  EXPECT_EQ(pcg.coarse().factorizations(), 4);
  EXPECT_EQ(pcg.coarse().coarsePatterns(), 3);
  EXPECT_EQ(pcg.coarse().stencilPairs(), 1);
}

// Q = S Z (Z^T S A S Z)^-1 Z^T S, column by column: symmetric, positive semidefinite, and Q (S A S) v = v for every v
// = S Z c of the coarse space (the coarse solve is exact there).
TEST(TwoLevelPcg, CoarseCorrectionIsSymmetricAndExactOnTheCoarseSpace) {
  const auto sys = smallSystem();
  const int n = sys->system.particleCount();
  CoarseCorrection coarse;
  coarse.setUp(sys->a, sys->s);
  ASSERT_GT(coarse.aggregateCount(), 1);
  ASSERT_LT(coarse.aggregateCount(), n / 4);
  const auto apply = [&](const VecX& r) {
    coarse.solve(r);
    VecX out(3 * n);
    for (int p = 0; p < n; ++p)
      particle(out, p) = sys->s.apply(p, Vec3::Map(coarse.corrections() + 3 * coarse.aggregates()[p]));
    return out;
  };
  const Eigen::MatrixXd s = filterMatrix(sys->s, n);
  Eigen::MatrixXd q(3 * n, 3 * n);
  for (int j = 0; j < 3 * n; ++j) q.col(j) = apply(s.col(j));  // Q = Q S: columns of S
  EXPECT_LT((q - q.transpose()).norm(), 1e-9 * q.norm());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (q + q.transpose()));
  EXPECT_GT(eigen.eigenvalues().minCoeff(), -1e-9 * eigen.eigenvalues().maxCoeff());
  EXPECT_GT(eigen.eigenvalues().maxCoeff(), 0);

  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd c(3, coarse.aggregateCount());
  for (double& value : c.reshaped()) value = normal(random);
  VecX v(3 * n);
  for (int p = 0; p < n; ++p) particle(v, p) = sys->s.apply(p, c.col(coarse.aggregates()[p]));
  const Eigen::MatrixXd a = dense(sys->a);
  EXPECT_LT((apply(s * a * v) - v).norm(), 1e-9 * v.norm());

  // The two dissected parts' solves on two threads give the same bytes as one after the other.
  const VecX r = s * a * v;
  coarse.solve(r, false);
  const VecX serial = Eigen::Map<const VecX>(coarse.corrections(), 3 * coarse.aggregateCount());
  coarse.solve(r, true);
  EXPECT_EQ(std::memcmp(serial.data(), coarse.corrections(), sizeof(double) * serial.size()), 0);

  coarse.setUp(sys->a, sys->s);  // the same pattern: aggregates and coarse pattern kept
  EXPECT_EQ(coarse.patternSetups(), 1);
}

// With stencils, the coarse matrix is the Galerkin matrix Z^T S A S Z of A with its stencils, A formed densely here
// from its product applied to unit vectors: the coarse solve inverts Z^T S A S Z on every coarse direction S keeps
// (Q A_s S Z c = S Z c for each unit c, A_s = S A S), with stencils between aggregates that the springs do not join
// (the coarse pattern is extended once, and kept for the same stencils) and on filtered particles.
TEST(TwoLevelPcg, CoarseMatrixWithStencilsIsTheGalerkinMatrix) {
  const auto sys = smallSystem(true, true);
  const int n = sys->system.particleCount();
  Eigen::MatrixXd a(3 * n, 3 * n);
  VecX unit = VecX::Zero(3 * n), column;
  for (int j = 0; j < 3 * n; ++j) {
    unit[j] = 1;
    sys->a.multiply(unit, column, false);
    a.col(j) = column;
    unit[j] = 0;
  }
  ASSERT_LT((a - dense(sys->a)).norm(), 1e-9 * a.norm());  // the product and the stencils' definition agree
  CoarseCorrection coarse;
  coarse.setUp(sys->a, sys->s);
  EXPECT_EQ(coarse.coarsePatterns(), 2);  // the springs' pattern, then extended for the stencils
  EXPECT_GT(coarse.stencilPairs(), 0);
  const int m = coarse.aggregateCount();
  const Eigen::MatrixXd s = filterMatrix(sys->s, n), sz = s * prolongation(coarse, n);
  const Eigen::MatrixXd galerkin = sz.transpose() * a * sz;
  // The stencils change the Galerkin matrix (else this would test the springs alone).
  PairBlockMatrix springs_only = sys->a;
  springs_only.stencils().clear();
  EXPECT_GT((galerkin - sz.transpose() * dense(springs_only) * sz).norm(), 0.1 * galerkin.norm());
  // Directions of the coarse space S keeps: the range of Z^T S Z.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> gram(sz.transpose() * sz);
  int kept = 0;
  for (int k = 0; k < 3 * m; ++k) {
    if (gram.eigenvalues()[k] < 1e-9) continue;
    ++kept;
    const VecX c = gram.eigenvectors().col(k);
    const VecX v = sz * c;
    coarse.solve(VecX(s * a * v));
    const Eigen::Map<const VecX> u(coarse.corrections(), 3 * m);
    EXPECT_LT((sz * u - v).norm(), 1e-9 * v.norm()) << "coarse direction " << k;
  }
  EXPECT_GT(kept, 3 * m - 6);
  coarse.setUp(sys->a, sys->s);  // the same stencils: the pattern covers them
  EXPECT_EQ(coarse.coarsePatterns(), 2);
  EXPECT_EQ(coarse.patternSetups(), 1);
}

// A cloth folded in four layers lying on each other (folded_cloth.h, landed), its backward-Euler matrix at dt 1/60
// with a penalty stencil (100 times the pair's effective mass along its normal, backward_euler.cpp's) for every pair of
// its surface within the thickness: a conjugate gradients loop written here, preconditioned by block-Jacobi plus the
// coarse correction, needs fewer iterations when the coarse level was set up with the stencils than without them
// (as before it saw them) and than block-Jacobi alone. Without them it needs more than block-Jacobi alone: the
// stencils are what resist the layers' motion across the sheet (the springs hardly do), and a coarse level blind to
// them corrects that motion as if it were free.
TEST(TwoLevelPcg, CoarseStencilsCutIterationsOnAStackedCloth) {
  const auto system = testing::foldedCloth(32, true, 4, 0.5, 0);
  const double h = 1.0 / 60;
  Simulation sim(*system, makeIntegrator("backward-euler"), h);
  ASSERT_FALSE(sim.advanceTo(0.5));
  const ForceJacobian& jacobian = *system->forceJacobian();
  const int n = system->particleCount();
  PairBlockMatrix a;
  a.reset(jacobian.jacobianPattern());
  jacobian.fillJacobian(0, sim.x(), sim.v(), h * h, h, a, nullptr, nullptr);
  for (int i = 0; i < n; ++i) a.self()[i] += jacobian.mass()[i];
  PairBlockMatrix springs = a;
  std::vector<ContactPair> pairs;
  PairJoin every;  // every pair within reach
  ASSERT_TRUE(collision::makeBodyCollisions(*system)->nearPairs(sim.x(), sim.x(), pairs, every));
  for (const ContactPair& c : pairs)
    if (const double weight = c.stencil.inverseMass(jacobian.inverseMass()); weight > 0)
      a.stencils().push_back({c.stencil, (100 / weight) * Sym3::outer(c.normal)});
  ASSERT_GT(a.stencils().size(), std::size_t(n));
  ParticleFilter s;
  s.reset(jacobian.inverseMass());
  std::vector<Sym3> diagonal;
  a.diagonal(diagonal, false);
  std::mt19937 random(5);
  std::normal_distribution<double> normal;
  VecX b(3 * n);
  for (double& value : b) value = normal(random);
  // Iterations to a relative residual of 1e-6 (no particle is filtered: S = I).
  const auto iterations = [&](const PairBlockMatrix* coarse_of) {
    CoarseCorrection coarse;
    if (coarse_of) coarse.setUp(*coarse_of, s);
    const auto precondition = [&](const VecX& r) {
      VecX z(3 * n);
      if (coarse_of) coarse.solve(r);
      for (int p = 0; p < n; ++p) {
        particle(z, p) = diagonal[p].dense().inverse() * particle(r, p);
        if (coarse_of) particle(z, p) += Vec3::Map(coarse.corrections() + 3 * coarse.aggregates()[p]);
      }
      return z;
    };
    VecX x = VecX::Zero(3 * n), r = b, z = precondition(r), c = z, q;
    double rz = r.dot(z);
    for (int k = 1; k <= 5000; ++k) {
      a.multiply(c, q, false);
      const double alpha = rz / c.dot(q);
      x += alpha * c;
      r -= alpha * q;
      if (r.norm() <= 1e-6 * b.norm()) {
        a.multiply(x, q, false);
        EXPECT_LT((b - q).norm(), 2e-6 * b.norm());  // solved
        return k;
      }
      z = precondition(r);
      const double rz_next = r.dot(z);
      c = z + (rz_next / rz) * c;
      rz = rz_next;
    }
    return 5001;
  };
  const int jacobi = iterations(nullptr), without = iterations(&springs), with = iterations(&a);
  std::printf("  %zu stencils: block-Jacobi %d iterations, two-level without them %d, with them %d\n",
              a.stencils().size(), jacobi, without, with);
  EXPECT_LT(with, jacobi * 3 / 4);
  EXPECT_LT(with, without / 2);
}

// The stiff cloth of stiff_cloth_bench, smaller (48 x 48) and for a quarter second: fewer iterations, same answer.
TEST(TwoLevelPcg, FewerIterationsThanBlockJacobiOnTheStiffCloth) {
  struct Result {
    long iterations;
    double residual;
    VecX x;
  };
  const auto run = [](CgPreconditioner preconditioner) {
    const auto system = testing::stiffCloth(48);
    IntegratorOptions options;
    options.cg_preconditioner = preconditioner;
    options.cg_error_fraction = 0;  // both to cg_tolerance
    Simulation sim(*system, makeIntegrator("backward-euler", options), 1.0 / 60);
    EXPECT_FALSE(sim.advanceTo(0.25));
    return Result{sim.integrator().stats().cg_iterations, sim.integrator().stats().max_cg_residual, sim.x()};
  };
  const Result jacobi = run(CgPreconditioner::BlockJacobi), two_level = run(CgPreconditioner::TwoLevel);
  std::printf("  block-Jacobi %ld CG iterations, two-level %ld\n", jacobi.iterations, two_level.iterations);
  EXPECT_LT(two_level.iterations, jacobi.iterations * 3 / 4);
  EXPECT_LE(two_level.residual, IntegratorOptions{}.cg_tolerance);
  // Both stop at a relative residual of 1e-3: positions agree far below the cloth's 8 cm spacing and its sag.
  EXPECT_LT((two_level.x - jacobi.x).lpNorm<Eigen::Infinity>(), 1e-3);
}

// Two-level on threads: a 64 x 64 cloth (two particle chunks) landing on a sphere (contact filters), the same bytes
// with 1 and 2 threads (the coarse level runs serially; thread_count_test.cpp covers the integrators at large).
// Backward Euler with the two-level preconditioner on a system from make() until `end`, on `threads` threads (every
// loop split: parallel threshold 0): the final positions, the integrator's stats into stats.
template <class Make>
VecX runTwoLevel(int threads, Make make, double end, IntegratorStats& stats) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  const int saved = parallelThreshold();
  setParallelThreshold(0);
  const auto system = make();
  IntegratorOptions options;
  options.cg_preconditioner = CgPreconditioner::TwoLevel;
  Simulation sim(*system, makeIntegrator("backward-euler", options), 1.0 / 60);
  EXPECT_FALSE(sim.advanceTo(end));
  setParallelThreshold(saved);
  stats = sim.integrator().stats();
  return sim.x();
}

template <class Make>
void expectSameBytesWithOneAndTwoThreads(Make make, double end, IntegratorStats& stats) {
  const VecX one = runTwoLevel(1, make, end, stats), two = runTwoLevel(2, make, end, stats);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(std::memcmp(one.data(), two.data(), sizeof(double) * one.size()), 0);
}

TEST(TwoLevelPcg, SameBytesWithOneAndTwoThreads) {
  IntegratorStats stats;
  expectSameBytesWithOneAndTwoThreads([] { return testing::clothOnSphere(64, 1e5); }, 3.0 / 60, stats);
  EXPECT_GT(stats.cg_iterations, 0);
}

// With contact stencils in the coarse level (a stacked cloth's layers pressed on each other, the coarse pattern
// extended for them): the same bytes with 1 and 2 threads.
TEST(TwoLevelPcg, SameBytesWithOneAndTwoThreadsWithStencils) {
  IntegratorStats stats;
  expectSameBytesWithOneAndTwoThreads([] { return testing::foldedCloth(24, true, 4, 0.5, 0); }, 0.3, stats);
  EXPECT_GT(stats.body_contact_pairs, 1000);
}

}  // namespace
}  // namespace wobble
