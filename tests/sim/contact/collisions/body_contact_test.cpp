// Contact between bodies (sim/contact/): the continuous test's cubic against analytic cases, the closest-point
// queries against brute force, and whole runs checked by an independent triangle-triangle intersection test
// (triangle_intersection.h): a fast jelly meeting a one-particle-thick cloth does not pass through it, and a step in
// which no two surfaces come near is the same bytes with the pass as without it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <tuple>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/contact/ccd/ccd.h"
#include "sim/contact/collisions/body_collisions.h"
#include "sim/simulation.h"
#include "tests/sim/cloth_drop.h"
#include "tests/sim/folded_cloth.h"
#include "tests/sim/jelly_on_cloth.h"
#include "tests/sim/jelly_stack.h"
#include "tests/sim/triangle_intersection.h"

namespace wobble {
namespace {

using collision::firstHit;
using collision::Primitive;

std::array<Vec3, 4> pts(Vec3 a, Vec3 b, Vec3 c, Vec3 d) { return {a, b, c, d}; }

// A point falls through the fixed triangle z = 0 from z = 1 to z = -1: it meets the face at t = 1/2.
TEST(Ccd, VertexThroughFaceAtKnownTime) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const auto hit = firstHit(Primitive::PointTriangle, pts({0.2, 0.2, 1}, a, b, c), pts({0.2, 0.2, -1}, a, b, c), 1e-6);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 0.5, 1e-12);
  EXPECT_NEAR(hit->normal.z(), 1, 1e-12);  // along the start's relative position: out of the side it came from
  // Through at t = 1/4, with the triangle moving up to meet it: z_p = 1 - 2t, z_tri = 2t.
  const auto moving = firstHit(Primitive::PointTriangle, pts({0.2, 0.2, 1}, a, b, c),
                               pts({0.2, 0.2, -1}, a + Vec3(0, 0, 2), b + Vec3(0, 0, 2), c + Vec3(0, 0, 2)), 1e-6);
  ASSERT_TRUE(moving);
  EXPECT_NEAR(moving->t, 0.25, 1e-12);
}

TEST(Ccd, VertexBesideFaceMisses) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // Through the plane at t = 1/2 but outside the triangle (x + y = 1.2 > 1).
  EXPECT_FALSE(firstHit(Primitive::PointTriangle, pts({0.6, 0.6, 1}, a, b, c), pts({0.6, 0.6, -1}, a, b, c), 1e-6));
  // Moving away from the face.
  EXPECT_FALSE(firstHit(Primitive::PointTriangle, pts({0.2, 0.2, 0.1}, a, b, c), pts({0.2, 0.2, 1}, a, b, c), 1e-6));
}

// Two crossed edges: a along x at z = 1 - 2t, b along y at z = 0; they meet at t = 1/2 at the origin.
TEST(Ccd, EdgeEdgeAtKnownTime) {
  const Vec3 b0(0, -1, 0), b1(0, 1, 0);
  const auto hit =
      firstHit(Primitive::EdgeEdge, pts({-1, 0, 1}, {1, 0, 1}, b0, b1), pts({-1, 0, -1}, {1, 0, -1}, b0, b1), 1e-6);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 0.5, 1e-12);
  EXPECT_NEAR(hit->at.w[0], 0.5, 1e-12);  // the middle of each edge
  EXPECT_NEAR(hit->at.w[2], -0.5, 1e-12);
  EXPECT_NEAR(std::abs(hit->normal.z()), 1, 1e-12);
  // Shifted along y beyond b's end: the lines cross, the segments do not.
  EXPECT_FALSE(
      firstHit(Primitive::EdgeEdge, pts({-1, 2, 1}, {1, 2, 1}, b0, b1), pts({-1, 2, -1}, {1, 2, -1}, b0, b1), 1e-6));
}

// Parallel edges in one plane all along: the cubic vanishes identically, and the meeting is found in the plane.
TEST(Ccd, ParallelEdgesMeetInTheirPlane) {
  const Vec3 b0(0, 0, 0), b1(1, 0, 0);
  const auto hit =
      firstHit(Primitive::EdgeEdge, pts({0, 0, 1}, {1, 0, 1}, b0, b1), pts({0, 0, -1}, {1, 0, -1}, b0, b1), 1e-6);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 0.5, 1e-9);
  EXPECT_NEAR(hit->normal.z(), 1, 1e-9);
  // Parallel, in one plane, sliding past each other without meeting (1 apart in z all along).
  EXPECT_FALSE(
      firstHit(Primitive::EdgeEdge, pts({0, 0, 1}, {1, 0, 1}, b0, b1), pts({3, 0, 1}, {4, 0, 1}, b0, b1), 1e-6));
}

// Near-degenerate: a point crossing the face at a grazing angle (1e-6 of height over 0.14 of travel), and one that
// arrives exactly on the face at the step's end (a root at t = 1).
TEST(Ccd, NearDegenerateCases) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const auto grazing =
      firstHit(Primitive::PointTriangle, pts({0.2, 0.2, 1e-6}, a, b, c), pts({0.3, 0.3, -1e-6}, a, b, c), 1e-9);
  ASSERT_TRUE(grazing);
  EXPECT_NEAR(grazing->t, 0.5, 1e-6);
  const auto landing =
      firstHit(Primitive::PointTriangle, pts({0.2, 0.2, 1}, a, b, c), pts({0.2, 0.2, 0}, a, b, c), 1e-9);
  ASSERT_TRUE(landing);
  EXPECT_DOUBLE_EQ(landing->t, 1);
  // The triangle flattening onto the point: c rises through the point's height (a cubic with three real roots).
  const auto tilting = firstHit(Primitive::PointTriangle, pts({0.25, 0.25, 0.1}, a, b, c),
                                pts({0.25, 0.25, 0.1}, a, b, Vec3(0, 1, 1)), 1e-9);
  ASSERT_TRUE(tilting);
  EXPECT_NEAR(tilting->t, 0.4, 1e-9);  // z at the point's (x, y) = t * 0.25 reaches 0.1
}

