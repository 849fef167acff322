// Air drag against exponential decay, and the cloth scene's sphere holding a pinned cloth: nothing falls through.
#include <gtest/gtest.h>

#include <cmath>

#include "point_masses.h"
#include "sim/bodies/cloth.h"
#include "sim/contact/colliders/sphere.h"

namespace wobble {
namespace {

TEST(Drag, VelocityDecaysExponentially) {
  // m v' = -c v: v(t) = v0 exp(-c t / m).
  Body b = testing::particles({Vec3::Zero()}, Vec3(3, 0, -4), 2.0);
  b.drag = 0.5;
  MassSpringSystem system(Vec3::Zero());
  system.addBody(b);
  Simulation sim(system, makeIntegrator("rk4"), 1e-3);
  ASSERT_FALSE(sim.advanceTo(2.0));
  const double factor = std::exp(-0.5 * 2.0 / 2.0);
  EXPECT_NEAR(sim.v()[0], 3 * factor, 1e-12);
  EXPECT_NEAR(sim.v()[2], -4 * factor, 1e-12);
  EXPECT_NEAR(sim.x()[0], 3 * (1 - factor) * 2.0 / 0.5, 1e-10);  // x = v0 m / c (1 - exp(-c t / m))
}

TEST(SphereCollider, HoldsTheClothAndPinnedCornersStay) {
  ClothParams p{.nx = 11, .ny = 11};
  p.pinned = clothPinSet("corners", p.nx, p.ny);
  MassSpringSystem system;
  system.addBody(buildCloth("cloth", p));
  system.addCollider(
      std::make_unique<SphereCollider>("ball", ContactParams{0, 0.5, 0.01}, Vec3::Zero(), 1.0, Vec3::Zero()));
  Simulation sim(system, makeIntegrator("rk4"), 1e-4);
  ASSERT_FALSE(sim.advanceTo(1.0));
  double deepest = 0;
  for (int i = 0; i < system.particleCount(); ++i) deepest = std::min(deepest, particle(sim.x(), i).norm() - 1.0);
  EXPECT_GT(deepest, -1e-9);  // step ends project onto the surface
  const int centre = 5 + 11 * 5;
  EXPECT_NEAR(particle(sim.x(), centre).y(), 1.0, 0.011);  // resting on top of the sphere, within epsilon
  for (int corner : p.pinned) EXPECT_EQ(particle(sim.x(), corner), particle(system.initialPositions(), corner));
}

}  // namespace
}  // namespace wobble
