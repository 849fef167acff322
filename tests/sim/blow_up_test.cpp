// The course framework's blow-up rule (NaN, or any |v|^2 > 1e6) stops the run at the step where it happens.
#include <gtest/gtest.h>

#include "point_masses.h"

namespace wobble {
namespace {

TEST(BlowUp, ExplicitEulerOnAStiffSpringIsCaughtAtOnce) {
  // omega h = sqrt(1e6) * 0.01 = 10: explicit Euler multiplies the amplitude by ~10 per step.
  MassSpringSystem system(Vec3::Zero());
  system.addBody(testing::anchoredSpring(1, 0.01, 0, 1e6, 0));
  Simulation sim(system, makeIntegrator("explicit-euler"), 0.01);
  const auto blow_up = sim.advanceTo(10.0);
  ASSERT_TRUE(blow_up);
  EXPECT_EQ(blow_up->integrator, "explicit-euler");
  EXPECT_EQ(blow_up->particle, 1);
  EXPECT_GT(blow_up->speed_squared, kBlowUpSpeedSquared);
  EXPECT_EQ(sim.steps(), blow_up->step);  // stopped at once
  EXPECT_LT(blow_up->step, 20);
  EXPECT_NEAR(blow_up->time, blow_up->step * 0.01, 1e-12);
  const std::string message = blow_up->message(0.01);
  for (const char* part : {"explicit-euler", "step", "t = ", "--dt", "--integrator"})
    EXPECT_NE(message.find(part), std::string::npos) << message;
}

TEST(BlowUp, Rk4SurvivesWhereExplicitEulerBlowsUp) {
  MassSpringSystem system(Vec3::Zero());
  system.addBody(testing::anchoredSpring(1, 0.01, 0, 1e4, 0));  // omega h = 100 * 0.02 = 2 < 2.83
  Simulation sim(system, makeIntegrator("rk4"), 0.02);
  EXPECT_FALSE(sim.advanceTo(10.0));
}

TEST(Simulation, LastStepLandsExactlyOnTheRequestedTime) {
  MassSpringSystem system;
  system.addBody(testing::particles({Vec3::Zero()}));
  Simulation sim(system, makeIntegrator("rk4"), 0.001);
  ASSERT_FALSE(sim.advanceTo(1.0 / 30));  // 33 full steps and one of 1/3 ms
  EXPECT_EQ(sim.time(), 1.0 / 30);
  EXPECT_EQ(sim.steps(), 34);
  EXPECT_NEAR(sim.x()[1], -0.5 * 9.8 / 900, 1e-15);
}

}  // namespace
}  // namespace wobble
