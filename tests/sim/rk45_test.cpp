// rk45 (Dormand-Prince 5(4), dopri5 control) as a step(t, h) integrator: it lands exactly on t + h, carries its step
// size and FSAL derivative across calls, counts its work, is 5th order, and refuses to loop forever.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "oscillator.h"

namespace wobble {
namespace {

using testing::OscillatorState;

// y'' = -y as a Dynamics of one particle (x component), so exact values are cos/sin.
struct Harmonic final : Dynamics {
  void acceleration(double, const VecX& x, const VecX&, VecX& a) const override { a = -x; }
};

// x'' = t: x = t^3 / 6 from rest, a cubic, which a 5th-order method integrates exactly. Any error in x at the end
// of a call is an error in where the call landed.
struct Ramp final : Dynamics {
  void acceleration(double t, const VecX& x, const VecX&, VecX& a) const override { a = VecX::Constant(x.size(), t); }
};

// Never finite: every substep is rejected until the step size underflows.
struct Broken final : Dynamics {
  void acceleration(double, const VecX& x, const VecX&, VecX& a) const override {
    a = VecX::Constant(x.size(), std::numeric_limits<double>::quiet_NaN());
  }
};

TEST(Rk45, CountsItsWorkAndReusesTheLastDerivative) {
  IntegratorOptions options;
  options.rtol = options.atol = 1e-8;
  auto integrator = makeIntegrator("rk45", options);
  EXPECT_EQ(integrator->name(), "rk45");
  VecX x = VecX::Zero(3), v = VecX::Zero(3);
  x[0] = 1;
  Harmonic dynamics;
  for (int i = 0; i < 10; ++i) integrator->step(dynamics, 0.25 * i, 0.25, x, v);
  const IntegratorStats& s = integrator->stats();
  EXPECT_EQ(s.steps, 10);
  EXPECT_GT(s.accepted, 10);  // several substeps per call at this tolerance
  // 6 evaluations per attempted substep (first same as last), plus one start and one for the initial step guess;
  // no re-evaluation between calls, since nothing changed the state in between.
  EXPECT_EQ(s.evaluations, 6 * (s.accepted + s.rejected) + 2);
  EXPECT_NEAR(x[0], std::cos(2.5), 1e-7);
  EXPECT_NEAR(v[0], -std::sin(2.5), 1e-7);
  // A state changed between calls (as contact resolution does) is not mistaken for the cached one.
  const long before = s.evaluations, substeps = s.accepted + s.rejected;
  v[0] += 0.1;
  integrator->step(dynamics, 2.5, 0.25, x, v);
  EXPECT_EQ(s.evaluations - before, 6 * (s.accepted + s.rejected - substeps) + 1);
}

TEST(Rk45, LandsExactlyOnTheEndOfEachStepAndCarriesItsStepSize) {
  auto integrator = makeIntegrator("rk45");
  VecX x = VecX::Zero(3), v = VecX::Zero(3);
  Ramp dynamics;
  // The first call starts from the initial guess (tiny here: the state is at rest) and grows the substep.
  integrator->step(dynamics, 0, 0.3, x, v);
  EXPECT_GT(integrator->stats().accepted, 1);
  EXPECT_NEAR(x[0], std::pow(0.3, 3) / 6, 1e-15);
  // Later calls start from the carried substep (large: the local error is round-off), one substep each.
  double t = 0.3;
  for (double h : {0.1, 0.25, 0.05, 1.0 / 3}) {
    const long accepted = integrator->stats().accepted;
    integrator->step(dynamics, t, h, x, v);
    t += h;
    EXPECT_EQ(integrator->stats().accepted - accepted, 1) << h;
    EXPECT_NEAR(x[0], t * t * t / 6, 1e-14) << t;
    EXPECT_NEAR(v[0], t * t / 2, 1e-14) << t;
  }
  EXPECT_EQ(integrator->stats().rejected, 0);
}

TEST(Rk45, IsFifthOrderAtAFixedNumberOfSubsteps) {
  // With tolerances so loose that every substep is accepted and clipped to the call's interval, rk45 is plain
  // DOPRI5 at a fixed step: the error falls ~2^5 per halving.
  IntegratorOptions options;
  options.rtol = options.atol = 1e3;
  auto system = testing::makeOscillator(2 * M_PI, 0.1);
  const OscillatorState s0{0.1, 0};
  std::vector<double> h, error;
  for (int steps : {16, 32, 64, 128}) {
    auto integrator = makeIntegrator("rk45", options);
    const OscillatorState s = testing::runOscillator(*integrator, *system, s0, 1.0 / steps, steps);
    EXPECT_EQ(integrator->stats().accepted, steps);
    const OscillatorState exact = testing::dampedOscillator(2 * M_PI, 0.1, s0, 1);
    h.push_back(1.0 / steps);
    error.push_back(std::hypot(s.x - exact.x, (s.v - exact.v) / (2 * M_PI)));
  }
  const double order = testing::fittedOrder(h, error);
  std::printf("  rk45 fixed-step order %.3f (error %.3g -> %.3g)\n", order, error.front(), error.back());
  EXPECT_NEAR(order, 5, 0.1);
}

TEST(Rk45, GivesUpInsteadOfLoopingForever) {
  VecX x = VecX::Ones(3), v = VecX::Zero(3);
  {
    auto integrator = makeIntegrator("rk45");
    EXPECT_THROW(integrator->step(Broken{}, 0, 0.1, x, v), std::runtime_error);
    EXPECT_THROW(integrator->step(Harmonic{}, 0, 0, x, v), std::invalid_argument);
    EXPECT_THROW(integrator->step(Harmonic{}, 0, -1, x, v), std::invalid_argument);
  }
  {
    IntegratorOptions options;
    options.rtol = options.atol = 1e-12;
    options.max_substeps = 10;
    auto integrator = makeIntegrator("rk45", options);
    x = VecX::Ones(3);
    try {
      integrator->step(Harmonic{}, 0, 100, x, v);
      ADD_FAILURE() << "expected std::runtime_error";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("max_substeps"), std::string::npos) << e.what();
    }
  }
  IntegratorOptions bad;
  bad.rtol = bad.atol = 0;
  EXPECT_THROW(makeIntegrator("rk45", bad), std::invalid_argument);
}

}  // namespace
}  // namespace wobble
