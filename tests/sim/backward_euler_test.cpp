// Backward Euler (Baraff-Witkin): the force Jacobians against finite differences, the stiff jelly it exists for,
// pinned particles, and the Newton option against the nonlinear backward-Euler equations themselves.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/plane.h"
#include "sim/force_jacobian.h"
#include "sim/simulation.h"

namespace wobble {
namespace {

Eigen::MatrixXd dense(const Triplets& t, Eigen::Index n) {
  Eigen::SparseMatrix<double> m(n, n);
  m.setFromTriplets(t.begin(), t.end());
  return Eigen::MatrixXd(m);
}

// A 3^3 jelly with drag, deformed by scaling about its centre plus a deterministic wobble.
std::unique_ptr<MassSpringSystem> smallJelly(double drag) {
  JellyParams p;
  p.n = 3;
  p.ks = 1000;
  p.kd = 7;
  Body body = buildJelly("jelly", p);
  body.drag = drag;
  auto system = std::make_unique<MassSpringSystem>();
  system->addBody(std::move(body));
  return system;
}

VecX deformed(const VecX& x, double scale) {
  VecX y = x;
  const Vec3 c = x.reshaped(3, x.size() / 3).rowwise().mean();
  for (Eigen::Index i = 0; i < x.size() / 3; ++i)
    particle(y, i) = c + scale * (particle(x, i) - c) + 0.01 * Vec3(std::sin(i), std::cos(3.0 * i), std::sin(7.0 * i));
  return y;
}

// Stretched springs (no clamping): dF/dx is the exact derivative of the spring forces; dF/dv is exact because the
// damper and drag forces are linear in v. Central differences of smoothForce are the oracle.
TEST(ForceJacobian, MatchesFiniteDifferencesOfTheSmoothForce) {
  auto system = smallJelly(0.3);
  const VecX x = deformed(system->initialPositions(), 1.2);
  const Eigen::Index n = x.size();
  Triplets tx, tv;
  system->addForceJacobians(0, x, VecX::Zero(n), tx, tv);
  const Eigen::MatrixXd kx = dense(tx, n), kv = dense(tv, n);
  Eigen::MatrixXd fd_x(n, n), fd_v(n, n);
  VecX fp, fm;
  const VecX v0 = VecX::Zero(n);  // at v = 0 the damper's x-derivative (left out of the Jacobian) vanishes
  for (Eigen::Index j = 0; j < n; ++j) {
    const double e = 1e-6;
    VecX xp = x, xm = x;
    xp[j] += e;
    xm[j] -= e;
    system->smoothForce(0, xp, v0, fp);
    system->smoothForce(0, xm, v0, fm);
    fd_x.col(j) = (fp - fm) / (2 * e);
    VecX vp = v0;
    vp[j] = 1;
    system->smoothForce(0, x, vp, fp);
    system->smoothForce(0, x, v0, fm);
    fd_v.col(j) = fp - fm;
  }
  EXPECT_LT((kx - fd_x).cwiseAbs().maxCoeff(), 1e-5 * kx.cwiseAbs().maxCoeff());
  EXPECT_LT((kv - fd_v).cwiseAbs().maxCoeff(), 1e-9 * kv.cwiseAbs().maxCoeff());
  EXPECT_LT((kx - kx.transpose()).cwiseAbs().maxCoeff(), 1e-12 * kx.cwiseAbs().maxCoeff());
}

// Compressed springs: the transverse term is clamped, so -dF/dx stays positive semidefinite (CG needs an SPD system).
TEST(ForceJacobian, StaysNegativeSemidefiniteUnderCompression) {
  auto system = smallJelly(0);
  const VecX x = deformed(system->initialPositions(), 0.7);
  Triplets tx, tv;
  system->addForceJacobians(0, x, VecX::Zero(x.size()), tx, tv);
  const Eigen::MatrixXd kx = dense(tx, x.size()), kv = dense(tv, x.size());
  const double scale = kx.cwiseAbs().maxCoeff();
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(-kx).eigenvalues().minCoeff(), -1e-10 * scale);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(-kv).eigenvalues().minCoeff(), -1e-10 * scale);
}

