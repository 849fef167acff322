// Detection skipped while nothing can come near (sim/contact/candidates/clearance.h): a step skips the pass only
// where the pass would have found nothing. Each run is compared with the same run that detects at every step
// (setSkipWhileApart(false)): the same bytes of every position and velocity, and the same contacts, collisions and
// smallest distance; and checked by the independent triangle-triangle test (tests/sim/triangle_intersection.h). Where
// nothing comes near, the skipped passes are counted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <tuple>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/contact/candidates/clearance.h"
#include "sim/contact/collisions/body_collisions.h"
#include "sim/contact/distance/separation.h"
#include "sim/simulation.h"
#include "tests/sim/cloth_on_sphere.h"
#include "tests/sim/folded_cloth.h"
#include "tests/sim/jelly_on_cloth.h"
#include "tests/sim/jelly_stack.h"
#include "tests/sim/triangle_intersection.h"

namespace wobble {
namespace {

struct Outcome {
  VecX x, v;
  collision::Stats stats;
  int most_intersecting = 0;  // the most intersecting triangle pairs at any checked step's end
};

testing::ParticleTriangles surfaces(const MassSpringSystem& system) {
  testing::ParticleTriangles s;
  for (std::size_t b = 0; b < system.bodies().size(); ++b)
    testing::addSurface(s, system.bodies()[b].body.surface, system.bodies()[b].first, int(b));
  return s;
}

// `system` run to `end` under `integrator` at dt, with skipping on or off; the independent test every `every` steps.
Outcome run(const std::function<std::unique_ptr<MassSpringSystem>()>& make, const std::string& integrator, double dt,
            double end, bool skip, int every = 10) {
  collision::setSkipWhileApart(skip);
  const auto system = make();
  const testing::ParticleTriangles tris = surfaces(*system);
  Simulation sim(*system, makeIntegrator(integrator), dt);
  Outcome r;
  int step = 0;
  sim.observeSteps([&](double, const VecX& x) {
    if (++step % every == 0) r.most_intersecting = std::max(r.most_intersecting, testing::intersectingPairs(tris, x));
  });
  EXPECT_FALSE(sim.advanceTo(end));
  collision::setSkipWhileApart(true);
  r.x = sim.x(), r.v = sim.v(), r.stats = *sim.bodyContact();
  r.most_intersecting = std::max(r.most_intersecting, testing::intersectingPairs(tris, sim.x()));
  return r;
}

void expectSame(const Outcome& skip, const Outcome& every) {
  EXPECT_EQ(skip.stats.passes, every.stats.passes);
  EXPECT_EQ(skip.stats.contacts, every.stats.contacts);
  EXPECT_EQ(skip.stats.ccd_hits, every.stats.ccd_hits);
  EXPECT_EQ(skip.stats.zone_activations, every.stats.zone_activations);
  EXPECT_EQ(skip.stats.min_distance, every.stats.min_distance);
  ASSERT_EQ(skip.x.size(), every.x.size());
  EXPECT_EQ(std::memcmp(skip.x.data(), every.x.data(), sizeof(double) * skip.x.size()), 0) << "positions differ";
  EXPECT_EQ(std::memcmp(skip.v.data(), every.v.data(), sizeof(double) * skip.v.size()), 0) << "velocities differ";
  EXPECT_EQ(every.stats.passes_skipped + every.stats.searches_skipped + every.stats.clearance_measures, 0);
}

// One body of three triangles, self-contact on, thickness 0.02: particles 0-2 the top one, 6-8 the bottom one, 3-5
// the middle one, far aside.
struct ThreeTriangles {
  static SurfaceMesh triangles() {
    SurfaceMesh m;
    for (int i = 0; i < 9; ++i) m.particle.push_back(i);
    m.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
    return m;
  }
  // The top and bottom ones `apart` above and below the origin, the middle one 5 aside.
  static VecX at(double apart) {
    const std::array<Vec3, 3> corner{Vec3(0, 0, 0), Vec3(0.3, 0, 0), Vec3(0, 0, 0.3)};
    VecX x(27);
    for (int t = 0; t < 3; ++t)
      for (int k = 0; k < 3; ++k)
        particle(x, 3 * t + k) = corner[k] + (t == 0 ? Vec3(0, apart, 0) : t == 2 ? Vec3(0, -apart, 0) : Vec3(5, 0, 0));
    return x;
  }
  SurfaceMesh mesh = triangles();  // (the members below are made in this order, each from those above)
  std::vector<collision::Surface> surfaces{{&mesh, 0, SurfaceContact{0.02, 0.3, true}, 1000.0}};
  VecX inverse_mass = VecX::Ones(9);
  collision::Stats stats;
  collision::SurfaceNodes nodes{surfaces, inverse_mass};
  collision::NodeMotion motion;
  collision::Settings settings;
  collision::CandidateSearch search{nodes, motion, settings, false, stats};
  collision::Clearance clearance{nodes, search, false, stats};
};

// Whether points sampled on the top and bottom triangles at some instant of a straight step from x0 to x1 lie closer
// than the thickness (an upper bound of their distance: a witness that they come within it).
bool comeWithinTheThickness(const VecX& x0, const VecX& x1) {
  for (int k = 0; k <= 8; ++k) {
    const VecX x = (1 - k / 8.0) * x0 + k / 8.0 * x1;
    std::vector<Vec3> top, bottom;
    constexpr int kSteps = 16;
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; i + j <= kSteps; ++j) {
        const double u = double(i) / kSteps, v = double(j) / kSteps;
        top.push_back((1 - u - v) * particle(x, 0) + u * particle(x, 1) + v * particle(x, 2));
        bottom.push_back((1 - u - v) * particle(x, 6) + u * particle(x, 7) + v * particle(x, 8));
      }
    for (const Vec3& a : top)
      for (const Vec3& b : bottom)
        if ((a - b).norm() < 0.02) return true;
  }
  return false;
}

// The bound itself, against an independent witness (comeWithinTheThickness): the top triangle 0.06 above the origin,
// the bottom one 0.06 below it. A step moves the top one down and the bottom one up by d each (the middle one stays,
// in the middle of the body's displacements: the worst case of the bound's factor 2), all three by a common random
// translation, and each particle by a little noise. Whenever the witness finds the triangles within the thickness, the
// clearance must not cover the step; it does cover the steps that stay well apart.
TEST(Clearance, NeverCoversAStepThatBringsTwoElementsWithinTheThickness) {
  const VecX reference = ThreeTriangles::at(0.06);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> closing(0, 0.1), unit(-1, 1);
  int covered = 0, within = 0;
  for (int trial = 0; trial < 300; ++trial) {
    ThreeTriangles body;
    ASSERT_TRUE(body.clearance.covers(reference, reference));  // measured there: the triangles are 0.12 apart
    const double d = closing(random);
    const Vec3 common(unit(random), unit(random), unit(random));
    VecX x1 = reference;
    for (int i = 0; i < 9; ++i)
      particle(x1, i) += common +
                         (i < 3    ? Vec3(0, -d, 0)
                          : i >= 6 ? Vec3(0, d, 0)
                                   : Vec3::Zero()) +
                         1e-3 * Vec3(unit(random), unit(random), unit(random));
    const bool near = comeWithinTheThickness(reference, x1), covers = body.clearance.covers(reference, x1);
    EXPECT_FALSE(near && covers) << "covered a step whose triangles come within the thickness: d = " << d;
    covered += covers;
    within += near;
  }
  EXPECT_GT(covered, 50);
  EXPECT_GT(within, 50);
}

// The same witness over a run of steps: the top and bottom triangles, 0.6 apart, close in on each other by 2 mm a step
// each until they pass through each other, all three drifting sideways, each particle with a little noise. The
// clearance measured again and again, ahead of the step's start once a measure has served to its end (the reference a
// state the run never passes through), never covers a step the witness finds within the thickness.
TEST(Clearance, MeasuresAheadNeverCoverAStepThatBringsTwoElementsWithinTheThickness) {
  ThreeTriangles body;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  int covered = 0, within = 0;
  VecX x0 = ThreeTriangles::at(0.3);
  for (int step = 1; step <= 170; ++step) {
    VecX x1 = ThreeTriangles::at(0.3 - 0.002 * step);
    for (int i = 0; i < 9; ++i)
      particle(x1, i) += Vec3(0.01, 0, 0.004) * step + 1e-4 * Vec3(unit(random), unit(random), unit(random));
    const bool near = comeWithinTheThickness(x0, x1), covers = body.clearance.covers(x0, x1);
    EXPECT_FALSE(near && covers) << "covered step " << step << ", whose triangles come within the thickness";
    covered += covers;
    within += near;
    if (!covers) body.clearance.passed(near);
    x0 = x1;
  }
  EXPECT_GT(covered, 100);
  EXPECT_GT(within, 5);
  EXPECT_GE(body.stats.clearance_measures, 4);
}

// The same run of steps checked twice: each call on its own, and with the pass after each step vouching that the step
// starts where the last one ended (continues: the start's spread taken from the last covered step's end). Every other
// step first checks a trial end far from its own (as backward Euler's searches do, not final), and a step not covered
// has its end moved before the next starts there (as the pass's impulses do). The two decide every call alike.
TEST(Clearance, ContinuingStepsDecideAsStepsOnTheirOwn) {
  ThreeTriangles alone, continuing;
  std::mt19937 random(13);
  std::uniform_real_distribution<double> unit(-1, 1);
  int covered = 0, differ = 0;
  VecX x0 = ThreeTriangles::at(0.3);
  for (int step = 1; step <= 170; ++step) {
    VecX x1 = ThreeTriangles::at(0.3 - 0.002 * step);
    for (int i = 0; i < 9; ++i)
      particle(x1, i) += Vec3(0.01, 0, 0.004) * step + 1e-4 * Vec3(unit(random), unit(random), unit(random));
    if (step % 2 == 0) {
      VecX trial = x1;
      for (int i = 0; i < 9; ++i) particle(trial, i) += 0.03 * Vec3(unit(random), unit(random), unit(random));
      differ += alone.clearance.covers(x0, trial) != continuing.clearance.covers(x0, trial);
    }
    const bool near = comeWithinTheThickness(x0, x1), by_itself = alone.clearance.covers(x0, x1, {.final_pass = true}),
               continued = continuing.clearance.covers(x0, x1, {.final_pass = true, .continues = step > 1});
    differ += by_itself != continued;
    EXPECT_FALSE(near && continued) << "covered step " << step << ", whose triangles come within the thickness";
    covered += continued;
    if (!by_itself) alone.clearance.passed(near);
    if (!continued) continuing.clearance.passed(near);
    if (!continued)
      for (int i = 0; i < 9; ++i) particle(x1, i) += 0.01 * Vec3(unit(random), unit(random), unit(random));
    x0 = x1;
  }
  EXPECT_EQ(differ, 0);
  EXPECT_GT(covered, 100);
  EXPECT_EQ(continuing.stats.clearance_measures, alone.stats.clearance_measures);
}

// The measured clearance against the nearest pair of elements the pass tests, found independently: points sampled on
// every vertex-triangle pair (the vertex not on the triangle) and edge-edge pair (no node shared) of one body of two
// 5 x 5 grid sheets, 0.1 apart, one over the other at a random height, with random noise: near pairs within each sheet
// and across. The clearance (found through the pairs of triangles whose boxes overlap) is at most the sampled least
// distance; and where the nearest pair is within 5 thicknesses (below the cap of what a measure looks for), it is the
// least of every such pair's bound (the gap along its nearest points' direction), each pair taken in turn.
TEST(Clearance, MeasuresTheNearestPairOfTwoSheets) {
  constexpr int n = 5, sheet = n * n;
  constexpr double spacing = 0.1, thickness = 0.02;
  SurfaceMesh mesh;
  for (int i = 0; i < 2 * sheet; ++i) mesh.particle.push_back(i);
  for (int s = 0; s < 2; ++s)
    for (int i = 0; i + 1 < n; ++i)
      for (int j = 0; j + 1 < n; ++j) {
        const int a = s * sheet + i * n + j, b = a + 1, c = a + n, d = c + 1;
        mesh.triangles.push_back({a, b, d});
        mesh.triangles.push_back({a, d, c});
      }
  std::vector<collision::Surface> surfaces{{&mesh, 0, SurfaceContact{thickness, 0.3, true}, 1000.0}};
  const VecX inverse_mass = VecX::Ones(6 * sheet);
  collision::Stats stats;
  collision::SurfaceNodes nodes{surfaces, inverse_mass};
  collision::NodeMotion motion;
  collision::Settings settings;
  collision::CandidateSearch search{nodes, motion, settings, false, stats};
  std::mt19937 random(17);
  std::uniform_real_distribution<double> unit(-1, 1), height(0.01, 0.15);
  int tight = 0;
  for (int trial = 0; trial < 40; ++trial) {
    // The upper sheet at the height, each node with noise of a fifth of the spacing; every other trial shifted so
    // that its nodes lie over the lower sheet's triangles, every other node lowered by half the height (nearest to the
    // lower sheet are those nodes, over triangles), with noise of a fiftieth.
    const bool poked = trial % 2 == 1;
    const double over = height(random), noise = poked ? 0.002 : 0.02;
    VecX x(6 * sheet);
    for (int s = 0; s < 2; ++s)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          Vec3 at(j * spacing, 0, i * spacing);
          if (s == 1)
            at += Vec3(0, over, 0) +
                  (poked ? Vec3(0.5 * spacing, -0.5 * over * ((i + j) % 2), 0.3 * spacing) : Vec3::Zero());
          particle(x, s * sheet + i * n + j) = at + noise * Vec3(unit(random), unit(random), unit(random));
        }
    collision::Clearance clearance{nodes, search, false, stats};
    clearance.covers(x, x);
    // The sampled least distance (each sample a point of the element: an upper bound of its pair's distance).
    const auto samples = [&](std::initializer_list<int> corners, int steps) {
      const std::vector<int> c(corners);
      std::vector<Vec3> out;
      for (int a = 0; a <= steps; ++a)
        for (int b = 0; b <= (c.size() == 3 ? steps - a : 0); ++b) {
          const double u = double(a) / steps, v = double(b) / steps;
          out.push_back(c.size() == 1 ? particle(x, c[0])
                        : c.size() == 2
                            ? Vec3((1 - u) * particle(x, c[0]) + u * particle(x, c[1]))
                            : Vec3((1 - u - v) * particle(x, c[0]) + u * particle(x, c[1]) + v * particle(x, c[2])));
        }
      return out;
    };
    const auto least = [](const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
      double d = std::numeric_limits<double>::infinity();
      for (const Vec3& p : a)
        for (const Vec3& q : b) d = std::min(d, (p - q).norm());
      return d;
    };
    double sampled = std::numeric_limits<double>::infinity();
    for (int v = 0; v < 2 * sheet; ++v)
      for (const auto& t : mesh.triangles)
        if (v != t[0] && v != t[1] && v != t[2])
          sampled = std::min(sampled, least(samples({v}, 1), samples({t[0], t[1], t[2]}, 16)));
    for (std::size_t e = 0; e < nodes.edges.size(); ++e)
      for (std::size_t f = e + 1; f < nodes.edges.size(); ++f) {
        const auto &p = nodes.edges[e], &q = nodes.edges[f];
        if (p[0] != q[0] && p[0] != q[1] && p[1] != q[0] && p[1] != q[1])
          sampled = std::min(sampled, least(samples({p[0], p[1]}, 16), samples({q[0], q[1]}, 16)));
      }
    // Every pair's bound, as a measure takes it.
    double bound = std::numeric_limits<double>::infinity();
    const auto take = [&](collision::Primitive kind, int first, int second) {
      const auto q = nodes.nodes(kind, first, second);
      const auto c =
          collision::nearest(kind, {particle(x, q[0]), particle(x, q[1]), particle(x, q[2]), particle(x, q[3])});
      const int split = kind == collision::Primitive::PointTriangle ? 1 : 2;
      bound = std::min(bound, c.distance > 0 ? collision::gapAlong(c.delta / c.distance, x, q, split) : 0.0);
    };
    for (int v = 0; v < 2 * sheet; ++v)
      for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        if (const auto& c = mesh.triangles[t]; v != c[0] && v != c[1] && v != c[2])
          take(collision::Primitive::PointTriangle, v, int(t));
    for (std::size_t e = 0; e < nodes.edges.size(); ++e)
      for (std::size_t f = e + 1; f < nodes.edges.size(); ++f)
        if (const auto& p = nodes.edges[e], &q = nodes.edges[f];
            p[0] != q[0] && p[0] != q[1] && p[1] != q[0] && p[1] != q[1])
          take(collision::Primitive::EdgeEdge, int(e), int(f));
    SCOPED_TRACE("sheets " + std::to_string(over) + " apart" + ", sampled least distance " + std::to_string(sampled));
    EXPECT_LE(clearance.clearance(), sampled) << "a pair nearer than the clearance";
    if (bound < 5 * thickness) {
      ++tight;
      EXPECT_EQ(clearance.clearance(), bound);
    }
  }
  EXPECT_GT(tight, 10);
}

