// The energy backward Euler's contact between bodies is held to (docs/energy.md, "What counts as energy"): the pairs'
// penalty is a potential within a step only (each step takes its normal, weights and rest gap afresh from its start:
// backward_euler_pairs.h), so the energy the run's checks and the tests count, Simulation::countedEnergy, is the
// system's total less the work the penalty's forces did on the bodies. Oracle: energy conservation. A jelly without
// dampers or friction dropped onto a pinned jelly, loading the pairs at the landing and unloading them as it springs
// back and rests: nothing else gives the bodies energy, so the counted energy may only fall, at every step, to within
// the linear solve's tolerance; the system's total alone rises as the pairs unload.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "sim/bodies/jelly.h"
#include "sim/simulation.h"

namespace wobble {
namespace {

class PairEnergy : public ::testing::TestWithParam<double> {};

TEST_P(PairEnergy, APressedJellyReleasedGainsNoCountedEnergy) {
  const double h = GetParam();
  MassSpringSystem system;
  Body lower = buildJelly(
      "lower",
      {.n = 4, .size = 0.8, .mass = 0.1, .ks = 3000, .kd = 0, .center = Vec3::Zero(), .rotation_axis = Vec3::UnitY()});
  lower.pinned.assign(lower.particleCount(), true);
  Body upper = buildJelly("upper", {.n = 4,
                                    .size = 0.4,
                                    .mass = 0.1,
                                    .ks = 3000,
                                    .kd = 0,
                                    .center = Vec3(0.05, 0.4 + 0.2 + 0.05, 0.03),
                                    .rotation_axis = Vec3::UnitY()});
  lower.contact.friction = upper.contact.friction = 0;
  system.addBody(std::move(lower));
  system.addBody(std::move(upper));
  Simulation sim(system, makeIntegrator("backward-euler"), h);
  double counted = sim.countedEnergy(), total = system.energy(sim.x(), sim.v());
  double counted_rise = 0, total_rise = 0;  // J: the largest rise over a step
  const double start = counted;
  for (int k = 1; k * h <= 2 + 1e-9; ++k) {
    ASSERT_FALSE(sim.advanceTo(k * h));
    const double c = sim.countedEnergy(), e = system.energy(sim.x(), sim.v());
    counted_rise = std::max(counted_rise, c - counted), total_rise = std::max(total_rise, e - total);
    counted = c, total = e;
  }
  std::printf(
      "1/%g s: largest rise over a step %.2e J counted, %.2e J of the system's total; counted %.4f -> %.4f J, "
      "the penalty's work %.4f J\n",
      1 / h, counted_rise, total_rise, start, counted, sim.penaltyWork());
  // Measured: at most 1.3e-5 J (CG's tolerance 1e-3; the linearized step); the system's total alone 0.03 J at 1/60 s
  // and 0.013 J at 1/240 s.
  EXPECT_LT(counted_rise, 1e-4);
  EXPECT_GT(total_rise, 1e-3) << "the pairs never unloaded: the test tests nothing";
  EXPECT_FALSE(sim.energyGain());
}

INSTANTIATE_TEST_SUITE_P(Press, PairEnergy, ::testing::Values(1.0 / 60, 1.0 / 240),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return "BackwardEuler_" + std::to_string(std::lround(1 / info.param));
                         });

}  // namespace
}  // namespace wobble
