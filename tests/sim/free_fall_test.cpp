// Free fall per integrator against the exact discretization errors of docs/numerics.md, and the jelly
// falling exactly as a point mass does while keeping its shape (the course frameworks' "slow-motion RK4" and "lost
// corner" bugs).
#include <gtest/gtest.h>

#include "point_masses.h"
#include "sim/bodies/jelly.h"

namespace wobble {
namespace {

constexpr double kG = 9.8, kH = 0.01, kT = 1.0;

double fallHeightError(const std::string& method) {
  MassSpringSystem system;
  system.addBody(testing::particles({Vec3(0, 100, 0)}));
  Simulation sim(system, makeIntegrator(method), kH);
  EXPECT_FALSE(sim.advanceTo(kT));
  EXPECT_EQ(sim.steps(), 100);
  return sim.x()[1] - (100 - 0.5 * kG * kT * kT);
}

TEST(FreeFall, ExplicitEulerIsHighByHalfGTH) {
  EXPECT_NEAR(fallHeightError("explicit-euler"), kG * kT * kH / 2, 1e-10);
}
// The predictor-corrector applies the predicted velocity, so on constant forces it equals symplectic Euler.
TEST(FreeFall, PredictorCorrectorIsLowByHalfGTH) { EXPECT_NEAR(fallHeightError("pc-euler"), -kG * kT * kH / 2, 1e-10); }
TEST(FreeFall, MidpointIsExact) { EXPECT_NEAR(fallHeightError("midpoint"), 0, 1e-11); }
TEST(FreeFall, Rk4IsExact) { EXPECT_NEAR(fallHeightError("rk4"), 0, 1e-11); }

class JellyFreeFall : public ::testing::TestWithParam<std::string> {};

TEST_P(JellyFreeFall, FallsAsAPointMassAndKeepsItsShape) {
  MassSpringSystem system;
  system.addBody(buildJelly("j", {.n = 5, .ks = 1000, .kd = 50, .rotation_deg = 30, .velocity = Vec3(1, 2, 0)}));
  const double h = 0.001, t = 1.0;
  Simulation sim(system, makeIntegrator(GetParam()), h);
  ASSERT_FALSE(sim.advanceTo(t));
  const int n = system.particleCount();
  // Every particle moves by the same displacement as a point mass under the same integrator.
  MassSpringSystem point;
  point.addBody(testing::particles({Vec3::Zero()}, Vec3(1, 2, 0)));
  Simulation reference(point, makeIntegrator(GetParam()), h);
  ASSERT_FALSE(reference.advanceTo(t));
  const Vec3 expected = reference.x().head<3>();
  double worst = 0;
  for (int i = 0; i < n; ++i)
    worst = std::max(worst, (particle(sim.x(), i) - particle(system.initialPositions(), i) - expected).norm());
  // Backward Euler solves its linear system iteratively (CG to a relative residual of 1e-6), the others are exact.
  const bool iterative = GetParam() == "backward-euler";
  EXPECT_LT(worst, iterative ? 1e-6 : 1e-9);
  EXPECT_LT(maxStrain(system.springs(), sim.x()), iterative ? 1e-8 : 1e-10);
  if (GetParam() == "rk4" || GetParam() == "midpoint") {  // exact on constant acceleration, so no "slow motion"
    EXPECT_NEAR(expected.y(), 2 * t - 0.5 * 9.8 * t * t, 1e-10);
  }
}

INSTANTIATE_TEST_SUITE_P(AllIntegrators, JellyFreeFall,
                         ::testing::ValuesIn(std::vector<std::string>(integratorNames().begin(),
                                                                      integratorNames().end())),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace wobble
