// No backward Euler step gains energy at an impact (docs/energy.md, "A step that gains is taken again"): a step
// whose end has more energy than its start is solved exactly, by Newton's iteration with a line search on its
// incremental potential (Gast et al. 2015), and taken again in halves where it still does. Two impacts that gained
// energy at 1/60 s: the default scene's jelly with every spring at ks 1e7 landing on the slope (1.385 times its energy
// in the step after the landing), and a jelly thrown at 150 m/s into a cloth curtain pinned along its top edge (the
// pass between bodies after the step gave it twice its energy in the first step of the impact). Oracle: the total
// energy (kinetic, gravitational, elastic), recomputed from the state at every step's end, never rises above the
// start's by more than kStepEnergyMargin (1%) of it, the rounding a step is allowed (sim/system.h): nothing moves a
// collider or a pin, so nothing gives the bodies energy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/plane.h"
#include "sim/simulation.h"
#include "tests/sim/folded_cloth.h"
#include "tests/sim/point_masses.h"

namespace wobble {
namespace {

constexpr double kStep = 1.0 / 60;

struct Outcome {
  double start = 0, highest = 0;  // J: the total energy at the start, and the highest at any step's end
  bool finished = false;
  std::string stopped;  // the blow-up's or the energy check's message
  long retakes = 0, exact_steps = 0;
};

Outcome run(MassSpringSystem& system, double duration, const IntegratorOptions& options = {}) {
  Simulation sim(system, makeIntegrator("backward-euler", options), kStep);
  Outcome r;
  r.start = r.highest = system.energy(sim.x(), sim.v());
  sim.observeSteps([&](double, const VecX&) { r.highest = std::max(r.highest, system.energy(sim.x(), sim.v())); });
  for (int frame = 1; frame * kStep <= duration + 1e-9; ++frame) {
    if (const auto blow_up = sim.advanceTo(frame * kStep)) {
      r.stopped = blow_up->message(kStep);
      return r;
    }
    if (sim.energyGain()) {
      r.stopped = sim.energyGain()->message(kStep);
      return r;
    }
  }
  r.finished = true;
  r.retakes = sim.energyRetakes();
  r.exact_steps = sim.integrator().stats().exact_steps;
  return r;
}

// scenes/jelly_slope.toml (the default scene) with every spring at ks 1e7: the 10^3 jelly lands on the slope at step
// 67 (1.1 s); the step after it went from 75.7 kJ to 205 kJ. 1.6 s: the landing and the tumble after it.
TEST(BackwardEulerEnergy, StiffJellyLandingOnTheSlopeGainsNothing) {
  MassSpringSystem system;
  system.addBody(buildJelly("jelly", JellyParams{.n = 10, .size = 4, .mass = 1, .ks = 1e7, .kd = 50}));
  system.addCollider(std::make_unique<PlaneCollider>("slope", ContactParams{0.8, 0.5, 0.01}, Vec3::Zero(),
                                                     Vec3(0.3420201433256687, 0.9396926207859084, 0)));
  const Outcome r = run(system, 1.6);
  EXPECT_TRUE(r.finished) << r.stopped;
  EXPECT_LE(r.highest, r.start * (1 + kStepEnergyMargin))
      << "the total energy rose from " << r.start << " J to " << r.highest << " J";
  EXPECT_GT(r.exact_steps, 0);  // the landing's steps were solved exactly: the case is the one it was
}

// A 4^3 jelly (3.2 kg, turned 20 degrees) thrown at 150 m/s into a 20 x 20 cloth curtain 2 m wide pinned along its
// top edge (jelly_trampoline's materials), from 2.35 m in front of it: 36 kJ of kinetic energy, 2.5 m a step. The first
// step went from 36 kJ to 176 kJ (the pass between bodies after the solve); at 120 m/s it did not gain.
TEST(BackwardEulerEnergy, JellyThrownAt150MetresASecondIntoACurtainGainsNothing) {
  MassSpringSystem system;
  ClothParams cloth{.nx = 20,
                    .ny = 20,
                    .size_x = 2,
                    .size_y = 2,
                    .center = Vec3(0, 1, 0),
                    .hanging = true,
                    .mass = 0.02,
                    .ks = 1500,
                    .kd = 3,
                    .drag = 0.1};
  cloth.pinned = clothPinSet("top-edge", cloth.nx, cloth.ny);
  system.addBody(buildCloth("curtain", cloth));
  system.addBody(buildJelly("jelly", JellyParams{.n = 4,
                                                 .size = 0.5,
                                                 .mass = 0.05,
                                                 .ks = 1500,
                                                 .kd = 3,
                                                 .center = Vec3(0.1, 1.1, 2.6),
                                                 .rotation_axis = Vec3::UnitY(),
                                                 .rotation_deg = 20,
                                                 .velocity = Vec3(0, 0, -150)}));
  const Outcome r = run(system, 0.5);
  EXPECT_TRUE(r.finished) << r.stopped;
  EXPECT_LE(r.highest, r.start * (1 + kStepEnergyMargin))
      << "the total energy rose from " << r.start << " J to " << r.highest << " J";
}

// Newton's iteration keeps the pairs its iterates press (docs/energy.md, "A step that gains is taken again"): a 50 x 50
// cloth laid in four layers half a spacing apart (body_contact_bench's stacked cloth) drops 1 cm onto a floor under
// backward Euler at 1/60 s. Its landing steps are solved exactly, and Newton moves each step's end away from the
// linearized solves'; a pair the end then presses that the active set does not hold was left to the pass after the
// step, whose impulses on the surface alone gave the stack 0.4 J in one step (at 100 x 100 0.52 J, 70% of its energy;
// the step was retaken). Oracle: the pass's continuous collision detection over every step of the landing finds
// nothing to stop (an independent check that the solve's ends cross no surface).
TEST(BackwardEulerEnergy, ExactStepsOfALandingStackLeaveNoCollisionToThePass) {
  const auto system = testing::foldedCloth(50, true, 4, 0.5, 0);
  IntegratorOptions options;
  options.cg_max_iterations = 20000;
  Simulation sim(*system, makeIntegrator("backward-euler", options), kStep);
  ASSERT_FALSE(sim.advanceTo(0.25));
  EXPECT_GT(sim.integrator().stats().exact_steps, 0);  // the landing was solved exactly: the case is the one it was
  EXPECT_EQ(sim.bodyContact()->ccd_hits, 0);
  EXPECT_EQ(sim.bodyContact()->zone_activations, 0);
}

// The line search alone (no Simulation: no retake, no energy check). A 1 kg particle on a stiff spring (rest 1 m, ks
// 1e5 N/m, no damper, no gravity) pinned at the origin, released stretched to 1.5 m at 100 m/s, 120 degrees from the
// spring's direction; backward Euler with newton at 1/60 s, its iteration capped at n linear solves (the linearized
// solve, then n - 1 Newton steps). From the linearized step's end a full Newton step overshoots: it raises the step's
// incremental potential and ends with 1.5 times the start's energy (a model of the iteration in double precision gives
// the same), while the step halved until the potential falls (Armijo) ends with a fifth of it. Oracles, computed here
// from the state alone: the incremental potential Phi(x1) = m |x1 - x0 - h v0|^2 / (2 h^2) + ks (|x1| - 1)^2 / 2 never
// rises from one cap to the next (each Newton step taken lowers it), and the energy m |v1|^2 / 2 + ks (|x1| - 1)^2 / 2
// at the step's end is never above the start's.
TEST(BackwardEulerEnergy, LineSearchKeepsAnOvershootingNewtonStepFromGainingEnergy) {
  constexpr double kMass = 1, kStiffness = 1e5, kRest = 1, kAngle = 2 * M_PI / 3;
  MassSpringSystem system(Vec3::Zero());
  Body body = testing::anchoredSpring(kRest, 0.5, 0, kStiffness, 0, kMass);
  particle(body.v, 1) = 100 * Vec3(std::cos(kAngle), std::sin(kAngle), 0);
  system.addBody(std::move(body));
  const VecX x0 = system.initialPositions(), v0 = system.initialVelocities();
  const auto energy = [&](const VecX& x, const VecX& v) {
    return 0.5 * kMass * particle(v, 1).squaredNorm() + 0.5 * kStiffness * std::pow(particle(x, 1).norm() - kRest, 2);
  };
  const auto phi = [&](const VecX& x1) {
    const Vec3 inertia = particle(x1, 1) - particle(x0, 1) - kStep * particle(v0, 1);
    return kMass * inertia.squaredNorm() / (2 * kStep * kStep) +
           0.5 * kStiffness * std::pow(particle(x1, 1).norm() - kRest, 2);
  };
  const double start = energy(x0, v0);
  double last_phi = INFINITY;
  for (int solves = 1; solves <= 6; ++solves) {
    IntegratorOptions options;
    options.newton = true;
    options.newton_max_iterations = solves;
    VecX x = x0, v = v0;
    makeIntegrator("backward-euler", options)->step(system, 0, kStep, x, v);
    ASSERT_TRUE(x.allFinite() && v.allFinite()) << solves << " solves";
    EXPECT_LE(phi(x), last_phi * (1 + 1e-12)) << solves << " solves: the Newton step raised the incremental potential";
    EXPECT_LE(energy(x, v), start * (1 + 1e-9)) << solves << " solves: the step gained energy";
    last_phi = phi(x);
  }
}

}  // namespace
}  // namespace wobble