struct NoJacobian final : Dynamics {
  void acceleration(double, const VecX&, const VecX& v, VecX& a) const override { a = -v; }
};

TEST(BackwardEuler, NeedsForceJacobians) {
  auto integrator = makeIntegrator("backward-euler");
  VecX x = VecX::Zero(3), v = VecX::Ones(3);
  EXPECT_THROW(integrator->step(NoJacobian{}, 0, 0.1, x, v), std::invalid_argument);
}

// The method's reason to exist: a 10^3 jelly with springs 7000x stiffer than the course default, at one step per
// 60 Hz frame (omega h ~ 50 for its stiffest modes; every explicit method blows up). ground_y: height of its lowest
// particles above the plane y = 0. Returns the largest spring strain seen at any frame end.
struct JellyRun {
  double worst_strain = 0, final_speed = 0, lowest = 0, highest = 0;
  int max_cg = 0;
};

JellyRun runStiffJelly(double ground_y, double restitution, int frames) {
  JellyParams p;
  p.ks = 1e7;
  p.center = Vec3(0, ground_y + p.size / 2, 0);
  MassSpringSystem system;
  system.addBody(buildJelly("jelly", p));
  ContactParams contact;
  contact.restitution = restitution;
  system.addCollider(std::make_unique<PlaneCollider>("ground", contact, Vec3::Zero(), Vec3::UnitY()));
  Simulation sim(system, makeIntegrator("backward-euler"), 1.0 / 60);
  JellyRun run;
  for (int frame = 1; frame <= frames; ++frame) {
    const auto blow_up = sim.advanceTo(frame / 60.0);
    EXPECT_FALSE(blow_up) << blow_up->message(1.0 / 60);
    if (blow_up) break;
    run.worst_strain = std::max(run.worst_strain, maxStrain(system.springs(), sim.x()));
    run.max_cg = std::max(run.max_cg, sim.integrator().stats().last_cg_iterations);
  }
  const auto y = sim.x().reshaped(3, system.particleCount()).row(1);
  run.lowest = y.minCoeff();
  run.highest = y.maxCoeff();
  run.final_speed = sim.v().cwiseAbs().maxCoeff();
  std::printf(
      "  jelly from %.2f m, e = %.1f: max strain %.3g, max CG iterations/step %d, y in [%.4f, %.4f], "
      "final max |v| %.3g\n",
      ground_y, restitution, run.worst_strain, run.max_cg, run.lowest, run.highest, run.final_speed);
  return run;
}

TEST(BackwardEuler, StiffJellyRestsOnAPlaneInShape) {
  const JellyRun run = runStiffJelly(0, 0.8, 30);
  EXPECT_LT(run.worst_strain, 1e-3);  // its own weight barely compresses springs this stiff
  EXPECT_NEAR(run.lowest, 0, 1e-3);
  EXPECT_NEAR(run.highest, 4, 1e-3);
  EXPECT_LT(run.final_speed, 1e-2);
}

// Dropped half a metre (3.1 m/s at impact): the bottom layer would sink up to v h = 5 cm into the plane in a step;
// the impact constraints stop it inside the solve (contact/constraints/constraints.h), so no end-of-step correction
// compresses it (that correction gave strains ~0.12). It must keep its shape and come to rest on the plane, within the
// contact band (epsilon 0.01), where a resting particle may sit anywhere.
TEST(BackwardEuler, StiffJellyDroppedOnAPlaneKeepsItsShapeAndSettles) {
  const JellyRun run = runStiffJelly(0.5, 0, 45);
  EXPECT_LT(run.worst_strain, 0.01);
  EXPECT_GT(run.lowest, -1e-3);
  EXPECT_LT(run.lowest, 0.01);
  EXPECT_NEAR(run.highest, 4, 1e-2);
  EXPECT_LT(run.final_speed, 0.1);
}

std::unique_ptr<MassSpringSystem> cornerPinnedCloth() {
  ClothParams p;
  p.nx = p.ny = 8;
  p.size_x = p.size_y = 2;
  p.pinned = clothPinSet("corners", p.nx, p.ny);
  auto system = std::make_unique<MassSpringSystem>();
  system->addBody(buildCloth("cloth", p));
  return system;
}