// Every root of random cubics in [0, 1] is among the candidate times (checked by sign changes on a fine grid).
TEST(Ccd, CandidatesHoldEveryRoot) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> times;
  for (int trial = 0; trial < 2000; ++trial) {
    // Roots placed in [0, 1] on purpose: (t - r1)(t - r2)(t - r3) scaled.
    const double r1 = 0.5 + 0.5 * u(rng), r2 = 0.5 + 0.5 * u(rng), r3 = 2 * u(rng), k = u(rng);
    const std::array<double, 4> c{-k * r1 * r2 * r3, k * (r1 * r2 + r1 * r3 + r2 * r3), -k * (r1 + r2 + r3), k};
    collision::candidateTimes(c, times);
    for (const double r : {r1, r2, r3}) {
      if (r < 0 || r > 1) continue;
      double nearest = 1;
      for (const double t : times) nearest = std::min(nearest, std::abs(t - r));
      EXPECT_LT(nearest, 1e-7) << "root " << r << " of trial " << trial;
    }
  }
}

// The closest-point queries against a brute-force search over the elements' parameters.
TEST(Ccd, ClosestPointsMatchBruteForce) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 p(u(rng), u(rng), u(rng)), a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)),
        c(u(rng), u(rng), u(rng));
    double best = 1e9;
    const int n = 200;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) best = std::min(best, (p - (a + (b - a) * i / n + (c - a) * j / n)).norm());
    EXPECT_LE(collision::pointTriangle(p, a, b, c).distance, best + 1e-12);
    EXPECT_GE(collision::pointTriangle(p, a, b, c).distance, best - 0.02);
    double best_ee = 1e9;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) best_ee = std::min(best_ee, ((p + (a - p) * i / n) - (b + (c - b) * j / n)).norm());
    EXPECT_LE(collision::edgeEdge(p, a, b, c).distance, best_ee + 1e-12);
    EXPECT_GE(collision::edgeEdge(p, a, b, c).distance, best_ee - 0.02);
  }
}

// The independent test itself, on cases decided by hand.
TEST(TriangleIntersection, HandCases) {
  using testing::trianglesIntersect;
  const std::array<Vec3, 3> t{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  EXPECT_TRUE(trianglesIntersect(t, {Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1), Vec3(2, 2, 0.5)}));   // pierces
  EXPECT_FALSE(trianglesIntersect(t, {Vec3(0.2, 0.2, 0.1), Vec3(1, 0.2, 1), Vec3(0.2, 1, 1)}));   // above
  EXPECT_FALSE(trianglesIntersect(t, {Vec3(0.8, 0.8, -1), Vec3(0.8, 0.8, 1), Vec3(2, 2, 0)}));    // beside the edge
  EXPECT_TRUE(trianglesIntersect(t, {Vec3(0.1, 0.1, 0), Vec3(0.5, 0.1, 0), Vec3(0.1, 0.5, 0)}));  // coplanar, inside
  EXPECT_FALSE(trianglesIntersect(t, {Vec3(2, 2, 0), Vec3(3, 2, 0), Vec3(2, 3, 0)}));             // coplanar, apart
  // Two triangles of one rotated face, apart: coplanar up to rounding, which must not read as crossing.
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.35, Vec3(0.3, 1, 0.2).normalized()).toRotationMatrix();
  const auto turned = [&](std::array<Vec3, 3> a) {
    for (Vec3& p : a) p = r * p;
    return a;
  };
  EXPECT_FALSE(trianglesIntersect(turned({Vec3(0, 2, 2), Vec3(0, 3, 1), Vec3(0, 3, 2)}),
                                  turned({Vec3(0, 1, 2), Vec3(0, 1, 1), Vec3(0, 2, 1)})));
}

testing::ParticleTriangles surfaces(const MassSpringSystem& system) {
  testing::ParticleTriangles s;
  for (std::size_t b = 0; b < system.bodies().size(); ++b)
    testing::addSurface(s, system.bodies()[b].body.surface, system.bodies()[b].first, int(b));
  return s;
}

// A 3^3 jelly 0.4 m wide at 10 m/s straight down onto a 12 x 12 cloth one particle thick, pinned at its corners:
// without contact it passes through in a few steps. With it, no triangle pair intersects at any step's end, the
// jelly ends above the cloth, and the pass counted its work.
void jellyMeetsCloth(const char* integrator, double dt) {
  MassSpringSystem system;
  ClothParams cloth;
  cloth.nx = cloth.ny = 12;
  cloth.size_x = cloth.size_y = 2;
  cloth.center = Vec3(0, 0, 0);
  cloth.ks = 5000;
  cloth.kd = 10;
  cloth.mass = 0.05;
  cloth.pinned = clothPinSet("corners", 12, 12);
  system.addBody(buildCloth("cloth", cloth));
  JellyParams jelly;
  jelly.n = 3;
  jelly.size = 0.4;
  jelly.center = Vec3(0.05, 0.35, 0.03);
  jelly.ks = 2000;
  jelly.kd = 5;
  jelly.mass = 0.1;
  jelly.velocity = Vec3(0, -10, 0);
  system.addBody(buildJelly("jelly", jelly));
  const auto tris = surfaces(system);
  {  // The control: the integrator and the colliders alone let the jelly through the cloth, as the oracle sees.
    VecX x = system.initialPositions(), v = system.initialVelocities();
    auto alone = makeIntegrator(integrator);
    int worst = 0;
    for (int k = 0; k < int(0.1 / dt); ++k) {
      alone->step(system, k * dt, dt, x, v);
      worst = std::max(worst, testing::intersectingPairs(tris, x));
    }
    EXPECT_GT(worst, 0) << integrator;
  }
  Simulation sim(system, makeIntegrator(integrator), dt);
  ASSERT_TRUE(sim.bodyContact());
  const int jelly_first = system.bodies()[1].first;
  for (int k = 1; k <= 40; ++k) {
    ASSERT_FALSE(sim.advanceTo(k * 0.01)) << integrator;
    ASSERT_EQ(testing::intersectingPairs(tris, sim.x()), 0) << integrator << " at t = " << sim.time();
  }
  double jelly_low = 1e9, cloth_low = 1e9;
  for (int i = 0; i < system.particleCount(); ++i) {
    double& low = i >= jelly_first ? jelly_low : cloth_low;
    low = std::min(low, particle(sim.x(), i).y());
  }
  // The jelly's lowest particle above the cloth's lowest (the sag under it): it did not pass through.
  EXPECT_GT(jelly_low, cloth_low) << integrator;
  EXPECT_GT(sim.bodyContact()->ccd_hits + sim.bodyContact()->contacts, 0);
  EXPECT_LT(sim.bodyContact()->min_distance, 0.02);
}

