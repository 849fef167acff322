// A floor's friction never adds energy under backward Euler (docs/contact.md, Friction under backward Euler). The
// case: foldedCloth's stack (tests/sim/folded_cloth.h), 50 x 50, four layers half a spacing apart with every spring at
// rest, dropped 1 cm onto a floor with friction 0.5 at 1/60 s, self-contact off so that its layers pass through each
// other onto the floor. Its folds' springs are pressed hard while a layer lands on the one below: a friction force
// sized from that push and held for the whole step pushed the cloth sideways at 0.7 m/s and stretched it (12.7 J from
// 1.6 J in one step; at 100 x 100, 60 000 J and a throw upward). Oracles: conservation laws. With the step solved
// exactly (Newton on the nonlinear backward-Euler equations) the total energy (kinetic + gravitational + elastic)
// never exceeds the start's; with the default single linearized solve, whose springs may store energy the
// linearization makes up (docs/energy.md), the kinetic plus gravitational energy never does (the elastic energy is 0
// at the start, every spring at rest, and never negative), and the cloth's top never rises above its drop height;
// the run's energy check stays quiet on the exact steps, and on linearized ones names the exact step as the fix.
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>

#include "sim/simulation.h"
#include "tests/sim/folded_cloth.h"

namespace wobble {
namespace {

constexpr int kSide = 50;
constexpr double kDt = 1.0 / 60;
constexpr int kSteps = 15;  // a quarter second: every layer has landed and the cloth has come to rest
// J: what the energy may exceed the start's by: 1% of the start's 1.64 J (at rest on the floor the contact band
// and the step's end projection move particles by round-off's worth, far below).
constexpr double kTolerance = 0.016;

struct Landing {
  double start = 0, start_top = 0;       // total energy (J) and highest particle (m) at the start
  double most = 0, most_mechanical = 0;  // the largest total, and kinetic + gravitational, energy at a step's end
  double top = 0;                        // the highest particle at any step's end
  double rest = 0;                       // total energy at the end
  std::optional<EnergyGain> gain;        // the run's own energy check, run at every step
};

double highest(const VecX& x) {
  double top = -1e300;
  for (Eigen::Index i = 1; i < x.size(); i += 3) top = std::max(top, x[i]);
  return top;
}

Landing land(double friction, bool newton) {
  const auto system = testing::foldedCloth(kSide, /*self_contact=*/false, /*layers=*/4, /*layer_gap=*/0.5, friction);
  IntegratorOptions options;
  options.cg_max_iterations = 20000;
  options.newton = newton;
  Simulation sim(*system, makeIntegrator("backward-euler", options), kDt);
  Landing l;
  l.start = system->energy(sim.x(), sim.v());
  l.start_top = highest(sim.x());
  l.most = l.most_mechanical = -1e300;
  for (int k = 0; k < kSteps; ++k) {
    EXPECT_FALSE(sim.advanceTo(sim.time() + kDt));
    const double total = system->energy(sim.x(), sim.v());
    l.most = std::max(l.most, total);
    // Kinetic + gravitational: the total less the springs' energy.
    l.most_mechanical = std::max(l.most_mechanical, total - springEnergy(system->springs(), sim.x()));
    l.top = std::max(l.top, highest(sim.x()));
  }
  l.rest = system->energy(sim.x(), sim.v());
  l.gain = sim.energyGain();
  return l;
}

TEST(FloorFriction, ExactStepsOfALandingClothNeverGainEnergy) {
  const Landing l = land(0.5, /*newton=*/true);
  EXPECT_LE(l.most, l.start + kTolerance) << "start " << l.start << " J";
  EXPECT_LE(l.top, l.start_top);
  EXPECT_LT(l.rest, l.start);  // the landing took energy out
  EXPECT_FALSE(l.gain) << l.gain->message(kDt);
}

TEST(FloorFriction, LinearizedStepsNeverThrowALandingCloth) {
  for (const double friction : {0.5, 0.0}) {
    const Landing l = land(friction, /*newton=*/false);
    EXPECT_LE(l.most_mechanical, l.start + kTolerance) << "friction " << friction << ", start " << l.start << " J";
    EXPECT_LE(l.top, l.start_top) << "friction " << friction;
    // What the linearization may make up the run's check reports, and says how to solve the step exactly.
    if (l.gain) {
      EXPECT_NE(l.gain->message(kDt).find("[simulation] newton = true"), std::string::npos);
    }
  }
}

TEST(FloorFriction, EnergyMessageNamesTheExactStepOnlyForALinearizedOne) {
  EnergyGain gain{"backward-euler", 3, 0.05, 1.6, 12.7, 0, 0.4, false};
  EXPECT_EQ(gain.message(kDt).find("newton"), std::string::npos);
  gain.linearized = true;
  EXPECT_NE(gain.message(kDt).find("the exact step instead of its linearization ([simulation] newton = true)"),
            std::string::npos);
}

}  // namespace
}  // namespace wobble
