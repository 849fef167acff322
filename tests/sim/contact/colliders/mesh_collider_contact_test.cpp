// A body on a mesh collider (sim/contact/colliders/mesh.h) through the whole step, not only the closest-point query: a
// jelly resting on a tilted ramp (friction holds it) and one sliding down it (no friction) never sink into it. The ramp
// is a square of two triangles, so its surface is a known plane: oracle, every particle's signed distance to that plane
// at every frame, against a tolerance of a millimetre (the contact's own band is a centimetre).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/mesh.h"
#include "sim/simulation.h"

namespace wobble {
namespace {

constexpr double kSlopeDeg = 20;
constexpr double kSink = 1e-3;  // m: how far below the ramp a particle may end a frame

struct Case {
  const char* integrator;
  double dt;
};

struct Outcome {
  double lowest = 0;  // the least signed distance of any particle to the ramp's plane over the run (m)
  double travel = 0;  // how far the jelly's centroid moved down the slope (m)
};

Outcome slideOrRest(const Case& c, double friction) {
  const double a = kSlopeDeg * EIGEN_PI / 180;
  const Vec3 u(std::cos(a), std::sin(a), 0), w(0, 0, 1), n(-std::sin(a), std::cos(a), 0);  // up the slope, across, out
  MassSpringSystem system;
  const std::vector<Vec3> points = {-3 * u - 3 * w, 3 * u - 3 * w, 3 * u + 3 * w, -3 * u + 3 * w};
  system.addCollider(std::make_unique<MeshCollider>("ramp", ContactParams{.restitution = 0, .friction = friction},
                                                    points, std::vector<std::array<int, 3>>{{0, 2, 1}, {0, 3, 2}},
                                                    Vec3::Zero()));
  // A 3^3 jelly lying square on the ramp, its bottom 2 cm above it.
  system.addBody(buildJelly("jelly", {.n = 3,
                                      .size = 0.5,
                                      .ks = 1400,
                                      .kd = 10,
                                      .center = 0.27 * n + u,
                                      .rotation_axis = Vec3::UnitZ(),
                                      .rotation_deg = kSlopeDeg}));
  const auto centroid = [&](const VecX& x) {
    Vec3 s = Vec3::Zero();
    for (int i = 0; i < system.particleCount(); ++i) s += particle(x, i);
    return Vec3(s / system.particleCount());
  };
  Simulation sim(system, makeIntegrator(c.integrator), c.dt);
  const Vec3 start = centroid(sim.x());
  Outcome o{1e9, 0};
  for (int frame = 1; frame <= 50; ++frame) {  // 1 s
    EXPECT_FALSE(sim.advanceTo(frame * 0.02)) << c.integrator;
    for (int i = 0; i < system.particleCount(); ++i) o.lowest = std::min(o.lowest, n.dot(particle(sim.x(), i)));
  }
  o.travel = -u.dot(centroid(sim.x()) - start);
  return o;
}

class MeshColliderContact : public ::testing::TestWithParam<Case> {};

TEST_P(MeshColliderContact, AJellyRestingOnARampDoesNotSinkIntoIt) {
  const Outcome o = slideOrRest(GetParam(), 1.0);  // friction 1 > tan 20 degrees: it stays
  EXPECT_GT(o.lowest, -kSink) << GetParam().integrator;
  EXPECT_LT(std::abs(o.travel), 0.05) << GetParam().integrator;
}

TEST_P(MeshColliderContact, AJellySlidingDownARampDoesNotSinkIntoIt) {
  const Outcome o = slideOrRest(GetParam(), 0);
  EXPECT_GT(o.lowest, -kSink) << GetParam().integrator;
  // Frictionless: g sin 20 degrees for about a second, 1.7 m down the slope (less the landing's 2 cm of fall).
  EXPECT_GT(o.travel, 1.2) << GetParam().integrator;
}

INSTANTIATE_TEST_SUITE_P(Integrators, MeshColliderContact,
                         ::testing::Values(Case{"rk4", 1e-3}, Case{"explicit-euler", 1e-4},
                                           Case{"backward-euler", 1.0 / 60}),
                         [](const auto& info) {
                           std::string s = info.param.integrator;
                           for (char& ch : s)
                             if (ch == '-') ch = '_';
                           return s;
                         });

}  // namespace
}  // namespace wobble