// cloth_sphere's cloth (the course's scene, 25 x 25, corners pinned) draping over the sphere under explicit Euler at
// 1e-4 s, its own self-contact on: no two of its elements come within the thickness, and nearly every pass is
// skipped, with the same bytes as a run that detects at every step.
TEST(Clearance, ADrapingClothWithNothingNearSkipsNearlyEveryPass) {
  const auto make = [] { return testing::clothOnSphere(25, ClothParams{}.ks, true); };
  const Outcome skip = run(make, "explicit-euler", 1e-4, 0.3, true, 500),
                every = run(make, "explicit-euler", 1e-4, 0.3, false, 500);
  EXPECT_EQ(every.stats.contacts + every.stats.ccd_hits, 0) << "something came near";
  EXPECT_GT(skip.stats.passes_skipped, skip.stats.passes * 95 / 100)
      << skip.stats.passes_skipped << " of " << skip.stats.passes << " passes skipped";
  EXPECT_EQ(skip.most_intersecting, 0);
  expectSame(skip, every);
}

// Runs that do come close, each the same bytes as with detection at every step, some passes skipped on the way, and
// no triangle pair intersecting at any checked step's end: the folded 20 x 20 cloth (folded_cloth.h) falling onto
// the floor and collapsing onto itself, under RK4 at 5e-4 s and backward Euler at 1/60 s (whose near-pair searches
// skip too); jelly_stack's two jellies (the upper falls onto the lower: pairs of two bodies, each body's shift); and a
// jelly thrown onto a pinned cloth with self-contact.
TEST(Clearance, SkippingKeepsEveryContact) {
  const auto folded = [] { return testing::foldedCloth(20, true); };
  const auto stack = [] { return testing::jellyStack(); };
  const auto trampoline = [] { return testing::jellyOnCloth(); };
  using Make = std::function<std::unique_ptr<MassSpringSystem>()>;
  for (const auto& [name, make, integrator, dt, end] :
       {std::tuple{"folded cloth", Make(folded), "rk4", 5e-4, 0.6},
        std::tuple{"folded cloth", Make(folded), "backward-euler", 1.0 / 60, 1.0},
        std::tuple{"jelly stack", Make(stack), "rk4", 1e-3, 1.2},
        std::tuple{"jelly stack", Make(stack), "backward-euler", 1.0 / 240, 1.2},
        std::tuple{"jelly on a cloth", Make(trampoline), "rk4", 2.5e-4, 0.6}}) {
    SCOPED_TRACE(std::string(name) + ", " + integrator);
    const Outcome skip = run(make, integrator, dt, end, true), every = run(make, integrator, dt, end, false);
    EXPECT_GT(every.stats.contacts + every.stats.ccd_hits, 0) << "nothing came near";
    EXPECT_GT(skip.stats.passes_skipped, 0) << "no pass skipped";
    EXPECT_EQ(skip.most_intersecting, 0);
    expectSame(skip, every);
  }
}

}  // namespace
}  // namespace wobble
