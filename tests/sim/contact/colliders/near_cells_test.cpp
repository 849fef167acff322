// Contact blends an embedded surface's points only in the cells a collider may be near (contact/colliders/response.h,
// nearPoints; Collider::mayBeNear). Oracles: each collider's own near() on points, and the same contact with the filter
// off.
//  - mayBeNear never says no for a box holding a point near() keeps (random boxes and points, every collider kind),
//    and does say no for most boxes away from the surface (the filter filters);
//  - on a mesh jelly striking a floor, a moving sphere, a box and a mesh, every point near() keeps on the blend of
//    every point lies in a cell the collider may be near and in that cell's box, and the contact forces, the step
//    ends' impacts, the colliders' work and a whole run are bit for bit those of the same colliders without the
//    filter (every cell asked, every point blended: the contact code before the filter);
//  - a cell's points tested four at a time (the half-space filter's loop) are those each point's own blend keeps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <random>

#include "sim/bodies/mesh_jelly.h"
#include "sim/contact/colliders/box.h"
#include "sim/contact/colliders/elevator.h"
#include "sim/contact/colliders/mesh.h"
#include "sim/contact/colliders/plane.h"
#include "sim/contact/colliders/response.h"
#include "sim/contact/colliders/sphere.h"
#include "sim/simulation.h"
#include "tests/sim/test_models.h"

namespace wobble {
namespace {

// A collider that forwards everything but mayBeNear, which it leaves at the default (true): contact without the filter.
class EveryCell final : public Collider {
 public:
  explicit EveryCell(std::unique_ptr<Collider> inner)
      : Collider(inner->name(), inner->contact()), inner_(std::move(inner)) {}
  std::optional<SurfacePoint> query(double t, const Vec3& x) const override { return inner_->query(t, x); }
  void near(double t, const StateRef& x, double margin, std::vector<int>& out) const override {
    inner_->near(t, x, margin, out);
  }
  std::optional<Eigen::AlignedBox3d> bounds(double t) const override { return inner_->bounds(t); }
  bool isStatic() const override { return inner_->isStatic(); }