TEST(BodyContact, FastJellyDoesNotTunnelThroughClothRk4) { jellyMeetsCloth("rk4", 2e-4); }
TEST(BodyContact, FastJellyDoesNotTunnelThroughClothBackwardEuler) { jellyMeetsCloth("backward-euler", 1.0 / 240); }

// Backward Euler's active set of pairs between bodies on a landing cloth (cloth_drop.h, 70 x 70, its first 50 steps at
// 1/60 s: it falls onto the sphere, buckles and folds onto itself): a check that changes the activity of fewer than a
// few pairs in a thousand ends the step (backward_euler.cpp, solveImpacts), and what it leaves goes to the pass after
// the step. What must hold whatever the solve leaves: no triangle pair intersecting at any step's end (the independent
// test) and the run's energy check quiet; and the landing takes at most 80 active-set solves (61 here; 104 when only
// an unchanged active set or the cap of 8 ended a step).
TEST(BodyContact, ALandingClothsStepsSettleTheirPairsWithinAFewSolves) {
  const auto system = testing::clothDrop(70);
  const auto tris = surfaces(*system);
  const double dt = 1.0 / 60;
  Simulation sim(*system, makeIntegrator("backward-euler"), dt);
  ASSERT_TRUE(sim.bodyContact());
  for (int k = 1; k <= 50; ++k) {
    ASSERT_FALSE(sim.advanceTo(k * dt));
    ASSERT_EQ(testing::intersectingPairs(tris, sim.x()), 0) << "at t = " << sim.time();
  }
  const IntegratorStats& s = sim.integrator().stats();
  EXPECT_GT(s.body_contact_steps, 10) << "the cloth never met itself in the solve";
  EXPECT_GT(sim.bodyContact()->contacts, 0);
  EXPECT_FALSE(sim.energyGain()) << sim.energyGain()->message(dt);
  EXPECT_LE(s.body_contact_active_set_solves, 80);
}

// A cloth lying collapsed on itself (the folded cloth of bench/body_contact_bench.cpp, folded_cloth.h, 64 x 64) under
// backward Euler at 1/60 s: once it has landed, the first check after a step's first solve switches a few pairs among
// tens of thousands, which ends the step as a later check would (backward_euler.cpp, solveImpacts): 2 more solves
// over the 20 steps after the landing, where a rule that let only a second check end a step took 13. What must hold
// whatever the solve leaves to the pass after the step: no triangle pair intersecting at any step's end (the
// independent test) and the run's energy check quiet.
TEST(BodyContact, ACollapsedClothSolvesAboutOnceAStep) {
  const auto system = testing::foldedCloth(64, true);
  const auto tris = surfaces(*system);
  const double dt = 1.0 / 60;
  Simulation sim(*system, makeIntegrator("backward-euler"), dt);
  ASSERT_FALSE(sim.advanceTo(30 * dt));  // the landing and collapse
  const IntegratorStats landed = sim.integrator().stats();
  const collision::Stats landed_contact = *sim.bodyContact();
  const int steps = 20;
  for (int k = 1; k <= steps; ++k) {
    ASSERT_FALSE(sim.advanceTo((30 + k) * dt));
    ASSERT_EQ(testing::intersectingPairs(tris, sim.x()), 0) << "at t = " << sim.time();
  }
  const IntegratorStats& s = sim.integrator().stats();
  EXPECT_EQ(s.body_contact_steps - landed.body_contact_steps, steps) << "the layers must touch at every step";
  EXPECT_LE(s.body_contact_active_set_solves - landed.body_contact_active_set_solves, steps / 4);
  // Its steps move some vertex by a sixth to a third of the thickness: a list padded for later steps (a skin) is
  // brought up to date where vertices left it, or left, and is not found again and again (each costs more than the
  // exact broad phase).
  const collision::Stats& c = *sim.bodyContact();
  const auto served = [](const collision::Stats& t) { return t.skin_searches + t.skin_passes; };
  EXPECT_LE(c.skin_lists - landed_contact.skin_lists, served(c) - served(landed_contact) + 1);
  EXPECT_GT(sim.bodyContact()->contacts, 0);
  EXPECT_FALSE(sim.energyGain()) << sim.energyGain()->message(dt);
}

