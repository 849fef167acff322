// Backward Euler's friction on colliders within Coulomb's cone (backward_euler_contact.cpp, boundFriction; Bridson,
// Fedkiw & Anderson 2002, section 7.2): a hold or a damper that would take more than mu times the normal impulse gives
// way to Coulomb's force. Oracles: Coulomb's law on an incline (a block slides at g (sin b - mu cos b) where tan b >
// mu, and stays where tan b < mu) and the energy (the slide's loss is friction's work, mu M g cos b per metre; nothing
// is gained), at 1/60 s and 1/240 s on the stiff jelly whose holds stalled it (|J_t| / J_n = 2.48 against mu = 0.3).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>

#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/box.h"
#include "sim/contact/colliders/plane.h"
#include "sim/simulation.h"

namespace wobble {
namespace {

constexpr double kG = 9.8, kMu = 0.3;

struct Slide {
  double speed1 = 0, speed2 = 0;  // m/s: the centre of mass's speed down the slope at t1 and t2
  double travel = 0;              // m: its travel down the slope from t1 to t2
  double loss = 0;                // J: the total energy lost from t1 to t2
  double gain = 0;                // J: the largest total energy at a step's end above the start's
  double fastest = 0;             // m/s: the largest particle speed at t2
  double mass = 0;                // kg
};

// The stiff jelly of the wedge test (5^3, 1 m, ks 1e5 unless given), set flat 5 cm above a plane of slope b (friction
// kMu, restitution 0.5), under backward Euler at step h. With heavy > 0, a second jelly of that many times its mass
// (springs as stiff for its weight) rests on a box's flat top well down the slope, out of the first's way.
Slide slide(double slope, double h, double t1, double t2, double heavy = 0, double ks = 1e5) {
  MassSpringSystem system(Vec3(0, -kG, 0));
  const Vec3 up(std::sin(slope), std::cos(slope), 0), down(std::cos(slope), -std::sin(slope), 0);
  system.addBody(buildJelly("jelly", {.n = 5,
                                      .size = 1,
                                      .ks = ks,
                                      .kd = 20,
                                      .center = 0.55 * up,
                                      .rotation_axis = Vec3::UnitZ(),
                                      .rotation_deg = -slope * 180 / M_PI}));
  system.addCollider(
      std::make_unique<PlaneCollider>("slope", ContactParams{.restitution = 0.5, .friction = kMu, .epsilon = 0.01},
                                      Vec3::Zero(), up));
  const int jelly = system.particleCount();
  if (heavy > 0) {
    const Vec3 top(30, -10, 0);
    system.addBody(buildJelly("heavy", {.n = 5,
                                        .size = 1,
                                        .mass = heavy,
                                        .ks = heavy * 1e5,
                                        .kd = heavy * 20,
                                        .center = top + Vec3(0, 0.505, 0),
                                        .rotation_axis = Vec3::UnitZ()}));
    system.addCollider(
        std::make_unique<BoxCollider>("table", ContactParams{.restitution = 0.5, .friction = kMu, .epsilon = 0.01},
                                      top - Vec3(0, 1, 0), Vec3(4, 2, 4)));
  }
  Simulation sim(system, makeIntegrator("backward-euler"), h);
  Slide s;
  const VecX& m = system.mass();
  s.mass = m.head(jelly).sum();
  const auto centre = [&](const VecX& y) {
    Vec3 c = Vec3::Zero();
    for (int i = 0; i < jelly; ++i) c += m[i] * particle(y, i);
    return Vec3(c / s.mass);
  };
  const double start = system.energy(sim.x(), sim.v());
  double energy = start, e1 = 0, d1 = 0;
  for (int k = 1; k * h <= t2 + 1e-9; ++k) {
    EXPECT_FALSE(sim.advanceTo(k * h));
    energy = system.energy(sim.x(), sim.v());
    s.gain = std::max(s.gain, energy - start);
    if (std::abs(k * h - t1) < 1e-9) {
      s.speed1 = down.dot(centre(sim.v()));
      e1 = energy, d1 = down.dot(centre(sim.x()));
    }
  }
  s.speed2 = down.dot(centre(sim.v()));
  s.travel = down.dot(centre(sim.x())) - d1;
  s.loss = e1 - energy;
  s.fastest = sim.v().head(3 * jelly).reshaped(3, jelly).colwise().norm().maxCoeff();
  return s;
}

class CoulombCone : public ::testing::TestWithParam<double> {};
std::string stepName(const ::testing::TestParamInfo<double>& info) {
  return "BackwardEuler_" + std::to_string(std::lround(1 / info.param));
}

// 0.5 rad, tan b = 0.55 > mu: from 0.3 s (landed) to 1.3 s the centre of mass accelerates at g (sin b - mu cos b) =
// 2.118 m/s^2, and the energy lost over the travel d is friction's work mu M g cos b d.
TEST_P(CoulombCone, AJellySlidesDownASteepSlopeAtCoulombsAcceleration) {
  const double h = GetParam(), slope = 0.5, t1 = 0.3, t2 = 1.3;
  const Slide s = slide(slope, h, t1, t2);
  const double expected = kG * (std::sin(slope) - kMu * std::cos(slope));
  const double acceleration = (s.speed2 - s.speed1) / (t2 - t1);
  const double work = kMu * s.mass * kG * std::cos(slope) * s.travel;
  std::printf(
      "1/%g s: acceleration %.4f m/s^2 (Coulomb %.4f), energy lost %.4g J over %.4g m (friction's work %.4g J), "
      "most above the start %.3g J\n",
      1 / h, acceleration, expected, s.loss, s.travel, work, s.gain);
  EXPECT_NEAR(acceleration, expected, 0.03 * expected);
  EXPECT_NEAR(s.loss, work, 0.05 * work);
  EXPECT_LE(s.gain, 0);
}

// The slide of a jelly 300 times as stiff (ks 3e7: its excess over each particle's diagonal is below 1 mm/s, so only
// its excess over its own mass as one rigid body lets it slide), beside a jelly 20 times as heavy resting on a table
// out of its way: the slider's excess is not divided by a mass it does not touch.
TEST_P(CoulombCone, AHeavyBodyElsewhereDoesNotHoldTheSlidingJelly) {
  const double h = GetParam(), slope = 0.5, t1 = 0.3, t2 = 1.3;
  const Slide s = slide(slope, h, t1, t2, 20, 3e7);
  const double expected = kG * (std::sin(slope) - kMu * std::cos(slope));
  const double acceleration = (s.speed2 - s.speed1) / (t2 - t1);
  std::printf("1/%g s: acceleration %.4f m/s^2 (Coulomb %.4f) beside a body 20 times as heavy\n", 1 / h, acceleration,
              expected);
  EXPECT_NEAR(acceleration, expected, 0.03 * expected);
}

// 0.2 rad, tan b = 0.20 < mu: static friction holds the landed jelly; from 0.5 s to 2.5 s its centre of mass moves
// less than 0.1 mm and it ends at rest.
TEST_P(CoulombCone, StaticFrictionHoldsAJellyOnAGentleSlope) {
  const double h = GetParam();
  const Slide s = slide(0.2, h, 0.5, 2.5);
  std::printf("1/%g s: travel %.3g m, speeds %.3g and %.3g m/s, largest particle speed %.3g m/s at 2.5 s\n", 1 / h,
              s.travel, s.speed1, s.speed2, s.fastest);
  EXPECT_LT(std::abs(s.travel), 1e-4);
  EXPECT_LT(s.fastest, 1e-3);
  EXPECT_LE(s.gain, 0);
}

INSTANTIATE_TEST_SUITE_P(Slope, CoulombCone, ::testing::Values(1.0 / 60, 1.0 / 240), stepName);

}  // namespace
}  // namespace wobble
