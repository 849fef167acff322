// Backward Euler's linear solver (fixed block pattern, Baraff-Witkin's filtered PCG, block-Jacobi) against an
// independent oracle: the same linearized step assembled densely from the triplet Jacobians (force_jacobian.h) and
// solved directly. Also: the contact filter holds, the reported residual is the achieved one, the pattern is sized
// once, and the error rule's early stops cost a small fraction of the method's error. (That no step allocates memory
// is allocation_test.cpp's.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/plane.h"
#include "sim/contact/colliders/sphere.h"
#include "sim/simulation.h"
#include "tests/sim/cloth_on_sphere.h"
#include "tests/sim/stiff_cloth.h"

namespace wobble {
namespace {

// A 4^3 stiff jelly (ks 1e5) settled for half a second on a floor, one bottom corner particle pinned.
struct Landed {
  std::unique_ptr<MassSpringSystem> system;
  VecX x, v;
  double t, h = 1.0 / 60;
};

Landed landedJelly() {
  JellyParams p;
  p.n = 4;
  p.ks = 1e5;
  p.center = Vec3(0, p.size / 2, 0);
  Body body = buildJelly("jelly", p);
  body.pinned[0] = true;
  Landed l{std::make_unique<MassSpringSystem>()};
  l.system->addBody(std::move(body));
  l.system->addCollider(
      std::make_unique<PlaneCollider>("floor", ContactParams{0, 0.5, 0.01}, Vec3::Zero(), Vec3::UnitY()));
  Simulation sim(*l.system, makeIntegrator("backward-euler"), l.h);
  EXPECT_FALSE(sim.advanceTo(0.5));
  l.x = sim.x();
  l.v = sim.v();
  l.t = sim.time();
  return l;
}

// The linearized step's pieces, densely: A = M - h dF/dv - h^2 dF/dx, b = h (F0 + h dF/dx v0), the filter S and
// the prescribed part z, from the system's public functions; and the contacts, for Coulomb's cone.
struct DenseStep {
  Eigen::MatrixXd a, s;
  VecX b, z, v;
  double h = 0;
  std::vector<ContactConstraint> contacts;
  VecX linearSolve() const {  // (S A S + I - S) y = S (b - A z), dv = y + z
    const Eigen::MatrixXd i = Eigen::MatrixXd::Identity(a.rows(), a.cols());
    return Eigen::MatrixXd(s * a * s + i - s).ldlt().solve(s * (b - a * z)) + z;
  }
  VecX solve();
  double relativeResidual(const VecX& dv) const { return (s * (b - a * dv)).norm() / (s * (b - a * z)).norm(); }
};

// Coulomb's cone (backward_euler_contact.cpp, boundFriction), on the dense system: after each solve, the constraint
// impulse J = A dv - b; a hold whose tangential J_t exceeds mu J_n (J_n = J . n + h N) by 10%, and a damper whose
// impulse h c |s1| at the end's slip s1 does, take Coulomb's force mu J_n / h against the pull or the slip instead, and
// such a force that the solve turns against the slip a damper of its size at that slip; solved again, at most 3 times.
VecX DenseStep::solve() {
  struct Force {
    ContactConstraint c;
    Vec3 f;
    bool damped = false;
  };
  std::vector<Force> forces;
  const auto tangent = [](const Vec3& n) { return Eigen::Matrix3d(Eigen::Matrix3d::Identity() - n * n.transpose()); };
  const auto slip = [&](const ContactConstraint& c, const VecX& dv) {
    return Vec3(tangent(c.normal) *
                (particle(v, c.particle) + particle(dv, c.particle) - c.surface_velocity - h * c.surface_acceleration));
  };
  const auto damp = [&](const ContactConstraint& c, double damping) {
    a.block<3, 3>(3 * c.particle, 3 * c.particle) += h * damping * tangent(c.normal);
    b.segment<3>(3 * c.particle) -= h * damping * slip(c, VecX::Zero(v.size()));
  };
  VecX dv = linearSolve();
  for (int pass = 0; pass < 3; ++pass) {
    const VecX j = a * dv - b;
    bool changed = false;
    for (Force& k : forces)
      if (!k.damped && slip(k.c, dv).dot(k.f) > 0) {
        k.damped = changed = true;
        b.segment<3>(3 * k.c.particle) -= h * k.f;
        damp(k.c, k.f.norm() / std::max(slip(k.c, dv).norm(), 1e-3));
      }
    for (ContactConstraint& c : contacts) {
      const Vec3 jp = j.segment<3>(3 * c.particle);
      const double bound = c.mu * std::max(0.0, jp.dot(c.normal) + h * c.support);
      Vec3 f;
      if (c.stick) {
        const Vec3 jt = tangent(c.normal) * jp;
        if (!(jt.norm() > 1.1 * bound)) continue;
        c.stick = false;
        c.damping = 0;  // its damper was never in the matrix
        s.block<3, 3>(3 * c.particle, 3 * c.particle) = tangent(c.normal);
        particle(z, c.particle) = h * c.normal_acceleration * c.normal;
        dv.segment<3>(3 * c.particle) = tangent(c.normal) * dv.segment<3>(3 * c.particle) + particle(z, c.particle);
        f = (bound / h) * jt.normalized();
      } else if (c.damping > 0) {
        const Vec3 s1 = slip(c, dv);
        if (!(h * c.damping * s1.norm() > 1.1 * bound)) continue;
        damp(c, -c.damping);
        c.damping = 0;
        f = -(bound / h) * s1.normalized();
      } else {
        continue;
      }
      b.segment<3>(3 * c.particle) += h * f;
      forces.push_back({c, f});
      changed = true;
    }
    if (!changed) break;
    dv = linearSolve();
  }
  return dv;
}

DenseStep denseStep(const MassSpringSystem& system, double t, const VecX& x, const VecX& v, double h) {
  const Eigen::Index n = x.size();
  Triplets tx, tv;
  system.addForceJacobians(t, x, v, tx, tv);
  Eigen::SparseMatrix<double> kx(n, n), kv(n, n);
  kx.setFromTriplets(tx.begin(), tx.end());
  kv.setFromTriplets(tv.begin(), tv.end());
  VecX m(n), a0;
  for (Eigen::Index i = 0; i < n; ++i) m[i] = system.mass()[i / 3];
  system.acceleration(t, x, v, a0);
  DenseStep d;
  d.v = v;
  d.h = h;
  d.a = Eigen::MatrixXd(m.asDiagonal()) - h * Eigen::MatrixXd(kv) - h * h * Eigen::MatrixXd(kx);
  d.b = h * (m.cwiseProduct(a0) + h * (kx * v));
  d.s = Eigen::MatrixXd::Identity(n, n);
  d.z = VecX::Zero(n);
  for (int p = 0; p < system.particleCount(); ++p)
    if (system.inverseMass()[p] == 0) d.s.block<3, 3>(3 * p, 3 * p).setZero();
  std::vector<ContactConstraint>& contacts = d.contacts;
  system.contactConstraints(t, x, v, contacts);
  EXPECT_EQ(contacts.size(), 15u);  // the bottom layer, 16 particles but the pinned one, is held by the floor
  // Friction (docs/contact.md): out of F0; a sticking contact holds the particle, its tangential change prescribed
  // too; a sliding one is a damper -c P (v1 - u1) on the tangential velocity relative to the surface.
  for (const ContactConstraint& c : contacts) {
    const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - c.normal * c.normal.transpose();
    auto s = d.s.block<3, 3>(3 * c.particle, 3 * c.particle);
    s -= c.normal * c.normal.transpose();
    particle(d.z, c.particle) = h * c.normal_acceleration * c.normal;
    d.b.segment<3>(3 * c.particle) -= h * c.friction;
    if (c.stick) {
      s.setZero();
      particle(d.z, c.particle) += h * c.tangential_acceleration;
    } else if (c.damping > 0) {
      d.a.block<3, 3>(3 * c.particle, 3 * c.particle) += h * c.damping * p;
      d.b.segment<3>(3 * c.particle) -=
          h * c.damping * p * (particle(v, c.particle) - c.surface_velocity - h * c.surface_acceleration);
    }
  }
  return d;
}

VecX stepDv(const MassSpringSystem& system, const Landed& l, const IntegratorOptions& options,
            IntegratorStats* stats = nullptr) {
  auto integrator = makeIntegrator("backward-euler", options);
  VecX x = l.x, v = l.v;
  integrator->step(system, l.t, l.h, x, v);
  if (stats) *stats = integrator->stats();
  return v - l.v;
}

// The step solved to 1e-12 against the dense direct solve; returns the step's stats.
IntegratorStats expectMatchesADirectSolve(const Landed& l) {
  DenseStep d = denseStep(*l.system, l.t, l.x, l.v, l.h);
  const VecX exact = d.solve();
  IntegratorOptions tight;
  tight.cg_tolerance = 1e-12;
  tight.cg_error_fraction = 0;
  IntegratorStats stats;
  const VecX dv = stepDv(*l.system, l, tight, &stats);
  EXPECT_LT((dv - exact).cwiseAbs().maxCoeff(), 1e-9 * exact.cwiseAbs().maxCoeff());
  return stats;
}

TEST(BackwardEulerSolver, MatchesADirectSolveOfTheFilteredSystem) { expectMatchesADirectSolve(landedJelly()); }

// The same with the jelly sliding sideways at 0.5 m/s over the floor (friction 0.5): its contacts slide, and their
// kinetic friction is a damper in the solve; the contacts by the pinned corner, held back, take more than Coulomb's
// cone allows from their dampers and are solved again with Coulomb's force (DenseStep::solve).
TEST(BackwardEulerSolver, MatchesADirectSolveWithSlidingFriction) {
  Landed l = landedJelly();
  for (int p = 0; p < l.system->particleCount(); ++p)
    if (l.system->inverseMass()[p] > 0) l.v[3 * p] += 0.5;
  std::vector<ContactConstraint> contacts;
  l.system->contactConstraints(l.t, l.x, l.v, contacts);
  ASSERT_TRUE(std::any_of(contacts.begin(), contacts.end(),
                          [](const ContactConstraint& c) { return !c.stick && c.damping > 0; }));
  EXPECT_GT(expectMatchesADirectSolve(l).friction_solves, 0);
}

// At the default tolerance the step is only as exact as the tolerance says, and it says so truthfully.
TEST(BackwardEulerSolver, ReportsTheResidualItAchieves) {
  const Landed l = landedJelly();
  const DenseStep d = denseStep(*l.system, l.t, l.x, l.v, l.h);
  const IntegratorOptions defaults;
  IntegratorStats stats;
  const VecX dv = stepDv(*l.system, l, defaults, &stats);
  const double achieved = d.relativeResidual(dv);
  EXPECT_LE(achieved, defaults.cg_tolerance);
  EXPECT_NEAR(stats.last_cg_residual, achieved, 1e-3 * achieved);
  EXPECT_GT(stats.last_cg_iterations, 1);
  // Over several steps: `last` is each step's own, `max` the largest of them so far.
  auto integrator = makeIntegrator("backward-euler", defaults);
  VecX x = l.x, v = l.v;
  double largest = 0;
  std::vector<double> lasts;
  for (int k = 0; k < 6; ++k) {
    integrator->step(*l.system, l.t + k * l.h, l.h, x, v);
    lasts.push_back(integrator->stats().last_cg_residual);
    largest = std::max(largest, lasts.back());
    EXPECT_EQ(integrator->stats().max_cg_residual, largest) << "step " << k;
  }
  EXPECT_NE(*std::min_element(lasts.begin(), lasts.end()), largest) << "every step reached the same residual";
}

// The filter: a pinned particle's dv is exactly 0 and a held particle's normal dv is exactly the prescribed one
// (the floor is static: 0), while its tangential dv is free.
TEST(BackwardEulerSolver, ContactFilterHoldsTheNormalVelocity) {
  const Landed l = landedJelly();
  std::vector<ContactConstraint> contacts;
  l.system->contactConstraints(l.t, l.x, l.v, contacts);
  ASSERT_FALSE(contacts.empty());
  const VecX dv = stepDv(*l.system, l, IntegratorOptions{});
  double tangential = 0;
  int sliding = 0;
  for (const ContactConstraint& c : contacts) {
    EXPECT_NEAR(c.normal.dot(particle(dv, c.particle)), l.h * c.normal_acceleration, 1e-15) << c.particle;
    const Vec3 t = particle(dv, c.particle) - c.normal.dot(particle(dv, c.particle)) * c.normal;
    if (c.stick) {  // held by static friction: the tangential change is the prescribed one too
      EXPECT_LT((t - l.h * c.tangential_acceleration).norm(), 1e-15) << c.particle;
    } else {
      tangential = std::max(tangential, t.norm());
      ++sliding;
    }
  }
  if (sliding > 0) {
    EXPECT_GT(tangential, 0);
  }
  EXPECT_EQ(particle(dv, 0), Vec3::Zero());
}

// The Jacobian pattern (the spring schedule) is built when a body is added, and the integrator sizes its matrix
// once: neither happens again per step. Adding a body changes the topology: both happen once more.
TEST(BackwardEulerSolver, SizesItsPatternOncePerTopology) {
  MassSpringSystem system;
  ClothParams p;
  p.nx = p.ny = 12;
  p.pinned = clothPinSet("corners", p.nx, p.ny);
  system.addBody(buildCloth("cloth", p));
  auto integrator = makeIntegrator("backward-euler");
  VecX x = system.initialPositions(), v = system.initialVelocities();
  for (int i = 0; i < 10; ++i) integrator->step(system, i / 60.0, 1.0 / 60, x, v);
  EXPECT_EQ(system.scheduleBuilds(), 1);
  EXPECT_EQ(integrator->stats().pattern_setups, 1);
  EXPECT_EQ(integrator->stats().jacobians, 10);
  p.center.y() += 1;
  system.addBody(buildCloth("cloth2", p));
  x = system.initialPositions();
  v = system.initialVelocities();
  for (int i = 0; i < 3; ++i) integrator->step(system, i / 60.0, 1.0 / 60, x, v);
  EXPECT_EQ(system.scheduleBuilds(), 2);
  EXPECT_EQ(integrator->stats().pattern_setups, 2);
}

// The error rule (cg_error_fraction): on a stiff cloth at dt 1/60 it stops solves early (fewer CG iterations than the
// relative tolerance alone), and the positions stay within a tenth of the method's own error (dt against dt/2, both
// solved exactly) of the exactly solved backward-Euler run: the solver's error is a fraction of the method's.
TEST(BackwardEulerSolver, ErrorRuleKeepsTheSolveErrorAFractionOfTheMethodError) {
  const auto run = [](double dt, double tolerance, double fraction, IntegratorStats* stats = nullptr) {
    const auto system = testing::stiffCloth(24);
    IntegratorOptions options;
    options.cg_tolerance = tolerance;
    options.cg_error_fraction = fraction;
    Simulation sim(*system, makeIntegrator("backward-euler", options), dt);
    EXPECT_FALSE(sim.advanceTo(0.5));
    if (stats) *stats = sim.integrator().stats();
    return VecX(sim.x());
  };
  const VecX exact = run(1.0 / 60, 1e-12, 0), half = run(1.0 / 120, 1e-12, 0);
  IntegratorStats with_rule, relative_only;
  const VecX fast = run(1.0 / 60, IntegratorOptions{}.cg_tolerance, IntegratorOptions{}.cg_error_fraction, &with_rule);
  run(1.0 / 60, IntegratorOptions{}.cg_tolerance, 0, &relative_only);
  const double method_error = (exact - half).lpNorm<Eigen::Infinity>();
  ASSERT_GT(method_error, 1e-3);  // the step's error is real: the rule has something to measure against
  EXPECT_GT(with_rule.error_rule_stops, 0);
  EXPECT_EQ(relative_only.error_rule_stops, 0);
  EXPECT_LT(with_rule.cg_iterations, relative_only.cg_iterations);
  EXPECT_LT((fast - exact).lpNorm<Eigen::Infinity>(), 0.1 * method_error);
  std::printf("  method error %.3g m, the rule's solve error %.3g m; CG iterations %ld with the rule, %ld without\n",
              method_error, (fast - exact).lpNorm<Eigen::Infinity>(), with_rule.cg_iterations,
              relative_only.cg_iterations);
}

// The error rule's estimate needs smooth motion: it waits for three steps without a contact constraint. A soft cloth
// lying on a sphere has contacts at every step after the first few and gets no early stop; the same cloth with no
// sphere, falling, gets many (so the first count means something).
TEST(BackwardEulerSolver, ErrorRuleWaitsWhileContactsAct) {
  const auto stops = [](bool sphere) {
    auto system = testing::clothOnSphere(12, 2e3);
    if (!sphere) {  // the same cloth alone
      ClothParams p;
      p.nx = p.ny = 12;
      p.ks = 2e3;
      p.pinned = clothPinSet("corners", p.nx, p.ny);
      system = std::make_unique<MassSpringSystem>();
      system->addBody(buildCloth("cloth", p));
    }
    Simulation sim(*system, makeIntegrator("backward-euler"), 1.0 / 240);
    EXPECT_FALSE(sim.advanceTo(0.5));
    return sim.integrator().stats().error_rule_stops;
  };
  EXPECT_EQ(stops(true), 0);
  EXPECT_GT(stops(false), 20);
}

}  // namespace
}  // namespace wobble
