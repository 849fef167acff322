// A particle on a damped spring against the analytic solution of the damped harmonic oscillator.
#include <gtest/gtest.h>

#include <cmath>

#include "point_masses.h"

namespace wobble {
namespace {

// x(t) = exp(-zeta w t) [x0 cos(wd t) + (v0 + zeta w x0)/wd sin(wd t)]
double analytic(double x0, double v0, double w, double zeta, double t) {
  const double wd = w * std::sqrt(1 - zeta * zeta);
  return std::exp(-zeta * w * t) * (x0 * std::cos(wd * t) + (v0 + zeta * w * x0) / wd * std::sin(wd * t));
}

TEST(DampedOscillator, Rk4MatchesAnalyticSolution) {
  const double m = 2, ks = 50, kd = 1, rest = 1, x0 = 0.1, v0 = -0.3;
  const double w = std::sqrt(ks / m), zeta = kd / (2 * std::sqrt(ks * m));
  MassSpringSystem system(Vec3::Zero());
  system.addBody(testing::anchoredSpring(rest, x0, v0, ks, kd, m));
  Simulation sim(system, makeIntegrator("rk4"), 1e-3);
  double worst = 0;
  for (int k = 1; k <= 300; ++k) {
    const double t = k * 0.01;
    ASSERT_FALSE(sim.advanceTo(t));
    worst = std::max(worst, std::abs(sim.x()[3] - rest - analytic(x0, v0, w, zeta, t)));
    EXPECT_EQ(sim.x().segment<3>(0), Vec3::Zero());  // the anchor is pinned
  }
  EXPECT_LT(worst, 1e-10);
}

}  // namespace
}  // namespace wobble