// Two jellies far apart: the pass runs every step and finds nothing, and every byte equals the integrator's step
// followed by the colliders' resolution alone.
TEST(BodyContact, ContactFreeStepsAreTheSameBytes) {
  MassSpringSystem system;
  JellyParams a;
  a.n = 3;
  a.size = 1;
  a.center = Vec3(-3, 0, 0);
  a.velocity = Vec3(0.5, 1, 0);
  a.rotation_deg = 20;
  system.addBody(buildJelly("a", a));
  a.center = Vec3(3, 0, 0);
  system.addBody(buildJelly("b", a));
  Simulation sim(system, makeIntegrator("rk4"), 1e-3);
  ASSERT_TRUE(sim.bodyContact());
  ASSERT_FALSE(sim.advanceTo(0.2));
  VecX x = system.initialPositions(), v = system.initialVelocities();
  auto rk4 = makeIntegrator("rk4");
  for (int k = 1; k <= 200; ++k) {  // as Simulation steps: the last step lands on 0.2 exactly
    const double t = (k - 1) * 1e-3;
    rk4->step(system, t, k == 200 ? 0.2 - t : 1e-3, x, v);
  }
  EXPECT_EQ(sim.steps(), 200);
  EXPECT_EQ(std::memcmp(x.data(), sim.x().data(), sizeof(double) * x.size()), 0);
  EXPECT_EQ(std::memcmp(v.data(), sim.v().data(), sizeof(double) * v.size()), 0);
  EXPECT_EQ(sim.bodyContact()->contacts + sim.bodyContact()->ccd_hits, 0);
  EXPECT_EQ(sim.bodyContact()->passes, 200);
}

// The smallest distance reported is over the pairs within the thickness: a hanging cloth with self-contact falling
// freely (cloth_drop.h, 24 x 24, its first 10 steps under backward Euler at 1/60 s and under RK4 at 5e-4 s, before it
// meets the sphere) reports none, though the boxes of its diagonal edges and triangles meet its neighbours in the
// plane, 0.7 spacings away (a distance it must not report). Once a cloth has folded onto itself, one below the
// thickness: the folded cloth of folded_cloth.h (24 x 24, four layers), landed and collapsed on the floor (1 s,
// backward Euler). (Not the hanging cloth: under Coulomb's friction, mu 0.4, it tips off the sphere's crown and slides
// to the floor without meeting itself, see MovingFramesFindTheSameContacts.)
TEST(BodyContact, TheSmallestDistanceIsOverPairsWithinTheThickness) {
  for (const auto& [integrator, dt] : {std::pair{"backward-euler", 1.0 / 60}, std::pair{"rk4", 5e-4}}) {
    SCOPED_TRACE(integrator);
    const auto system = testing::clothDrop(24);
    Simulation sim(*system, makeIntegrator(integrator), dt);
    ASSERT_FALSE(sim.advanceTo(10 * dt));
    EXPECT_EQ(sim.bodyContact()->contacts, 0);
    EXPECT_EQ(sim.bodyContact()->min_distance, std::numeric_limits<double>::infinity());
  }
  const auto system = testing::foldedCloth(24, true);
  Simulation sim(*system, makeIntegrator("backward-euler"), 1.0 / 60);
  ASSERT_FALSE(sim.advanceTo(1.0));
  const double thickness = system->bodies()[0].body.contact.thickness;
  EXPECT_GT(sim.bodyContact()->contacts, 0);
  EXPECT_LT(sim.bodyContact()->min_distance, thickness);
}

// Two runs with the broad phase's culls on and off found the same: the same counts, the same bytes.
void expectSameRuns(const collision::Stats& cull, const VecX& x, const VecX& v, const collision::Stats& all,
                    const VecX& x_all, const VecX& v_all) {
  EXPECT_EQ(cull.contacts, all.contacts);
  EXPECT_EQ(cull.ccd_hits, all.ccd_hits);
  EXPECT_EQ(cull.zone_activations, all.zone_activations);
  EXPECT_EQ(cull.min_distance, all.min_distance);
  ASSERT_EQ(x.size(), x_all.size());
  EXPECT_EQ(std::memcmp(x.data(), x_all.data(), sizeof(double) * x.size()), 0);
  EXPECT_EQ(std::memcmp(v.data(), v_all.data(), sizeof(double) * v.size()), 0);
}

// The broad phase's culls (contact/collisions/body_collisions.h, setBroadPhaseCulls) drop only pairs that cannot be
// near or collide: the folded cloth of bench/body_contact_bench.cpp (folded_cloth.h), 20 x 20, landing on the floor and
// collapsing onto itself under backward Euler at 1/60 s (its solves' searches and the pass after the step; and the pass
// alone, `in_solve` off) and under RK4 at 5e-4 s (the pass, every step), gives the same bytes and the same counts with
// the culls as without, with contacts (and under backward Euler collisions) found on the way and no triangle pair
// intersecting at the end (the independent test); under RK4 most passes that run (not skipped while nothing is near:
// candidates/clearance.h) take the candidates kept from an earlier step (the skin), in the search for the pairs of its
// penalty layer before the step.
TEST(BodyContact, BroadPhaseCullsFindTheSameContacts) {
  struct Result {
    VecX x, v;
    collision::Stats stats;
    testing::ParticleTriangles tris;
  };
  for (const auto& [integrator, in_solve, dt, end] :
       {std::tuple{"backward-euler", true, 1.0 / 60, 0.6}, std::tuple{"backward-euler", false, 1.0 / 60, 0.6},
        std::tuple{"rk4", true, 5e-4, 0.4}}) {
    SCOPED_TRACE(std::string(integrator) + (in_solve ? "" : ", in_solve off"));
    const auto run = [&](bool cull) {
      collision::setBroadPhaseCulls(cull);
      const auto system = testing::foldedCloth(20, true);
      IntegratorOptions options;
      options.body_contact_in_solve = in_solve;
      Simulation sim(*system, makeIntegrator(integrator, options), dt);
      EXPECT_FALSE(sim.advanceTo(end));
      collision::setBroadPhaseCulls(true);
      return Result{sim.x(), sim.v(), *sim.bodyContact(), surfaces(*system)};
    };
    const Result cull = run(true), all = run(false);
    EXPECT_GT(cull.stats.contacts, 0);
    if (std::string(integrator) == "backward-euler") {
      // With the contacts in the solve the solve presses every pair before it touches (docs/body-contact.md, "Rest"):
      // no collision is left to the pass here. As the layers settle, its searches take the step skin's list, brought
      // up to date where vertices left their intervals (contact/candidates/skins.h, StepSkin).
      if (in_solve) EXPECT_GT(cull.stats.skin_updates, 0);
      else EXPECT_GT(cull.stats.ccd_hits, 0);
    } else {  // RK4's small steps: most steps that run a search for their penalty layer before the step (the pass
              // after it takes that step's list) take the candidates an earlier step found (its skin)
      EXPECT_GT(cull.stats.skin_passes + cull.stats.skin_searches, (cull.stats.passes - cull.stats.passes_skipped) / 2);
    }
    EXPECT_EQ(all.stats.skin_passes + all.stats.skin_searches + all.stats.step_rounds + all.stats.skin_updates, 0);
    EXPECT_EQ(testing::intersectingPairs(cull.tris, cull.x), 0);
    expectSameRuns(cull.stats, cull.x, cull.v, all.stats, all.x, all.v);
  }
}