// Pinned particles are filtered out of the solve: they must not move by a single bit, one-step or Newton.
TEST(BackwardEuler, PinnedParticlesNeverMove) {
  auto system = cornerPinnedCloth();
  for (bool newton : {false, true}) {
    IntegratorOptions options;
    options.newton = newton;
    auto integrator = makeIntegrator("backward-euler", options);
    VecX x = system->initialPositions(), v = system->initialVelocities();
    const double h = 1.0 / 60;
    for (int i = 0; i < 60; ++i) {
      integrator->step(*system, i * h, h, x, v);
      for (int p = 0; p < system->particleCount(); ++p)
        if (system->inverseMass()[p] == 0) {
          ASSERT_EQ(particle(x, p), particle(system->initialPositions(), p)) << "particle " << p;
          ASSERT_EQ(particle(v, p), Vec3::Zero());
        }
    }
    // The rest of the cloth did sag between the corners.
    EXPECT_LT(x.reshaped(3, system->particleCount()).row(1).minCoeff(), 0.9);
  }
}

// Residual of the backward-Euler equations themselves, independent of the integrator: for the free particles,
// M (v1 - v0) - h F(x0 + h v1, v1) with x1 = x0 + h v1 (no contact here). Max over coordinates of |M^-1 r| (m/s).
double backwardEulerResidual(const MassSpringSystem& system, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                             const VecX& v1) {
  VecX f;
  system.smoothForce(h, x1, v1, f);
  double worst = (x1 - x0 - h * v1).cwiseAbs().maxCoeff() / h;
  for (int p = 0; p < system.particleCount(); ++p)
    if (system.inverseMass()[p] != 0)
      worst = std::max(worst, (particle(v1, p) - particle(v0, p) - h * system.inverseMass()[p] * particle(f, p))
                                  .cwiseAbs()
                                  .maxCoeff());
  return worst;
}

TEST(BackwardEuler, NewtonConvergesToTheNonlinearSolution) {
  auto system = cornerPinnedCloth();
  IntegratorOptions one_step, newton;
  newton.newton = true;
  newton.newton_tolerance = 1e-9;
  newton.cg_tolerance = 1e-8;
  auto linearized = makeIntegrator("backward-euler", one_step);
  auto iterated = makeIntegrator("backward-euler", newton);
  // Large steps on a falling, swinging cloth: the one linear solve leaves a clear residual; Newton removes it.
  const double h = 1.0 / 30;
  VecX x = system->initialPositions(), v = system->initialVelocities();
  double worst_one_step = 0, worst_newton = 0;
  int most_solves = 0;
  for (int i = 0; i < 30; ++i) {
    VecX x1 = x, v1 = v;
    linearized->step(*system, i * h, h, x1, v1);
    worst_one_step = std::max(worst_one_step, backwardEulerResidual(*system, h, x, v, x1, v1));
    x1 = x;
    v1 = v;
    iterated->step(*system, i * h, h, x1, v1);
    const IntegratorStats& s = iterated->stats();
    const double tolerance = newton.newton_tolerance * std::max(1.0, v1.cwiseAbs().maxCoeff());
    EXPECT_LE(s.last_residual, tolerance) << "step " << i;
    EXPECT_LE(backwardEulerResidual(*system, h, x, v, x1, v1), 2 * tolerance) << "step " << i;
    worst_newton = std::max(worst_newton, backwardEulerResidual(*system, h, x, v, x1, v1));
    most_solves = std::max(most_solves, s.last_linear_solves);
    x = x1;
    v = v1;
  }
  std::printf("  residual |M^-1 r|: one linearized step up to %.3g m/s, Newton up to %.3g m/s (<= %d solves)\n",
              worst_one_step, worst_newton, most_solves);
  EXPECT_GT(worst_one_step, 1e3 * worst_newton);
  EXPECT_LT(most_solves, newton.newton_max_iterations);
}

}  // namespace
}  // namespace wobble
