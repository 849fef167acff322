// Under backward Euler the contacts are inside the solve, and the pass after the step (continuous detection, impulses,
// impact zones: sim/contact/) is what still guarantees that no surface ends a step through another. A jelly thrown
// fast at another, at a step long enough that it covers its own size, is a case the solve alone leaves crossing.
// Oracle: the independent triangle-triangle test (tests/sim/triangle_intersection.h) at every step's end.
#include <gtest/gtest.h>

#include "sim/bodies/jelly.h"
#include "sim/simulation.h"
#include "tests/sim/triangle_intersection.h"

namespace wobble {
namespace {

struct Case {
  double speed;  // m/s, each jelly, towards the other
  double dt;
};

class BackwardEulerPass : public ::testing::TestWithParam<Case> {};

TEST_P(BackwardEulerPass, NoJellyEndsAStepThroughAnotherAtAnyStep) {
  const Case c = GetParam();
  MassSpringSystem system(Vec3::Zero());
  JellyParams a{.n = 3, .size = 0.4, .ks = 3000, .kd = 5, .center = Vec3(-0.6, 0, 0), .velocity = Vec3(c.speed, 0, 0)};
  system.addBody(buildJelly("left", a));
  // Turned so that an edge meets a face off-centre.
  const JellyParams b{.n = 3,
                      .size = 0.4,
                      .ks = 3000,
                      .kd = 5,
                      .center = Vec3(0.6, 0.1, 0.05),
                      .rotation_axis = Vec3(0, 1, 0.3),
                      .rotation_deg = 35,
                      .velocity = Vec3(-c.speed, 0, 0)};
  system.addBody(buildJelly("right", b));
  testing::ParticleTriangles tris;
  for (std::size_t k = 0; k < system.bodies().size(); ++k)
    testing::addSurface(tris, system.bodies()[k].body.surface, system.bodies()[k].first, int(k));
  Simulation sim(system, makeIntegrator("backward-euler"), c.dt);
  for (int k = 1; k <= 20; ++k) {
    ASSERT_FALSE(sim.advanceTo(k * c.dt)) << "step " << k;
    std::vector<std::array<int, 2>> pairs;
    testing::intersectingPairs(tris, sim.x(), &pairs);
    int crossing = 0;  // between the two bodies: a jelly has no self-contact, and one crushed this hard may fold
    for (const auto& [i, j] : pairs) crossing += tris.body[i] != tris.body[j];
    ASSERT_EQ(crossing, 0) << "step " << k << " at " << c.speed << " m/s, dt " << c.dt;
  }
  EXPECT_GT(sim.integrator().stats().body_contact_pairs, 0);  // they met, in the solve
}

// Without the pass these end steps with 6, 10 and 37 triangle pairs of the two jellies through each other.
INSTANTIATE_TEST_SUITE_P(FastImpacts, BackwardEulerPass,
                         ::testing::Values(Case{10, 1.0 / 60}, Case{5, 1.0 / 30}, Case{30, 1.0 / 60}));

}  // namespace
}  // namespace wobble