// A body's pairs with itself are found in a frame that moves with the body over the step
// (contact/candidates/search.h, moving frames: a common translation changes none of the tests that follow). Two
// runs under backward Euler at 1/60 s: cloth_drop.h's 24 x 24 cloth released hanging at 3 m/s downwards: it lands
// edge first on the sphere 7 degrees from its crown, tips over to one side and slides off to the floor (Coulomb's
// friction, mu 0.4, holds a sheet lying on a sphere only within atan 0.4 = 22 degrees of the crown when nothing hangs
// on the other side: the capstan balance dT/dtheta = mu (rho g R cos theta + T) - rho g R sin theta from T = 0 at the
// crown turns negative before the equator), so it never meets itself; and a 3^3 jelly dropped at 4 m/s onto a pinned 16
// x 16 cloth with self-contact (the cloth's pairs with itself in its frame, the pairs between the two bodies in the
// world's, merged). Each gives the same bytes and counts with the culls as without (the jelly's run with contacts on
// the way) and no triangle pair intersecting at the end; in the hanging cloth's fall, before it meets anything, a broad
// phase with the culls lists under a third of the candidates that one in the world frame lists (its swept boxes reach
// along the fall, over the neighbours in the cloth's own plane). And one body meeting itself while its frame moves:
// folded_cloth.h's 20 x 20 cloth thrown along a floor without friction at 5 m/s (0.8 particle spacings a step), no air
// drag, collapsing onto itself as it lands, finds what the same cloth released at rest finds (Galilean invariance; to
// 0.3 s, before round-off, which the collapse amplifies, parts the two runs): the same contacts within 1% (seen: the
// same 4 195), the same shape carried along to 1 mm (seen 0.16 mm; the thickness is 26 mm) and no more candidates a
// broad phase than 1.2 times those at rest (seen 0.92; the world frame's 3.0); and the same bytes with the culls as
// without.
TEST(BodyContact, MovingFramesFindTheSameContacts) {
  const auto hanging = [] { return testing::clothDrop(24, Vec3(0, -3, 0)); };
  const auto trampoline = [] { return testing::jellyOnCloth(); };
  struct Result {
    VecX x, v;
    collision::Stats fall, stats;
  };
  const auto mean = [](const collision::Stats& s) { return double(s.candidates) / double(s.broad_phases); };
  for (const auto& [name, make, fall, end] : {std::tuple{"hanging cloth", std::function(hanging), 0.1, 2.0},
                                              std::tuple{"jelly on a cloth", std::function(trampoline), 0.05, 0.6}}) {
    SCOPED_TRACE(name);
    const auto run = [&](bool cull) {
      collision::setBroadPhaseCulls(cull);
      const auto system = make();
      Simulation sim(*system, makeIntegrator("backward-euler"), 1.0 / 60);
      EXPECT_FALSE(sim.advanceTo(fall));
      const collision::Stats falling = *sim.bodyContact();
      EXPECT_FALSE(sim.advanceTo(end));
      collision::setBroadPhaseCulls(true);
      EXPECT_EQ(testing::intersectingPairs(surfaces(*system), sim.x()), 0);
      return Result{sim.x(), sim.v(), falling, *sim.bodyContact()};
    };
    const Result cull = run(true), all = run(false);
    EXPECT_EQ(cull.fall.contacts + cull.fall.ccd_hits, 0) << "the fall met something";
    if (std::string(name) == "hanging cloth") {
      EXPECT_LT(mean(cull.fall), mean(all.fall) / 3)
          << "candidates a broad phase in the fall, against the world frame's";
      EXPECT_GT(cull.stats.step_updates, 0) << "no solve's end moved beyond the step list's margin";
    } else EXPECT_GT(cull.stats.contacts, 0);
    expectSameRuns(cull.stats, cull.x, cull.v, all.stats, all.x, all.v);
  }
  SCOPED_TRACE("folded cloth thrown along the floor");
  const Vec3 slide(4, 0, 3);  // m/s: 8.3 cm a step
  const auto collapse = [&](const Vec3& velocity, bool cull) {
    collision::setBroadPhaseCulls(cull);
    const auto system = testing::foldedCloth(20, true, 4, 0, 0, velocity, 0);
    Simulation sim(*system, makeIntegrator("backward-euler"), 1.0 / 60);
    EXPECT_FALSE(sim.advanceTo(0.2));
    const collision::Stats falling = *sim.bodyContact();
    EXPECT_FALSE(sim.advanceTo(0.3));
    collision::setBroadPhaseCulls(true);
    EXPECT_EQ(testing::intersectingPairs(surfaces(*system), sim.x()), 0);
    VecX carried = sim.x();  // less the slide
    for (Eigen::Index i = 0; i < carried.size(); i += 3) carried.segment<3>(i) -= velocity * sim.time();
    return Result{carried, sim.v(), falling, *sim.bodyContact()};
  };
  const Result rest = collapse(Vec3::Zero(), true), moving = collapse(slide, true), world = collapse(slide, false);
  EXPECT_EQ(moving.fall.contacts + moving.fall.ccd_hits, 0) << "the fall met something";
  EXPECT_GT(rest.stats.contacts, 0);
  EXPECT_NEAR(double(moving.stats.contacts), double(rest.stats.contacts), 0.01 * double(rest.stats.contacts));
  EXPECT_LT((moving.x - rest.x).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT(mean(moving.stats), 1.2 * mean(rest.stats)) << "candidates a broad phase, sliding against at rest";
  expectSameRuns(moving.stats, moving.x, moving.v, world.stats, world.x, world.v);
}

// Candidates kept across steps (a skin, contact/candidates/skins.h) serve a body resting on another under
// backward Euler: jelly_stack's two jellies at 1/60 s, the upper one landing on the lower and coming to rest, give the
// same bytes and counts with the broad phase's shortcuts as without, with the contacts in the solve (its near-pair
// searches take kept lists) and with the pass alone (the pass takes them). (The kept lists' reach is checked where
// bodies keep moving, by BroadPhaseCullsFindTheSameContacts: the same code keeps both.)
TEST(BodyContact, KeptCandidatesOfARestingStackFindTheSameContacts) {
  for (const bool in_solve : {true, false}) {
    SCOPED_TRACE(in_solve ? "in_solve" : "in_solve off");
    const auto run = [&](bool cull) {
      collision::setBroadPhaseCulls(cull);
      const auto system = testing::jellyStack();
      IntegratorOptions options;
      options.body_contact_in_solve = in_solve;
      Simulation sim(*system, makeIntegrator("backward-euler", options), 1.0 / 60);
      EXPECT_FALSE(sim.advanceTo(3));
      collision::setBroadPhaseCulls(true);
      return std::tuple{VecX(sim.x()), VecX(sim.v()), *sim.bodyContact()};
    };
    const auto [x, v, stats] = run(true);
    const auto [x_all, v_all, stats_all] = run(false);
    EXPECT_GT(stats.contacts, 0);
    EXPECT_GT(in_solve ? stats.skin_searches : stats.skin_passes, 0);
    EXPECT_EQ(stats_all.skin_searches + stats_all.skin_passes, 0);
    expectSameRuns(stats, x, v, stats_all, x_all, v_all);
  }
}

// Backward Euler's later near-pair searches of a step pass over the candidates whose pair an earlier search put in
// the solver's list, as long as it is still there (contact/collisions/near_pairs.cpp). Over states of
// the folded cloth collapsing onto itself, a step's searches with the shortcuts find what the exact broad phase finds
// for the same list, pair for pair and bit for bit: after the list lost every pair, a third of them (their places taken
// by others), or kept them all in another order; and on the list the first search filled itself, as the solver's is:
// kept as it was, or with one pair moved from the middle to the end (where the search's record of its place no longer
// holds).
TEST(BodyContact, LaterNearPairSearchesFindWhatLeftTheList) {
  const auto system = testing::foldedCloth(20, true);
  Simulation sim(*system, makeIntegrator("backward-euler", {}), 1.0 / 60);
  const double h = 1.0 / 60;
  const auto same = [](const std::vector<ContactPair>& a, const std::vector<ContactPair>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const ContactPair &p = a[i], &q = b[i];
      if (p.element != q.element || p.stencil.size != q.stencil.size || p.normal != q.normal ||
          p.thickness != q.thickness || p.friction != q.friction)
        return false;
      for (int j = 0; j < p.stencil.size; ++j)
        if (p.stencil.particle[j] != q.stencil.particle[j] || p.stencil.w[j] != q.stencil.w[j]) return false;
    }
    return true;
  };
  int checked = 0;
  for (const double t : {0.3, 0.45, 0.6}) {
    ASSERT_FALSE(sim.advanceTo(t));
    SCOPED_TRACE("at " + std::to_string(t) + " s");
    const VecX x0 = sim.x(), v = sim.v();
    const VecX first_end = x0 + h * v, later_end = x0 + 1.001 * h * v;  // a later solve's end, near the first
    const auto kept = collision::makeBodyCollisions(*system);
    std::vector<ContactPair> found;
    kept->nearPairs(x0, first_end, found);
    ASSERT_GT(found.size(), 30u);
    // What the solver's list holds at the later search: nothing; a third of the pairs overwritten by copies of others
    // (their places held by pairs of other elements); all of them, reversed.
    std::vector<ContactPair> thinned = found, reversed(found.rbegin(), found.rend());
    for (std::size_t i = 0; i < thinned.size(); i += 3) thinned[i] = found[(i + 1) % found.size()];
    for (const auto& [held, rejoin] :
         {std::pair{std::vector<ContactPair>{}, true}, std::pair{thinned, true}, std::pair{reversed, false}}) {
      std::vector<ContactPair> with_culls = held, exact = held;
      auto later = collision::makeBodyCollisions(*system);  // the same searches on a new instance: this step's first
      std::vector<ContactPair> scratch;
      later->nearPairs(x0, first_end, scratch);
      later->nearPairs(x0, later_end, with_culls);
      collision::setBroadPhaseCulls(false);
      collision::makeBodyCollisions(*system)->nearPairs(x0, later_end, exact);
      collision::setBroadPhaseCulls(true);
      if (rejoin) {
        EXPECT_GT(with_culls.size(), held.size()) << "no pair joined again: nothing was checked";
      }
      EXPECT_TRUE(same(with_culls, exact)) << with_culls.size() << " pairs against " << exact.size();
      ++checked;
    }
    for (const bool moved : {false, true}) {
      auto later = collision::makeBodyCollisions(*system);
      std::vector<ContactPair> own;
      later->nearPairs(x0, first_end, own);
      if (moved) {
        const ContactPair middle = own[own.size() / 2];
        own.erase(own.begin() + std::ptrdiff_t(own.size() / 2));
        own.push_back(middle);
      }
      std::vector<ContactPair> exact = own;
      later->nearPairs(x0, later_end, own);
      collision::setBroadPhaseCulls(false);
      collision::makeBodyCollisions(*system)->nearPairs(x0, later_end, exact);
      collision::setBroadPhaseCulls(true);
      EXPECT_TRUE(same(own, exact)) << own.size() << " pairs against " << exact.size();
      ++checked;
    }
  }
  EXPECT_EQ(checked, 15);
}

