// The box collider: its signed distance and normals outside, inside and at an edge, its bounds, and a particle
// dropped on its top that comes to rest there.
#include <gtest/gtest.h>

#include "sim/contact/colliders/box.h"
#include "tests/sim/point_masses.h"

namespace wobble {
namespace {

TEST(BoxCollider, DistanceAndNormalOutsideInsideAndAtAnEdge) {
  const BoxCollider box("crate", ContactParams{}, Vec3(0, 1, 0), Vec3(2, 2, 2));
  const auto above = box.query(0, Vec3(0, 2.5, 0));
  EXPECT_DOUBLE_EQ(above->distance, 0.5);
  EXPECT_TRUE(above->normal.isApprox(Vec3::UnitY()));
  const auto inside = box.query(0, Vec3(0.9, 1, 0));
  EXPECT_NEAR(inside->distance, -0.1, 1e-12);
  EXPECT_TRUE(inside->normal.isApprox(Vec3::UnitX()));
  const auto edge = box.query(0, Vec3(2, 3, 0));  // 1 past the +x face and 1 above the top
  EXPECT_NEAR(edge->distance, std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(edge->normal.isApprox(Vec3(1, 1, 0).normalized()));
  const auto bounds = box.bounds(0);
  ASSERT_TRUE(bounds);
  EXPECT_TRUE(bounds->min().isApprox(Vec3(-1, 0, -1)));
  EXPECT_TRUE(bounds->max().isApprox(Vec3(1, 2, 1)));
}

TEST(BoxCollider, ADroppedParticleComesToRestOnTheTop) {
  MassSpringSystem system;
  system.addBody(testing::particles({Vec3(0.2, 3, -0.3)}));
  system.addCollider(
      std::make_unique<BoxCollider>("crate", ContactParams{0.5, 0.5, 0.01}, Vec3(0, 1, 0), Vec3(2, 2, 2)));
  Simulation sim(system, makeIntegrator("rk4"), 1e-3);
  ASSERT_FALSE(sim.advanceTo(3));
  EXPECT_NEAR(sim.x()[1], 2, 0.011);      // on the top face, within the contact tolerance
  EXPECT_LT(sim.v().norm(), 9.8 * 1e-3);  // at rest: what gravity adds in one step, at most
}

}  // namespace
}  // namespace wobble
