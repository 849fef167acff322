// Convergence orders on smooth problems without contact: the slope of log(error) against log(h) over four halvings
// must be within 0.1 of each method's theoretical order (docs/numerics.md), against two independent
// oracles: the analytic damped oscillator, and a swinging pinned cloth (nonlinear, 25 particles) against a tight rk45
// solve.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "oscillator.h"
#include "sim/bodies/cloth.h"

namespace wobble {
namespace {

using testing::OscillatorState;

struct Expected {
  const char* method;
  double order;
  int coarsest_steps;  // steps over the interval at the coarsest h: enough to be in the asymptotic regime
};

// omega = 2 pi, zeta = 0.1, one period. Errors from the largest h down to h/16.
const Expected kMethods[] = {
    {"explicit-euler", 1, 256}, {"symplectic-euler", 1, 256}, {"pc-euler", 1, 256},
    {"backward-euler", 1, 256}, {"midpoint", 2, 64},          {"rk4", 4, 16},
};

double oscillatorError(const std::string& method, int steps) {
  const double w = 2 * M_PI, zeta = 0.1, t_end = 1;
  const OscillatorState s0{0.1, 0};
  auto system = testing::makeOscillator(w, zeta);
  IntegratorOptions options;
  options.cg_tolerance = 1e-14;  // backward-euler: solve exactly, so only the method's error is measured
  options.cg_error_fraction = 0;
  auto integrator = makeIntegrator(method, options);
  const OscillatorState s = testing::runOscillator(*integrator, *system, s0, t_end / steps, steps);
  const OscillatorState exact = testing::dampedOscillator(w, zeta, s0, t_end);
  return std::hypot(s.x - exact.x, (s.v - exact.v) / w);
}

TEST(Convergence, OrdersOnTheDampedOscillatorMatchTheory) {
  for (const Expected& e : kMethods) {
    std::vector<double> h, error;
    for (int k = 0; k <= 4; ++k) {
      const int steps = e.coarsest_steps << k;
      h.push_back(1.0 / steps);
      error.push_back(oscillatorError(e.method, steps));
    }
    const double order = testing::fittedOrder(h, error);
    EXPECT_NEAR(order, e.order, 0.1) << e.method << ": errors " << error.front() << " .. " << error.back();
    RecordProperty(std::string(e.method) + "_oscillator_order", std::to_string(order));
    std::printf("  %-17s oscillator order %.3f (error %.3g -> %.3g)\n", e.method, order, error.front(), error.back());
  }
}

// A 5 x 5 cloth, 1 m square, horizontal, pinned along one edge, released from rest: it swings down under gravity.
// Soft enough springs that every explicit method is stable at the coarsest step.
std::unique_ptr<MassSpringSystem> swingingCloth() {
  ClothParams p;
  p.nx = p.ny = 5;
  p.size_x = p.size_y = 1;
  p.mass = 0.1;
  p.ks = 100;
  p.kd = 0.5;
  p.drag = 0.01;
  p.pinned = clothPinSet("top-edge", p.nx, p.ny);
  auto system = std::make_unique<MassSpringSystem>();
  system->addBody(buildCloth("cloth", p));
  return system;
}

VecX clothPositionsAt(const MassSpringSystem& system, const std::string& method, const IntegratorOptions& options,
                      int steps, double t_end) {
  auto integrator = makeIntegrator(method, options);
  VecX x = system.initialPositions(), v = system.initialVelocities();
  const double h = t_end / steps;
  for (int i = 0; i < steps; ++i) integrator->step(system, i * h, h, x, v);
  return x;
}

TEST(Convergence, OrdersOnASwingingPinnedClothMatchTheory) {
  const double t_end = 0.5;
  auto system = swingingCloth();
  IntegratorOptions tight;
  tight.rtol = tight.atol = 1e-13;
  tight.cg_tolerance = 1e-14;
  tight.cg_error_fraction = 0;
  const VecX reference = clothPositionsAt(*system, "rk45", tight, 1, t_end);
  // The swing is large: the free edge has dropped by several centimetres at least.
  ASSERT_GT((reference - system->initialPositions()).cwiseAbs().maxCoeff(), 0.05);
  for (const Expected& e : kMethods) {
    std::vector<double> h, error;
    for (int k = 0; k <= 4; ++k) {
      const int steps = e.coarsest_steps << k;
      h.push_back(t_end / steps);
      error.push_back((clothPositionsAt(*system, e.method, tight, steps, t_end) - reference).cwiseAbs().maxCoeff());
    }
    const double order = testing::fittedOrder(h, error);
    EXPECT_NEAR(order, e.order, 0.1) << e.method << ": errors " << error.front() << " .. " << error.back();
    std::printf("  %-17s cloth order %.3f (error %.3g -> %.3g)\n", e.method, order, error.front(), error.back());
  }
}

// DOPRI5 is 5th order: at a fixed number of substeps the global error falls ~2^5 per halving. Its adaptive use is
// checked by tolerance: at rtol 1e-8 the error against the analytic solution is at that level, and it shrinks
// with the tolerance.
TEST(Convergence, Rk45ReachesItsTolerance) {
  const double w = 2 * M_PI, zeta = 0.1, t_end = 2, frame = 0.25;  // long calls: substeps set by the tolerance
  const OscillatorState s0{0.1, 0};
  auto system = testing::makeOscillator(w, zeta);
  std::vector<double> errors;
  for (double tol : {1e-6, 1e-8, 1e-10}) {
    IntegratorOptions options;
    options.rtol = tol;
    options.atol = tol;
    auto integrator = makeIntegrator("rk45", options);
    VecX x, v;
    testing::setOscillatorState(s0, x, v);
    double worst = 0;
    const int frames = static_cast<int>(std::lround(t_end / frame));
    for (int i = 0; i < frames; ++i) {
      integrator->step(*system, i * frame, frame, x, v);
      const OscillatorState s = testing::oscillatorState(x, v);
      const OscillatorState exact = testing::dampedOscillator(w, zeta, s0, (i + 1) * frame);
      worst = std::max(worst, std::max(std::abs(s.x - exact.x), std::abs(s.v - exact.v) / w));
    }
    errors.push_back(worst);
    std::printf("  rk45 tol %.0e: max error %.3g over %ld substeps (%ld rejected), %ld evaluations\n", tol, worst,
                integrator->stats().accepted, integrator->stats().rejected, integrator->stats().evaluations);
  }
  // "Near the tolerance": at most 10x above it (local errors add up over substeps), and not wastefully far below.
  EXPECT_LT(errors[1], 10 * 1e-8);
  EXPECT_GT(errors[1], 1e-8 / 100);
  // Tighter tolerance, smaller error: about tol^(5/6) or better per factor 100.
  EXPECT_LT(errors[1], errors[0] / 10);
  EXPECT_LT(errors[2], errors[1] / 10);
}

}  // namespace
}  // namespace wobble
