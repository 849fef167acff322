// Collider::near, the cheap test contact code runs before query(): on random points it keeps exactly the particles
// whose query() distance is below the margin (the sphere may keep a few more within round-off, never fewer).
#include <gtest/gtest.h>

#include <random>

#include "sim/contact/colliders/elevator.h"
#include "sim/contact/colliders/plane.h"
#include "sim/contact/colliders/sphere.h"

namespace wobble {
namespace {

void expectNearMatchesQuery(const Collider& c, double t, bool exact) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3, 3);
  const int n = 20000;
  VecX x(3 * n);
  for (auto& value : x) value = u(rng);
  const double margin = 0.3;  // wide, so that many random points fall in the band
  std::vector<int> near, expected;
  c.near(t, x, margin, near);
  for (int i = 0; i < n; ++i)
    if (const auto s = c.query(t, particle(x, i)); s && s->distance < margin) expected.push_back(i);
  ASSERT_GT(expected.size(), 100u) << c.name();
  ASSERT_LT(expected.size(), std::size_t(n)) << c.name();
  if (exact) {
    EXPECT_EQ(near, expected) << c.name();
  } else {
    EXPECT_TRUE(std::includes(near.begin(), near.end(), expected.begin(), expected.end())) << c.name();
    EXPECT_LE(near.size(), expected.size() + 2) << c.name();
  }
}

TEST(ColliderNear, KeepsExactlyTheParticlesWithinTheMargin) {
  expectNearMatchesQuery(PlaneCollider("plane", {}, Vec3(0, 0.5, 0), Vec3(1, 2, 0.5)), 0, true);
  expectNearMatchesQuery(SphereCollider("sphere", {}, Vec3(0.1, 0, 0), 1.5, Vec3(0.2, 0, 0)), 1.0, false);
  expectNearMatchesQuery(ElevatorCollider("elevator", {}, ElevatorSchedule{}, 3, 0.5), 0.5, true);
}

}  // namespace
}  // namespace wobble
