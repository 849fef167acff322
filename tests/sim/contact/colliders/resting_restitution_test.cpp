// Resting contact on a bouncy floor (contact/colliders/response.h; docs/body-contact.md, "Rest"): a jelly that has
// landed on a floor of restitution 0.5 comes to rest under every integrator (RK4 and backward Euler at 1/60 s and
// 1/240 s, symplectic Euler and midpoint at 1/240 s): only the approach a particle brings into a step bounces. A floor
// that gave each loaded particle within its band the restitution of its approach at every step's end, however slow,
// would give the approach a step's load adds (a h) back as e a h, and the jelly's bottom would hop for ever. Oracle:
// the speeds themselves (every particle, over every step of the last half second). And a real impact still bounces: the
// particle's apex after a bounce at these steps is e^2 times its drop (Contact.BounceIsTheSameUnderEveryIntegrator
// covers 1e-4 s).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>

#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/plane.h"
#include "sim/simulation.h"
#include "tests/sim/point_masses.h"

namespace wobble {
namespace {

struct Case {
  const char* integrator;
  double dt;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.integrator << " at 1/" << std::lround(1 / c.dt) << " s"; }
std::string caseName(const ::testing::TestParamInfo<Case>& info) {
  std::string name = std::string(info.param.integrator) + "_" + std::to_string(std::lround(1 / info.param.dt));
  for (char& ch : name)
    if (ch == '-') ch = '_';
  return name;
}

class RestingRestitution : public ::testing::TestWithParam<Case> {};

TEST_P(RestingRestitution, JellyOnABouncyFloorComesToRest) {
  const Case c = GetParam();
  MassSpringSystem system;
  // The soft jelly of the rest tests (tests/sim/jelly_column.h), dropped 5 cm.
  system.addBody(
      buildJelly("jelly", {.n = 3, .size = 0.5, .mass = 0.05, .ks = 100, .kd = 0.5, .center = Vec3(0, 0.3, 0)}));
  system.addCollider(
      std::make_unique<PlaneCollider>("floor", ContactParams{0.5, 0.6, 0.01}, Vec3::Zero(), Vec3::UnitY()));
  Simulation sim(system, makeIntegrator(c.integrator), c.dt);
  constexpr double kFrame = 1.0 / 60;
  double speed = 0;  // the largest particle speed over the last half second's steps
  for (int frame = 1; frame <= 4 * 60; ++frame) {
    ASSERT_FALSE(sim.advanceTo(frame * kFrame)) << c.integrator;
    if (frame > int(3.5 * 60)) speed = std::max(speed, sim.lastIntervalMaxSpeed());
  }
  // At rest: 0.01 m/s (measured: 0). Every approach bouncing, the floor kept the jelly hopping at 0.14 m/s under RK4
  // at 1/60 s and 0.03-0.05 m/s at 1/240 s.
  EXPECT_LT(speed, 0.01) << c.integrator << " at 1/" << 1 / c.dt << " s";
  std::printf("%s 1/%g s: largest particle speed over the last 0.5 s of 4 s %.5f m/s\n", c.integrator, 1 / c.dt, speed);
}

TEST_P(RestingRestitution, ParticleBouncesToRestitutionSquaredItsDrop) {
  const Case c = GetParam();
  const double e = 0.8, drop = 1.0;
  MassSpringSystem system;
  system.addBody(testing::particles({Vec3(0, drop, 0)}));
  system.addCollider(std::make_unique<PlaneCollider>("floor", ContactParams{e, 0, 0.01}, Vec3::Zero(), Vec3::UnitY()));
  Simulation sim(system, makeIntegrator(c.integrator), c.dt);
  double apex = 0;
  bool bounced = false;
  while (sim.time() < 1.3) {
    ASSERT_FALSE(sim.advanceTo(sim.time() + c.dt));
    bounced |= sim.v()[1] > 0;
    if (bounced) apex = std::max(apex, sim.x()[1]);
  }
  ASSERT_TRUE(bounced) << c.integrator;
  // Tolerance: the bounce is taken anywhere in the 0.01 m band and at a step's end, where the fall has gained up to
  // g h (0.16 m/s at 1/60 s of the 4.4 m/s impact: 7% of the apex), and the explicit Euler methods' flight errs by h
  // g t.
  EXPECT_NEAR(apex, e * e * drop, 0.1 * e * e * drop) << c.integrator;
}

INSTANTIATE_TEST_SUITE_P(Floor, RestingRestitution,
                         ::testing::Values(Case{"rk4", 1.0 / 60}, Case{"rk4", 1.0 / 240},
                                           Case{"symplectic-euler", 1.0 / 240}, Case{"midpoint", 1.0 / 240},
                                           Case{"backward-euler", 1.0 / 60}, Case{"backward-euler", 1.0 / 240}),
                         caseName);

}  // namespace
}  // namespace wobble