// What a near-pair search hands backward Euler's solve (PairJoin): of the pairs within reach (what a search without a
// rule lists), with `only` exactly the pairs of those elements, and with `pressed` exactly the pairs whose gap at the
// end lies below the penalty's rest gap by more than the slack (a quarter of the start distance, at most of the
// thickness), each predicate evaluated here on the pairs themselves,
// in the same order; every other pair within reach and not in the list yet counted as held back. On the folded cloth
// collapsing onto itself, at ends where some vertices moved by up to a thickness, for a step's first search and for a
// later one after it (whose candidates come from the first's list).
TEST(BodyContact, ASearchHandsTheSolveThePairsItsRulePicks) {
  const auto system = testing::foldedCloth(20, true);
  const double h = 1.0 / 60;
  Simulation sim(*system, makeIntegrator("backward-euler", {}), h);
  ASSERT_FALSE(sim.advanceTo(0.45));
  // Ends that press some pairs: a tenth of the vertices moved up or down by up to a thickness, and another twentieth.
  const double thickness = system->bodies()[0].body.contact.thickness;
  std::mt19937 random(11);
  const auto moved = [&](VecX end, double share) {
    for (Eigen::Index i = 0; i < end.size() / 3; ++i)
      if (std::uniform_real_distribution<double>(0, 1)(random) < share)
        end[3 * i + 1] += std::uniform_real_distribution<double>(-1, 1)(random) * thickness;
    return end;
  };
  const VecX x0 = sim.x(), first_end = moved(x0 + h * sim.v(), 0.1), later_end = moved(first_end, 0.05);
  const auto pressed = [&](const ContactPair& c, const VecX& end) {
    return c.gap(end) <
           std::min(0.0, c.gap(x0)) * (1 - 0.1) - 0.25 * std::clamp(c.gap(x0) + c.thickness, 0.0, c.thickness);
  };
  // The later search follows a first that handed over a third of the pairs within reach at the first end.
  std::vector<ContactPair> at_first, held;
  collision::makeBodyCollisions(*system)->nearPairs(x0, first_end, at_first);
  std::vector<std::array<int, 4>> thirds;
  for (std::size_t i = 0; i < at_first.size(); i += 3)
    thirds.push_back(at_first[i].element), held.push_back(at_first[i]);
  std::sort(thirds.begin(), thirds.end());
  for (const bool later : {false, true}) {
    SCOPED_TRACE(later ? "a later search" : "a step's first search");
    const VecX& end = later ? later_end : first_end;
    const std::size_t before = later ? held.size() : 0;
    // Every pair within reach, after those the solver's list holds: the exact broad phase's, without a rule.
    std::vector<ContactPair> every(held.begin(), held.begin() + std::ptrdiff_t(before));
    collision::setBroadPhaseCulls(false);
    collision::makeBodyCollisions(*system)->nearPairs(x0, end, every);
    collision::setBroadPhaseCulls(true);
    ASSERT_GT(every.size(), before + 100);
    const auto search = [&](PairJoin& join) {
      auto collisions = collision::makeBodyCollisions(*system);
      std::vector<ContactPair> out;
      if (later) {
        PairJoin first{.only = &thirds};
        collisions->nearPairs(x0, first_end, out, first);
        EXPECT_EQ(out.size(), held.size());
      }
      collisions->nearPairs(x0, end, out, join);
      EXPECT_EQ(out.size() + join.held_back, every.size()) << "pairs within reach neither handed over nor held back";
      return std::vector<ContactPair>(out.begin() + std::ptrdiff_t(before), out.end());
    };
    std::vector<std::array<int, 4>> some;
    std::vector<ContactPair> expected_only, expected_pressed;
    for (std::size_t i = before; i < every.size(); ++i) {
      if (i % 3 == 1) some.push_back(every[i].element), expected_only.push_back(every[i]);
      if (pressed(every[i], end)) expected_pressed.push_back(every[i]);
    }
    std::sort(some.begin(), some.end());
    PairJoin only{.only = &some};
    const std::vector<ContactPair> handed_only = search(only);
    PairJoin press{.pressed = true, .recovery = 0.1, .slack = 0.25};
    const std::vector<ContactPair> handed_pressed = search(press);
    ASSERT_GT(expected_pressed.size(), 10u);
    ASSERT_LT(expected_pressed.size(), (every.size() - before) / 2)
        << "the rule would pick most pairs: nothing to check";
    for (const auto& [handed, expected] :
         {std::pair{&handed_only, &expected_only}, std::pair{&handed_pressed, &expected_pressed}}) {
      ASSERT_EQ(handed->size(), expected->size());
      for (std::size_t i = 0; i < expected->size(); ++i) {
        ASSERT_EQ((*handed)[i].element, (*expected)[i].element) << "pair " << i;
        ASSERT_EQ((*handed)[i].normal, (*expected)[i].normal) << "pair " << i;
      }
    }
  }
}