 private:
  std::unique_ptr<Collider> inner_;
};

std::unique_ptr<MeshCollider> meshBox(const Vec3& corner, const Vec3& size, const Vec3& velocity) {
  ModelMesh m = testing::box(size);
  for (Vec3& p : m.points) p += corner;
  return std::make_unique<MeshCollider>("block", ContactParams{0.4, 0.5, 0.01}, m.points, m.triangles, velocity);
}

// An open mesh: one sheet (two triangles) facing up, 3 x 3 m about the origin at height y.
std::unique_ptr<MeshCollider> sheet(double y) {
  std::vector<Vec3> p{{-1.5, y, -1.5}, {1.5, y, -1.5}, {1.5, y, 1.5}, {-1.5, y, 1.5}};
  return std::make_unique<MeshCollider>("sheet", ContactParams{}, p,
                                        std::vector<std::array<int, 3>>{{0, 2, 1}, {0, 3, 2}}, Vec3::Zero());
}

// Every collider kind, placed about the origin.
std::vector<std::unique_ptr<Collider>> everyKind() {
  std::vector<std::unique_ptr<Collider>> c;
  c.push_back(std::make_unique<PlaneCollider>("plane", ContactParams{}, Vec3(0, 0.5, 0), Vec3(1, 2, 0.5)));
  c.push_back(std::make_unique<SphereCollider>("sphere", ContactParams{}, Vec3(0.1, 0, 0), 1.5, Vec3(0.2, 0, 0)));
  c.push_back(std::make_unique<ElevatorCollider>("elevator", ContactParams{}, ElevatorSchedule{}, 3, 0.5));
  c.push_back(std::make_unique<BoxCollider>("box", ContactParams{}, Vec3(0.3, -0.2, 0.1), Vec3(2, 1, 1.5)));
  c.push_back(meshBox(Vec3(-1, -0.5, -0.8), Vec3(2, 1.2, 1.6), Vec3(0.1, 0, 0)));
  c.push_back(sheet(0.2));
  return c;
}

TEST(NearCells, MayBeNearHoldsEveryBoxWithAPointNearKeeps) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> centre(-2, 2), unit(0, 1);
  const double margin = 0.05, t = 0.7;
  for (const auto& collider : everyKind()) {
    int kept_boxes = 0, refused = 0, refused_far = 0, far = 0;
    for (int b = 0; b < 4000; ++b) {
      const Vec3 c(centre(rng), centre(rng), centre(rng));
      const Vec3 half = (b % 4 == 0 ? 0.0 : 0.3) * Vec3(unit(rng), unit(rng), unit(rng));  // a quarter are points
      const Eigen::AlignedBox3d box(c - half, c + half);
      // Points of the box: its 8 corners and random ones inside.
      const int n = 40;
      VecX x(3 * n);
      for (int i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a)
          x[3 * i + a] = i < 8 ? (i >> a & 1 ? box.max()[a] : box.min()[a]) : box.min()[a] + 2 * half[a] * unit(rng);
      std::vector<int> near;
      collider->near(t, x, margin, near);
      const bool may = collider->mayBeNear(t, box, margin);
      if (!near.empty()) {
        ++kept_boxes;
        EXPECT_TRUE(may) << collider->name() << ": a box holding a near point at " << c.transpose();
      }
      if (!may) ++refused;
      // Far from the collider's bounds (or, for the plane, from the plane itself): no point of it can be near.
      const auto bounds = collider->bounds(t);
      const double away =
          bounds ? std::sqrt(box.squaredExteriorDistance(*bounds)) : collider->query(t, c)->distance - half.norm();
      if (away > margin + 0.1) ++far, refused_far += !may;
    }
    EXPECT_GT(kept_boxes, 100) << collider->name();   // the random boxes do meet the surface
    EXPECT_GT(refused, 400) << collider->name();      // and the test does refuse boxes
    EXPECT_EQ(refused_far, far) << collider->name();  // every box clearly away from it
  }
}

// Jelly and colliders of the oracle scene: a mesh jelly (a sphere of 0.5 m) falling onto a floor, its sides striking a
// moving sphere, a box and a moving mesh block. filtered = false wraps each collider in EveryCell.
std::unique_ptr<MassSpringSystem> scene(bool filtered) {
  auto system = std::make_unique<MassSpringSystem>();
  MeshJellyParams p{.cells = 6, .ks = 1500, .kd = 5};
  p.placement.center = Vec3(0, 0.62, 0);
  p.velocity = Vec3(0.2, -1.5, 0.1);
  system->addBody(buildMeshJelly("jelly", testing::uvSphere(0.5, 24, 48), p));
  std::vector<std::unique_ptr<Collider>> c;
  c.push_back(std::make_unique<PlaneCollider>("floor", ContactParams{0.3, 0.6, 0.01}, Vec3::Zero(), Vec3(0.05, 1, 0)));
  c.push_back(std::make_unique<SphereCollider>("ball", ContactParams{0.5, 0.4, 0.01}, Vec3(0.62, 0.3, 0.1), 0.25,
                                               Vec3(-0.1, 0, 0)));
  c.push_back(
      std::make_unique<BoxCollider>("crate", ContactParams{0.2, 0.5, 0.01}, Vec3(-0.7, 0.2, 0), Vec3(0.5, 0.4, 0.6)));
  c.push_back(meshBox(Vec3(-0.3, 0, 0.45), Vec3(0.6, 0.3, 0.4), Vec3(0, 0, -0.05)));
  for (auto& collider : c)
    system->addCollider(filtered ? std::move(collider) : std::make_unique<EveryCell>(std::move(collider)));
  system->setStepSize(1e-3);
  return system;
}

bool sameBits(const VecX& a, const VecX& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

TEST(NearCells, FilteredContactIsExactlyEveryPointBlended) {
  const auto filtered = scene(true), oracle = scene(false);
  const WeightedPoints& points = filtered->embeddedPoints();
  ASSERT_GT(points.size(), 1000);
  Simulation sim(*filtered, makeIntegrator("rk4"), 1e-3);
  std::vector<int> touched(filtered->colliders().size(), 0);  // points near each collider, over the states below
  int asked_cells = 0, cells = 0;
  for (int k = 1; k <= 40; ++k) {
    ASSERT_FALSE(sim.advanceTo(0.01 * k));
    const double t = sim.time();
    const VecX &x = sim.x(), &v = sim.v();
    // Every point near() keeps among all the blends lies in a cell the collider may be near, inside its box.
    VecX all;
    points.blendAll(x, all);
    std::vector<Eigen::AlignedBox3d> boxes;
    points.cellBounds(x, boxes);
    for (std::size_t c = 0; c < filtered->colliders().size(); ++c) {
      const Collider& collider = *filtered->colliders()[c];
      std::vector<int> near, listed;
      collider.near(t, all, collider.contact().epsilon, near);
      touched[c] += int(near.size());
      for (const int p : near) {
        EXPECT_TRUE(collider.mayBeNear(t, boxes[points.cell(p)], collider.contact().epsilon)) << collider.name();
        EXPECT_TRUE(boxes[points.cell(p)].contains(particle(all, p))) << collider.name();
      }
      VecX at;
      CellBoxes cell_boxes;
      nearPoints(collider, t, points, x, cell_boxes, collider.contact().epsilon, listed, at);
      EXPECT_EQ(listed, near) << collider.name() << " at t = " << t;
      for (const auto& box : boxes) asked_cells += collider.mayBeNear(t, box, collider.contact().epsilon);
      cells += points.cellCount();
    }
    // The same forces, impacts and work with the filter off, to the bit.
    VecX f_filtered, f_oracle;
    filtered->force(t, x, v, f_filtered);
    oracle->force(t, x, v, f_oracle);
    EXPECT_TRUE(sameBits(f_filtered, f_oracle)) << "contact forces at t = " << t;
    VecX x1 = x, v1 = v, x2 = x, v2 = v;
    filtered->resolveCollisions(t, x1, v1);
    oracle->resolveCollisions(t, x2, v2);
    EXPECT_TRUE(sameBits(x1, x2) && sameBits(v1, v2)) << "impacts at t = " << t;
    const VecX x_end = x + 0.01 * v, v_end = v + 0.01 * f_filtered;  // any second state: the work's two ends
    EXPECT_EQ(filtered->colliderWork(t, 0.01, x, v, x_end, v_end), oracle->colliderWork(t, 0.01, x, v, x_end, v_end));
  }
  for (std::size_t c = 0; c < touched.size(); ++c)
    EXPECT_GT(touched[c], 0) << filtered->colliders()[c]->name() << " never met the jelly: the scene tests nothing";
  EXPECT_LT(asked_cells, cells / 4);  // most cells are never blended

  // A whole run, to the bit.
  Simulation run(*oracle, makeIntegrator("rk4"), 1e-3);
  for (int k = 1; k <= 40; ++k) ASSERT_FALSE(run.advanceTo(0.01 * k));  // the same steps
  EXPECT_TRUE(sameBits(sim.x(), run.x()) && sameBits(sim.v(), run.v()));
}

TEST(NearCells, WeightsMustBeAConvexCombination) {
  // The cell's box holds its points only for weights >= 0 summing to 1.
  WeightedPoints points;
  const VecX inv_mass = VecX::Ones(8);
  const std::array<int, 8> cell{0, 1, 2, 3, 4, 5, 6, 7};
  EXPECT_THROW(points.add(cell, {1.5, -0.5, 0, 0, 0, 0, 0, 0}, 0, inv_mass), std::invalid_argument);
  EXPECT_THROW(points.add(cell, {0.5, 0.4, 0, 0, 0, 0, 0, 0}, 0, inv_mass), std::invalid_argument);
  points.add(cell, {0.125, 0.125, 0.125, 0.125, 0.125, 0.125, 0.125, 0.125}, 0, inv_mass);
  points.add(cell, {1, 0, 0, 0, 0, 0, 0, 0}, 0, inv_mass);
  EXPECT_EQ(points.size(), 2);
  EXPECT_EQ(points.cellCount(), 1);
}

TEST(NearCells, CellPointsBelowKeepEachPointsOwnTest) {
  // The half-space filter tests a cell's points four at a time (WeightedPoints::cellPointsBelow): the very sums and
  // test blendValue(s, p) < limit takes point by point. Cells of 1 to 9 points (full and partial quads), random convex
  // weights, random values of either sign.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1), value(-3, 3);
  const int particles = 40;
  const VecX inv_mass = VecX::Ones(particles);
  VecX s(particles);
  for (int i = 0; i < particles; ++i) s[i] = value(rng);
  WeightedPoints points;
  std::vector<int> order(particles);
  for (int cell = 0; cell < 9; ++cell) {
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    std::array<int, 8> particle;
    std::copy_n(order.begin(), 8, particle.begin());
    for (int p = 0; p <= cell; ++p) {
      std::array<double, 8> w;
      double sum = 0;
      for (double& wk : w) sum += (wk = unit(rng) * unit(rng));
      for (double& wk : w) wk /= sum;
      w[7] = 1;
      for (int k = 0; k < 7; ++k) w[7] -= w[k];  // summing to 1 within round-off
      if (w[7] < 0) w[7] = 0;
      points.add(particle, w, 0, inv_mass);
    }
  }
  ASSERT_EQ(points.cellCount(), 9);
  for (int c = 0; c < points.cellCount(); ++c) {
    const std::span<const int> cell = points.cellPoints(c);
    ASSERT_EQ(int(cell.size()), c + 1);
    double values[8];
    for (int k = 0; k < 8; ++k) values[k] = s[points.cellParticles(c)[k]];
    // Limits at each point's own blend (not below it: kept only if a sum rounded otherwise), one unit in the last
    // place above it (kept), below and above every value.
    std::vector<double> limits{-10.0, 10.0};
    for (const int p : cell) {
      limits.push_back(points.blendValue(s, p));
      limits.push_back(std::nextafter(points.blendValue(s, p), 10.0));
    }
    for (const double limit : limits) {
      std::vector<int> expected, got;
      for (const int p : cell)
        if (points.blendValue(s, p) < limit) expected.push_back(p);
      points.cellPointsBelow(c, values, limit, got);
      EXPECT_EQ(got, expected) << "cell " << c << " limit " << limit;
    }
  }
}

}  // namespace
}  // namespace wobble
