// Spring and damper forces against hand-computed values, and Newton's third law over a whole jelly.
#include <gtest/gtest.h>

#include <random>

#include "sim/bodies/jelly.h"
#include "sim/springs.h"

namespace wobble {
namespace {

TEST(Springs, HookeForceMatchesHandComputation) {
  // a at (3, 4, 0), b at the origin: length 5, rest 2, ks 10 -> |f| = 30 along -(3, 4)/5 on a.
  Springs s;
  s.add(0, 1, 2.0, 10.0, 0.0, SpringType::Structural);
  VecX x(6), v = VecX::Zero(6), f = VecX::Zero(6);
  x << 3, 4, 0, 0, 0, 0;
  addSpringForces(s, x, v, f);
  EXPECT_NEAR(f[0], -18.0, 1e-12);
  EXPECT_NEAR(f[1], -24.0, 1e-12);
  EXPECT_NEAR(f[3], 18.0, 1e-12);
  EXPECT_NEAR(f[4], 24.0, 1e-12);
  EXPECT_NEAR(springEnergy(s, x), 0.5 * 10 * 9, 1e-12);
}

TEST(Springs, DamperActsOnlyAlongTheSpring) {
  // At rest length: only the damper acts. Relative velocity (1, 7, 0) projected on d = (1, 0, 0) is 1.
  Springs s;
  s.add(0, 1, 2.0, 10.0, 3.0, SpringType::Structural);
  VecX x(6), v(6), f = VecX::Zero(6);
  x << 2, 0, 0, 0, 0, 0;
  v << 1, 7, 0, 0, 0, 0;
  addSpringForces(s, x, v, f);
  EXPECT_NEAR(f[0], -3.0, 1e-12);
  EXPECT_NEAR(f[1], 0.0, 1e-12);
  EXPECT_NEAR(f[3], 3.0, 1e-12);
}

TEST(Springs, InternalForcesSumToZeroAndHaveNoTorque) {
  Body jelly = buildJelly("j", {.n = 4});
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.1);
  VecX x = jelly.x, v(jelly.x.size()), f = VecX::Zero(jelly.x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += noise(rng), v[i] = noise(rng) * 10;
  addSpringForces(jelly.springs, x, v, f);
  Vec3 total = Vec3::Zero(), torque = Vec3::Zero();
  double largest = 0;
  for (int i = 0; i < jelly.particleCount(); ++i) {
    total += particle(f, i);
    torque += Vec3(particle(x, i)).cross(Vec3(particle(f, i)));
    largest = std::max(largest, particle(f, i).norm());
  }
  ASSERT_GT(largest, 1.0);  // the perturbation really loads the springs
  EXPECT_LT(total.norm(), 1e-10 * largest);
  EXPECT_LT(torque.norm(), 1e-9 * largest);  // central forces: no net torque
}

TEST(Springs, CoincidentEndpointsGiveNoNaN) {
  Springs s;
  s.add(0, 1, 1.0, 10.0, 1.0, SpringType::Structural);
  VecX x = VecX::Zero(6), v = VecX::Ones(6), f = VecX::Zero(6);
  addSpringForces(s, x, v, f);
  EXPECT_TRUE(f.allFinite());
}

}  // namespace
}  // namespace wobble