// Backward Euler's step lists are kept from step to step and brought up to date where vertices left their intervals
// (contact/candidates/skins.h, StepSkin). Over 24 steps of the folded cloth collapsing onto itself, a
// search at each step's start by one instance kept throughout finds what a new instance with the exact broad phase
// finds, pair for pair and bit for bit, at ends where a random 8% of the vertices lie up to three thicknesses above or
// below their own (towards or through the layers beside them: beyond their intervals at the end only).
TEST(BodyContact, KeptStepListsFindWhatTheBroadPhaseFinds) {
  const auto system = testing::foldedCloth(20, true);
  const double h = 1.0 / 60, thickness = system->bodies()[0].body.contact.thickness;
  Simulation sim(*system, makeIntegrator("backward-euler", {}), h);
  ASSERT_FALSE(sim.advanceTo(0.25));
  const auto kept = collision::makeBodyCollisions(*system);
  std::mt19937 random(7);
  for (int step = 0; step < 24; ++step) {
    ASSERT_FALSE(sim.advanceTo(0.25 + (step + 1) * h));
    SCOPED_TRACE("at " + std::to_string(sim.time()) + " s");
    const VecX x0 = sim.x();
    VecX end = x0 + h * sim.v();
    for (Eigen::Index i = 0; i < end.size() / 3; ++i)
      if (std::uniform_real_distribution<double>(0, 1)(random) < 0.08)
        end[3 * i + 1] += std::uniform_real_distribution<double>(-3, 3)(random) * thickness;
    std::vector<ContactPair> with_culls, exact;
    kept->nearPairs(x0, end, with_culls);
    collision::setBroadPhaseCulls(false);
    collision::makeBodyCollisions(*system)->nearPairs(x0, end, exact);
    collision::setBroadPhaseCulls(true);
    ASSERT_EQ(with_culls.size(), exact.size());
    for (std::size_t i = 0; i < exact.size(); ++i) {
      ASSERT_EQ(with_culls[i].element, exact[i].element) << "pair " << i;
      ASSERT_EQ(with_culls[i].normal, exact[i].normal) << "pair " << i;
    }
  }
  const collision::Stats& stats = kept->stats();
  EXPECT_GE(stats.skin_searches, 12) << "the kept lists served under half the steps";
  EXPECT_GT(stats.skin_updates, 8) << "the kept lists were hardly brought up to date";
}

