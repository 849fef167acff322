// Contact between bodies never adds energy (docs/energy.md, docs/body-contact.md). Oracles: the conservation laws.
// Two jellies thrown at each other without gravity or colliders, under every integrator at a step it is stable at:
// the only forces besides contact are springs and dampers, so the total energy (kinetic + elastic) after the impact
// is at most what it was before it, and the total momentum stays what it was (contact forces and impulses act in
// equal and opposite pairs). And the two did meet and did not pass through each other.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/bodies/jelly.h"
#include "sim/simulation.h"
#include "tests/sim/momentum.h"
#include "tests/sim/triangle_intersection.h"

namespace wobble {
namespace {

// Energy may rise by this fraction of the energy before the impact: the integrators' own drift over the run (explicit
// Euler's is about 1e-4 of it at 1e-4 s); the impulses of the post-step pass alone gained 13-16% on the shipped
// scenes under backward Euler before the contacts went into its solve.
constexpr double kImpactTolerance = 0.01;

struct Case {
  const char* integrator;
  double dt;
  // Of the momentum's change, relative to the sum of |m v|: rounding for the explicit methods; backward Euler's linear
  // solve stops at a relative residual of 1e-3 (its cg_tolerance), whose net force its rigid-mode correction removes
  // while the bodies touch (docs/body-contact.md, "Momentum"): 0.1%.
  double momentum_tolerance = 1e-9;
};

Vec3 centroid(const MassSpringSystem& system, const VecX& x, int body) {
  const BodySlot& slot = system.bodies()[body];
  Vec3 c = Vec3::Zero();
  for (int i = 0; i < slot.body.particleCount(); ++i) c += particle(x, slot.first + i);
  return c / slot.body.particleCount();
}

// A 4^3 jelly (ks 2000, as the collider-impact test's) at 2 m/s into another at -2 m/s, the second turned so that
// an edge meets a face off-centre: both bodies spin off after the impact.
void jellyOnJelly(const Case& c) {
  MassSpringSystem system(Vec3::Zero());
  JellyParams a{.n = 4, .size = 1, .ks = 2000, .kd = 5, .center = Vec3(-0.8, 0, 0), .velocity = Vec3(2, 0, 0)};
  system.addBody(buildJelly("left", a));
  JellyParams b = a;
  b.center = Vec3(0.9, 0.25, 0.1);
  b.velocity = Vec3(-2, 0, 0);
  b.rotation_axis = Vec3(0, 1, 0.3);
  b.rotation_deg = 35;
  system.addBody(buildJelly("right", b));
  testing::ParticleTriangles tris;
  for (std::size_t k = 0; k < system.bodies().size(); ++k)
    testing::addSurface(tris, system.bodies()[k].body.surface, system.bodies()[k].first, int(k));
  Simulation sim(system, makeIntegrator(c.integrator), c.dt);
  ASSERT_TRUE(sim.bodyContact());
  const double before = system.energy(sim.x(), sim.v());
  const Vec3 p0 = testing::momentum(system, sim.v());
  const double p_scale = 2.0 * system.mass().sum();  // |m v| summed over both bodies
  int worst = 0;
  for (int frame = 1; frame <= 30; ++frame) {  // 0.6 s: meet at about 0.1 s, apart by the end
    ASSERT_FALSE(sim.advanceTo(frame * 0.02)) << c.integrator;
    worst = std::max(worst, testing::intersectingPairs(tris, sim.x()));
  }
  const double after = system.energy(sim.x(), sim.v());
  EXPECT_LE(after, before * (1 + kImpactTolerance))
      << c.integrator << ": the impact took the energy from " << before << " J to " << after << " J";
  EXPECT_LT((testing::momentum(system, sim.v()) - p0).norm(), c.momentum_tolerance * p_scale) << c.integrator;
  EXPECT_EQ(worst, 0) << c.integrator;
  // They met (contact was found) and bounced apart: the left one is still left of the right one, moving left.
  const collision::Stats& s = *sim.bodyContact();
  EXPECT_GT(s.contacts + s.ccd_hits + sim.integrator().stats().body_contact_pairs, 0) << c.integrator;
  EXPECT_LT(centroid(system, sim.x(), 0).x(), centroid(system, sim.x(), 1).x()) << c.integrator;
  Vec3 left_v = Vec3::Zero();
  for (int i = 0; i < system.bodies()[0].body.particleCount(); ++i) left_v += particle(sim.v(), i);
  EXPECT_LT(left_v.x(), 0) << c.integrator << ": the left jelly did not bounce back";
  EXPECT_FALSE(sim.energyGain()) << sim.energyGain()->message(c.dt);
}

class BodyImpactEnergy : public ::testing::TestWithParam<Case> {};

TEST_P(BodyImpactEnergy, JellyOnJellyNeverGains) { jellyOnJelly(GetParam()); }

// Each integrator at a step it is stable at on these jellies (omega_max about 130 /s): the Euler family needs small
// steps, RK4 and midpoint a millisecond, backward Euler takes 1/60 s (and 1/120 s). rk45 adapts its substeps inside
// 1/240 s: the pass after the step runs once a step, and at 1/60 s its impulses, moving the touching particles alone
// by h times their velocity change, triple the energy (docs/body-contact.md, "Limits").
INSTANTIATE_TEST_SUITE_P(EveryIntegrator, BodyImpactEnergy,
                         ::testing::Values(Case{"explicit-euler", 1e-4}, Case{"symplectic-euler", 1e-4},
                                           Case{"pc-euler", 1e-4}, Case{"midpoint", 1e-3}, Case{"rk4", 1e-3},
                                           Case{"rk45", 1.0 / 240}, Case{"backward-euler", 1.0 / 60, 1e-3},
                                           Case{"backward-euler", 1.0 / 120, 1e-3}),
                         [](const auto& info) {
                           std::string name = std::string(info.param.integrator) + "_" +
                                              std::to_string(int(std::lround(1 / info.param.dt)));
                           for (char& ch : name)
                             if (ch == '-') ch = '_';
                           return name;
                         });

}  // namespace
}  // namespace wobble
