// A mesh jelly's visible surface (its model embedded in the lattice, contact/colliders/weighted_points.h) meets other
// bodies' surfaces (docs/body-contact.md, docs/mesh-bodies.md). Oracles: the independent triangle-triangle test (Moller
// 1997, triangle_intersection.h) on the embedded surfaces as written, at every frame; the conservation laws (energy
// never gained by an impact, momentum kept); the run's own energy check. RK4 and backward Euler (whose solve takes the
// embedded pairs in, as stencils of up to 32 particles).
#include <gtest/gtest.h>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/bodies/mesh_jelly.h"
#include "sim/contact/colliders/plane.h"
#include "sim/simulation.h"
#include "tests/sim/momentum.h"
#include "tests/sim/test_models.h"
#include "tests/sim/triangle_intersection.h"

namespace wobble {
namespace {

struct Case {
  const char* integrator;
  double dt;
  double momentum_tolerance;  // as in body_impact_energy_test.cpp: rounding, or backward Euler's linear solve
};

testing::ParticleTriangles surfaces(const MassSpringSystem& system) {
  testing::ParticleTriangles s;
  for (std::size_t b = 0; b < system.bodies().size(); ++b)
    testing::addSurface(s, system.bodies()[b].body.surface, system.bodies()[b].first, int(b));
  return s;
}

// The mean of a body's surface points as written (its embedded surface for a mesh jelly).
Vec3 surfaceCenter(const MassSpringSystem& system, const VecX& x, int body) {
  const BodySlot& slot = system.bodies()[body];
  const SurfaceFrame f = evaluateSurface(slot.body.surface, x, slot.first);
  Vec3 c = Vec3::Zero();
  for (const auto& p : f.positions) c += p.cast<double>();
  return c / double(f.positions.size());
}

// A sphere model (its lattice's corners stick out beyond it, up to a cell's diagonal) thrown at a turned cube jelly
// without gravity: only the embedded surface may touch. Energy after the impact at most before it (1%), momentum
// kept, no triangles intersecting at any frame, and they bounce apart.
void sphereIntoCube(const Case& c) {
  MassSpringSystem system(Vec3::Zero());
  MeshJellyParams ball{.cells = 4, .ks = 2000, .kd = 5, .velocity = Vec3(2, 0, 0)};
  ball.placement.center = Vec3(-0.8, 0.1, 0);
  system.addBody(buildMeshJelly("ball", testing::uvSphere(0.5, 8, 12), ball));
  system.addBody(buildJelly("cube", {.n = 4,
                                     .size = 1,
                                     .ks = 2000,
                                     .kd = 5,
                                     .center = Vec3(0.9, 0.25, 0.1),
                                     .rotation_axis = Vec3(0, 1, 0.3),
                                     .rotation_deg = 35,
                                     .velocity = Vec3(-2, 0, 0)}));
  const auto tris = surfaces(system);
  ASSERT_EQ(testing::intersectingPairs(tris, system.initialPositions()), 0);
  Simulation sim(system, makeIntegrator(c.integrator), c.dt);
  ASSERT_TRUE(sim.bodyContact());
  const double before = system.energy(sim.x(), sim.v());
  const Vec3 p0 = testing::momentum(system, sim.v());
  const double p_scale = 2.0 * system.mass().sum();
  int worst = 0;
  for (int frame = 1; frame <= 30; ++frame) {  // 0.6 s: meet at about 0.1 s, apart by the end
    ASSERT_FALSE(sim.advanceTo(frame * 0.02)) << c.integrator;
    worst = std::max(worst, testing::intersectingPairs(tris, sim.x()));
  }
  EXPECT_EQ(worst, 0) << c.integrator;
  const double after = system.energy(sim.x(), sim.v());
  EXPECT_LE(after, before * 1.01) << c.integrator << ": " << before << " J to " << after << " J";
  EXPECT_LT((testing::momentum(system, sim.v()) - p0).norm(), c.momentum_tolerance * p_scale) << c.integrator;
  const collision::Stats& s = *sim.bodyContact();
  EXPECT_GT(s.contacts + s.ccd_hits + sim.integrator().stats().body_contact_pairs, 0) << c.integrator;
  EXPECT_LT(surfaceCenter(system, sim.x(), 0).x(), surfaceCenter(system, sim.x(), 1).x()) << c.integrator;
  // The impact stopped the ball's surface: its particles' momentum along x is at most half what it was.
  const auto ball_momentum = [&](const VecX& v) {
    double p = 0;
    for (int i = 0; i < system.bodies()[0].body.particleCount(); ++i) p += system.mass()[i] * v[3 * i];
    return p;
  };
  EXPECT_LT(ball_momentum(sim.v()), 0.5 * ball_momentum(system.initialVelocities())) << c.integrator;
  EXPECT_FALSE(sim.energyGain()) << sim.energyGain()->message(c.dt);
}

// Two mesh jellies stacked under gravity on a floor: a tilted box model dropped onto a wider one resting there (their
// lattices' cells do not line up with the boxes' faces). No triangles intersect at any frame, the run's energy check
// stays quiet, and the upper box ends on the lower.
void boxOntoBox(const Case& c) {
  MassSpringSystem system;
  system.addCollider(
      std::make_unique<PlaneCollider>("floor", ContactParams{0.3, 0.5, 0.01}, Vec3::Zero(), Vec3::UnitY()));
  MeshJellyParams lower{.cells = 4, .ks = 3000, .kd = 20};
  lower.placement.center = Vec3(0, 0.3, 0);
  system.addBody(buildMeshJelly("lower", testing::box(Vec3(1.1, 0.55, 1.1)), lower));
  MeshJellyParams upper{.cells = 3, .ks = 3000, .kd = 20};
  upper.placement = {.center = Vec3(0.1, 1.4, 0), .rotation_axis = Vec3(1, 0, 1), .rotation_deg = 25};
  system.addBody(buildMeshJelly("upper", testing::box(Vec3(0.6, 0.4, 0.6)), upper));
  const auto tris = surfaces(system);
  ASSERT_EQ(testing::intersectingPairs(tris, system.initialPositions()), 0);
  Simulation sim(system, makeIntegrator(c.integrator), c.dt);
  int worst = 0;
  for (int frame = 1; frame <= 36; ++frame) {  // 1.2 s at 30 frames a second
    ASSERT_FALSE(sim.advanceTo(frame / 30.0)) << c.integrator;
    worst = std::max(worst, testing::intersectingPairs(tris, sim.x()));
  }
  EXPECT_EQ(worst, 0) << c.integrator;
  EXPECT_FALSE(sim.energyGain()) << sim.energyGain()->message(c.dt);
  const collision::Stats& s = *sim.bodyContact();
  EXPECT_GT(s.contacts + s.ccd_hits + sim.integrator().stats().body_contact_pairs, 0) << c.integrator;
  EXPECT_GT(surfaceCenter(system, sim.x(), 1).y(), surfaceCenter(system, sim.x(), 0).y() + 0.3) << c.integrator;
}

// A sphere model dropped onto a small cloth pinned at its corners: the cloth catches the visible surface.
void ballOntoCloth(const Case& c) {
  MassSpringSystem system;
  ClothParams cloth{.nx = 12, .ny = 12, .size_x = 2, .size_y = 2, .center = Vec3(0, 1, 0), .ks = 5000, .kd = 50};
  cloth.pinned = clothPinSet("corners", cloth.nx, cloth.ny);
  system.addBody(buildCloth("cloth", cloth));
  MeshJellyParams ball{.cells = 3, .mass = 0.2, .ks = 2000, .kd = 10};
  ball.placement.center = Vec3(0.05, 1.6, -0.05);
  system.addBody(buildMeshJelly("ball", testing::uvSphere(0.35, 8, 12), ball));
  const auto tris = surfaces(system);
  Simulation sim(system, makeIntegrator(c.integrator), c.dt);
  int worst = 0;
  for (int frame = 1; frame <= 24; ++frame) {  // 0.8 s
    ASSERT_FALSE(sim.advanceTo(frame / 30.0)) << c.integrator;
    worst = std::max(worst, testing::intersectingPairs(tris, sim.x()));
  }
  EXPECT_EQ(worst, 0) << c.integrator;
  EXPECT_FALSE(sim.energyGain()) << sim.energyGain()->message(c.dt);
  // Caught: the ball's lowest surface point is above the cloth's lowest particle.
  const SurfaceFrame f = evaluateSurface(system.bodies()[1].body.surface, sim.x(), system.bodies()[1].first);
  double ball_low = 1e9, cloth_low = 1e9;
  for (const auto& p : f.positions) ball_low = std::min(ball_low, double(p.y()));
  for (int i = 0; i < system.bodies()[0].body.particleCount(); ++i) cloth_low = std::min(cloth_low, sim.x()[3 * i + 1]);
  EXPECT_GT(ball_low, cloth_low) << c.integrator;
}

class MeshBodyContact : public ::testing::TestWithParam<Case> {};

TEST_P(MeshBodyContact, SphereModelIntoCubeJellyNeverGainsNorPassesThrough) { sphereIntoCube(GetParam()); }
TEST_P(MeshBodyContact, BoxModelLandsOnBoxModelWithoutIntersecting) { boxOntoBox(GetParam()); }
TEST_P(MeshBodyContact, SphereModelIsCaughtByAPinnedCloth) { ballOntoCloth(GetParam()); }

INSTANTIATE_TEST_SUITE_P(Integrators, MeshBodyContact,
                         ::testing::Values(Case{"rk4", 5e-4, 1e-9}, Case{"backward-euler", 1.0 / 60, 1e-2}),
                         [](const auto& info) {
                           std::string name = info.param.integrator;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace wobble