// A step whose broad phase would list more candidate pairs than its budget (Settings::candidates_per_vertex,
// min_candidates) stops the run like a blow-up, saying why and what to try, instead of filling memory: the folded
// cloth with a budget of 2 pairs per vertex and no floor (it lists about 40 a vertex once its layers lie on each
// other) stops at the first step that needs more, under
// backward Euler with the contacts in its solve and with the pass alone, and under RK4; with the default budget it
// runs on (BroadPhaseCullsFindTheSameContacts).
TEST(BodyContact, ABroadPhaseOverItsBudgetStopsTheRun) {
  for (const auto& [integrator, in_solve, dt] :
       {std::tuple{"backward-euler", true, 1.0 / 60}, std::tuple{"backward-euler", false, 1.0 / 60},
        std::tuple{"rk4", true, 5e-4}}) {
    SCOPED_TRACE(std::string(integrator) + (in_solve ? "" : ", in_solve off"));
    const auto system = testing::foldedCloth(20, true);
    collision::Settings settings = system->contactSettings();
    settings.candidates_per_vertex = 2;
    settings.min_candidates = 0;
    system->setContactSettings(settings);
    IntegratorOptions options;
    options.body_contact_in_solve = in_solve;
    Simulation sim(*system, makeIntegrator(integrator, options), dt);
    const auto stop = sim.advanceTo(0.6);
    ASSERT_TRUE(stop.has_value());
    EXPECT_NE(stop->reason.find("more than 800 candidate pairs in this step (400 surface vertices)"), std::string::npos)
        << stop->reason;
    EXPECT_NE(stop->message(dt).find("Try a smaller time step"), std::string::npos);
    EXPECT_LT(stop->time, 0.6);
    EXPECT_TRUE(sim.x().allFinite());
  }
}

// A budget only ever stops a run; it never thins what the broad phase lists. Over a range of budgets, each run of
// the folded cloth either stops with the budget's message or ends on the same bytes as the run without a budget:
// among them budgets the point-triangle pairs fit in and the edge-edge pairs then overflow.
TEST(BodyContact, ABudgetStopsTheRunOrChangesNothing) {
  const auto run = [](long budget, std::optional<BlowUp>& stop) {
    const auto system = testing::foldedCloth(20, true);
    collision::Settings settings = system->contactSettings();
    if (budget > 0) settings.candidates_per_vertex = 0, settings.min_candidates = budget;
    system->setContactSettings(settings);
    Simulation sim(*system, makeIntegrator("backward-euler", {}), 1.0 / 60);
    stop = sim.advanceTo(0.6);
    return VecX(sim.x());
  };
  std::optional<BlowUp> stop;
  const VecX free = run(0, stop);
  ASSERT_FALSE(stop.has_value());
  int stopped = 0, ran = 0;
  for (long budget = 1000; budget <= 40000; budget = budget * 3 / 2) {
    SCOPED_TRACE("budget " + std::to_string(budget));
    const VecX x = run(budget, stop);
    if (stop) {
      ++stopped;
      EXPECT_NE(stop->reason.find("more than " + std::to_string(budget) + " candidate pairs"), std::string::npos)
          << stop->reason;
      continue;
    }
    ++ran;
    ASSERT_EQ(x.size(), free.size());
    EXPECT_EQ(std::memcmp(x.data(), free.data(), sizeof(double) * x.size()), 0);
  }
  EXPECT_GT(stopped, 0);
  EXPECT_GT(ran, 0);
}

}  // namespace
}  // namespace wobble
