// Collision response against analytic oracles: bounce apexes e^(2k) H0, restitution relative to a moving surface,
// Coulomb friction on the 20-degree slope, and resting contact that is the same under every integrator.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/elevator.h"
#include "sim/contact/colliders/plane.h"
#include "sim/contact/colliders/sphere.h"
#include "tests/sim/point_masses.h"

namespace wobble {
namespace {

const double kSin20 = std::sin(EIGEN_PI / 9), kCos20 = std::cos(EIGEN_PI / 9);

std::vector<std::string> allIntegrators() { return {integratorNames().begin(), integratorNames().end()}; }

TEST(Bounce, ApexHeightsFollowRestitutionSquared) {
  const double e = 0.8, h0 = 2.0;
  MassSpringSystem system;
  system.addBody(testing::particles({Vec3(0, h0, 0)}));
  system.addCollider(std::make_unique<PlaneCollider>("floor", ContactParams{e, 0, 0.01}, Vec3::Zero(), Vec3::UnitY()));
  Simulation sim(system, makeIntegrator("rk4"), 1e-4);
  std::vector<double> apexes;
  double previous_vy = 0;
  while (apexes.size() < 3 && sim.time() < 10) {
    ASSERT_FALSE(sim.advanceTo(sim.time() + 1e-4));
    const double vy = sim.v()[1];
    if (previous_vy > 0 && vy <= 0) apexes.push_back(sim.x()[1]);
    previous_vy = vy;
  }
  ASSERT_EQ(apexes.size(), 3u);
  // Tolerance: the bounce happens anywhere in the 0.01 contact band, and the apex is sampled at 1e-4 s.
  for (int k = 1; k <= 3; ++k) EXPECT_NEAR(apexes[k - 1], std::pow(e, 2 * k) * h0, 0.015) << "rebound " << k;
}

TEST(Bounce, RestitutionIsRelativeToTheMovingElevator) {
  // At t = 1 s the platform rises at u = 3 m/s with its top at 1 + 1.5 = 2.5 m. A particle just below its top,
  // falling at -2 m/s, leaves at u - e (v - u) = 3 - 0.8 (-5) = 7 m/s, moved back onto the top.
  MassSpringSystem system;
  system.addBody(testing::particles({Vec3(0.5, 2.499, 0)}, Vec3(0.3, -2, 0)));
  system.addCollider(
      std::make_unique<ElevatorCollider>("lift", ContactParams{0.8, 0.5, 0.01}, ElevatorSchedule{}, 5, 0.25));
  VecX x = system.initialPositions(), v = system.initialVelocities();
  system.resolveCollisions(1.0, x, v);
  EXPECT_NEAR(v[1], 7.0, 1e-12);
  EXPECT_NEAR(v[0], 0.3, 1e-12);  // tangential velocity untouched by restitution
  EXPECT_NEAR(x[1], 2.5, 1e-12);
  // Off the platform's footprint nothing happens.
  VecX x2 = x, v2 = v;
  x2[0] = 2.6;
  x2[1] = 2.499;
  v2[1] = -2;
  system.resolveCollisions(1.0, x2, v2);
  EXPECT_EQ(v2[1], -2);
}

TEST(Bounce, ParticleDroppedOnRisingElevatorLeavesAtRelativeRestitution) {
  // Integrated version: drop onto the rising platform; just after the bounce, v' = u - e (v - u) within a step's drift.
  MassSpringSystem system;
  system.addBody(testing::particles({Vec3(0, 3.0, 0)}));
  system.addCollider(
      std::make_unique<ElevatorCollider>("lift", ContactParams{0.8, 0, 0.01}, ElevatorSchedule{}, 5, 0.25));
  Simulation sim(system, makeIntegrator("rk4"), 1e-5);
  double previous_v = 0, previous_t = 0;
  while (sim.time() < 1.5) {
    previous_v = sim.v()[1];
    previous_t = sim.time();
    ASSERT_FALSE(sim.advanceTo(sim.time() + 1e-5));
    if (sim.v()[1] > previous_v + 1) break;  // the bounce
  }
  ASSERT_LT(sim.time(), 1.5);
  const double u = ElevatorSchedule{}.velocity(previous_t);
  EXPECT_NEAR(sim.v()[1], u - 0.8 * (previous_v - u), 0.01);
}

TEST(ElevatorCollider, ScheduleIsAFunctionOfTime) {
  const ElevatorSchedule s;  // accel 3, travel 2, pause 0.001: period 4.002
  EXPECT_DOUBLE_EQ(s.period(), 4.002);
  EXPECT_DOUBLE_EQ(s.height(1.0), 1.5);
  EXPECT_DOUBLE_EQ(s.velocity(1.0), 3.0);
  EXPECT_NEAR(s.velocity(1.999999), 6.0, 1e-5);  // reaching 6 m/s...
  EXPECT_DOUBLE_EQ(s.height(2.0), 6.0);          // ...6 m up...
  EXPECT_DOUBLE_EQ(s.velocity(2.0), 0.0);        // ...and stopping dead
  EXPECT_DOUBLE_EQ(s.height(2.0005), 6.0);
  EXPECT_NEAR(s.height(3.001), 4.5, 1e-12);
  EXPECT_NEAR(s.velocity(3.001), -3.0, 1e-12);
  EXPECT_NEAR(s.height(4.0015), 0.0, 1e-12);
  EXPECT_NEAR(s.height(4.002 + 1.0), 1.5, 1e-9);  // periodic
  EXPECT_NEAR(s.height(10 * 4.002 + 3.001), 4.5, 1e-9);
  const ElevatorCollider lift("lift", {}, s, 5, 0.25);
  EXPECT_NEAR(lift.topCenter(1.0).y(), 2.5, 1e-12);
}

// A single particle resting on the 20-degree slope: Coulomb friction holds it iff mu >= tan(20 deg) = 0.364.
double slideAfter(double mu, double t, const std::string& method) {
  const Vec3 normal(kSin20, kCos20, 0);
  MassSpringSystem system;
  system.addBody(testing::particles({Vec3::Zero()}));
  system.addCollider(std::make_unique<PlaneCollider>("slope", ContactParams{0.8, mu, 0.01}, Vec3::Zero(), normal));
  Simulation sim(system, makeIntegrator(method), 1e-3);
  EXPECT_FALSE(sim.advanceTo(t));
  EXPECT_NEAR(normal.dot(sim.x().head<3>()), 0, 1e-9) << "left the surface";
  return sim.x().head<3>().norm();
}

TEST(Friction, ParticleStaysOnTheSlopeAboveTan20) {
  for (const auto& method : allIntegrators()) EXPECT_LT(slideAfter(0.5, 2.0, method), 1e-9) << method;
}

TEST(Friction, ParticleSlidesBelowTan20WithCoulombAcceleration) {
  const double mu = 0.2, t = 2.0, expected = 0.5 * 9.8 * (kSin20 - mu * kCos20) * t * t;
  for (const auto& method : {"midpoint", "rk4"})
    EXPECT_NEAR(slideAfter(mu, t, method), expected, 1e-3 * expected) << method;
  EXPECT_NEAR(slideAfter(mu, t, "explicit-euler"), expected, 0.01 * expected);
}

TEST(Friction, JellyBlockRestingOnTheSlopeStaysOrSlides) {
  // A 3^3 block placed flat on the slope (rotated -20 deg about z). Its bottom layer, the particles in contact, may
  // shift a fraction of a millimetre while the block settles under its own weight (edge particles briefly carry
  // more than their share); after that, static friction must hold it exactly: no creep, and the block at rest.
  const Vec3 normal(kSin20, kCos20, 0), downhill(kCos20, -kSin20, 0);
  const auto run = [&](double mu, std::initializer_list<double> times) {
    MassSpringSystem system;
    system.addBody(buildJelly("block", {.n = 3,
                                        .size = 1,
                                        .ks = 5000,
                                        .kd = 50,
                                        .center = 0.5 * normal,
                                        .rotation_axis = Vec3::UnitZ(),
                                        .rotation_deg = -20}));
    system.addCollider(std::make_unique<PlaneCollider>("slope", ContactParams{0.8, mu, 0.01}, Vec3::Zero(), normal));
    Simulation sim(system, makeIntegrator("rk4"), 1e-3);
    std::vector<double> slips;
    for (double t : times) {
      EXPECT_FALSE(sim.advanceTo(t));
      double slip = 0;
      for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) {
          const int id = i + 9 * k;  // lattice row j = 0: the face on the slope
          slip += downhill.dot(particle(sim.x(), id) - particle(system.initialPositions(), id)) / 9;
        }
      slips.push_back(slip);
    }
    slips.push_back(sim.v().cwiseAbs().maxCoeff());
    return slips;
  };
  const auto held = run(0.6, {1.0, 4.0});
  EXPECT_LT(std::abs(held[0]), 1e-3);            // settling
  EXPECT_LT(std::abs(held[1] - held[0]), 1e-9);  // then not a nanometre more
  EXPECT_LT(held[2], 1e-9);                      // at rest
  const double slide = 0.5 * 9.8 * (kSin20 - 0.1 * kCos20) * 4;
  EXPECT_NEAR(run(0.1, {2.0})[0], slide, 0.05 * slide);
}

TEST(Contact, RestingParticleIsStillUnderEveryIntegrator) {
  // No jitter: stage evaluations must leave no velocity or position edits behind.
  for (const auto& method : allIntegrators()) {
    MassSpringSystem system;
    system.addBody(testing::particles({Vec3(0, 0.005, 0)}));
    system.addCollider(std::make_unique<PlaneCollider>("floor", ContactParams{}, Vec3::Zero(), Vec3::UnitY()));
    Simulation sim(system, makeIntegrator(method), 1e-3);
    ASSERT_FALSE(sim.advanceTo(1.0));
    EXPECT_NEAR(sim.x()[1], 0.005, 1e-12) << method;
    EXPECT_LT(sim.v().norm(), 1e-12) << method;
  }
}

TEST(Contact, BounceIsTheSameUnderEveryIntegrator) {
  // Free flight is exact for midpoint and RK4 and first-order for the Euler methods; all give the e^2 apex.
  for (const auto& method : allIntegrators()) {
    MassSpringSystem system;
    system.addBody(testing::particles({Vec3(0, 1, 0)}));
    system.addCollider(
        std::make_unique<PlaneCollider>("floor", ContactParams{0.5, 0, 0.01}, Vec3::Zero(), Vec3::UnitY()));
    Simulation sim(system, makeIntegrator(method), 1e-4);
    double apex = 0;
    bool bounced = false;
    while (sim.time() < 1.2) {
      ASSERT_FALSE(sim.advanceTo(sim.time() + 1e-4));
      bounced |= sim.v()[1] > 0;
      if (bounced) apex = std::max(apex, sim.x()[1]);
    }
    EXPECT_NEAR(apex, 0.25, 0.01) << method;
  }
}

TEST(Contact, MovingSphereCarriesRestingCloth) {
  // A particle resting on top of a sphere moving sideways with friction is dragged along (kinetic friction).
  MassSpringSystem system;
  system.addBody(testing::particles({Vec3(0, 1.0, 0)}));
  system.addCollider(
      std::make_unique<SphereCollider>("ball", ContactParams{0, 0.5, 0.01}, Vec3::Zero(), 1.0, Vec3(1, 0, 0)));
  Simulation sim(system, makeIntegrator("rk4"), 1e-3);
  ASSERT_FALSE(sim.advanceTo(0.05));
  EXPECT_GT(sim.v()[0], 0.2);  // mu g t = 0.245 m/s gained by friction
  EXPECT_LT(sim.v()[0], 0.3);
}

TEST(Pinning, PinnedParticlesNeverMove) {
  for (const auto& method : allIntegrators()) {
    MassSpringSystem system;
    system.addBody(testing::anchoredSpring(1, 0.5, 3, 100, 1));
    Simulation sim(system, makeIntegrator(method), 1e-3);
    ASSERT_FALSE(sim.advanceTo(0.5));
    EXPECT_EQ(sim.x().head<3>(), Vec3::Zero()) << method;
    EXPECT_EQ(sim.v().head<3>(), Vec3::Zero()) << method;
    EXPECT_NE(sim.x()[3], 1.5) << method;  // while the free end moves
  }
}

}  // namespace
}  // namespace wobble
