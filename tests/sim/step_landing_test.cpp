// Simulation::advanceTo lands on the requested times with whole steps of dt, the last one shortened only when the
// interval is not a whole number of steps: round-off in summing steps never adds a sliver step.
#include <gtest/gtest.h>

#include "point_masses.h"

namespace wobble {
namespace {

long stepsFor(double dt, double fps, double duration) {
  MassSpringSystem system;
  system.addBody(testing::particles({Vec3(0, 1, 0)}));
  Simulation sim(system, makeIntegrator("symplectic-euler"), dt);
  const long frames = std::lround(duration * fps);
  for (long k = 1; k <= frames; ++k) {
    EXPECT_FALSE(sim.advanceTo(double(k) / fps));
    EXPECT_EQ(sim.time(), double(k) / fps);
  }
  return sim.steps();
}

TEST(StepLanding, ThreeSecondsAtATenThousandthAreThirtyThousandSteps) {
  EXPECT_EQ(stepsFor(1e-4, 1.0 / 3, 3), 30000);  // one call to t = 3
  EXPECT_EQ(stepsFor(1e-4, 50, 3), 30000);       // frame by frame, 200 steps a frame
  EXPECT_EQ(stepsFor(1e-3, 60, 3), 3060);        // 16.67 steps a frame: 17 each, the last one shortened
  EXPECT_EQ(stepsFor(0.1, 60, 1), 60);           // a step longer than a frame: one (short) step per frame
}

}  // namespace
}  // namespace wobble
