// Mesh jelly and mesh collider against independent oracles: the lattice fill of a sphere against its volume, the
// embedded surface at rest against the placed model, a cube model against the cube jelly, and the mesh collider's
// closest point against an analytic plane and sphere.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/bodies/jelly.h"
#include "sim/bodies/mesh_jelly.h"
#include "sim/contact/colliders/mesh.h"
#include "test_models.h"

namespace wobble {
namespace {

using testing::uvSphere;

ModelMesh cube(double size) { return testing::box(Vec3::Constant(size)); }

double surfaceArea(const ModelMesh& m) {
  double a = 0;
  for (const auto& t : m.triangles)
    a += 0.5 * (m.points[t[1]] - m.points[t[0]]).cross(m.points[t[2]] - m.points[t[0]]).norm();
  return a;
}

TEST(MeshJelly, ModelsAreChecked) {
  EXPECT_EQ(checkModel(uvSphere(1, 16, 32), true), "");
  EXPECT_EQ(checkModel(cube(1), true), "");
  ModelMesh open = cube(1);
  open.triangles.pop_back();
  EXPECT_NE(checkModel(open, true).find("3 boundary edges"), std::string::npos) << checkModel(open, true);
  EXPECT_EQ(checkModel(open, false), "");  // an open collider is fine
  ModelMesh nan = cube(1);
  nan.points[3].x() = std::nan("");
  EXPECT_NE(checkModel(nan, true).find("vertex 4"), std::string::npos);
  ModelMesh inverted = cube(1);
  for (auto& t : inverted.triangles) std::swap(t[1], t[2]);
  EXPECT_NE(checkModel(inverted, true).find("inside out"), std::string::npos);
  ModelMesh fin = cube(1);
  fin.points.emplace_back(0.5, 2, 0);
  fin.triangles.push_back({0, 4, 8});  // a third triangle on edge 0-4
  EXPECT_NE(checkModel(fin, true).find("not manifold"), std::string::npos);
  EXPECT_NE(checkModel(ModelMesh{}, true).find("empty"), std::string::npos);
}

// Cells whose centre is inside: their volume tends to the sphere's; the error is at most the shell of cells the
// surface cuts (area x half a cell diagonal), and it shrinks as the cells do. Every kept cell together covers it.
TEST(MeshJelly, LatticeFillOfASphereMatchesItsVolume) {
  const ModelMesh sphere = uvSphere(1, 48, 96);
  const double volume = meshVolume(sphere.points, sphere.triangles), area = surfaceArea(sphere);
  EXPECT_NEAR(volume, 4 * EIGEN_PI / 3, 0.01);
  double previous = 1e9;
  for (int cells : {8, 16, 32}) {
    const LatticeFill f = fillLattice(localPoints(sphere, 1), sphere.triangles, cells);
    const double cell_volume = f.h * f.h * f.h;
    double inside = 0, kept = 0;
    for (std::size_t c = 0; c < f.inside.size(); ++c) {
      inside += f.inside[c] * cell_volume;
      kept += f.kept[c] * cell_volume;
    }
    const double error = std::abs(inside - volume);
    EXPECT_LT(error, area * f.h * std::sqrt(3.0) / 2) << cells;
    EXPECT_LT(error, previous) << cells;
    EXPECT_GT(kept, volume) << cells;
    previous = error;
  }
  EXPECT_LT(previous / volume, 0.01);  // 32 cells: within 1%
}

TEST(MeshJelly, EmbeddedSurfaceIsTheModelAtRest) {
  ModelMesh sphere = uvSphere(1.3, 12, 24);
  for (Vec3& p : sphere.points) p += Vec3(5, -2, 1);  // off-centre in the file
  MeshJellyParams p;
  p.cells = 7;
  p.placement = {Vec3(0.5, 3, -1), 1.7, Vec3(1, 2, 3), 40};
  const Body body = buildMeshJelly("s", sphere, p);
  const SurfaceFrame f = evaluateSurface(body.surface, body.x, 0);
  const std::vector<Vec3> local = localPoints(sphere, 1.7);
  ASSERT_GE(f.positions.size(), sphere.points.size());
  double worst = 0;
  for (std::size_t v = 0; v < sphere.points.size(); ++v) {
    const Vec3 expected = p.placement.center + p.placement.rotation() * local[v];
    worst = std::max(worst, (f.positions[v].cast<double>() - expected).norm());
  }
  EXPECT_LT(worst, 1e-5);  // float positions of a 4 m model
  for (const EmbeddedPoint& e : body.surface.embedded) {
    double sum = 0;
    for (int c = 0; c < 8; ++c) {
      EXPECT_GE(e.weight[c], 0);
      sum += e.weight[c];
    }
    EXPECT_NEAR(sum, 1, 1e-12);
  }
  EXPECT_EQ(body.surface.triangles, sphere.triangles);  // no UVs: no seam vertices, faces as read
}

// A cube model with cells = n - 1 is the cube jelly of n: the same particles in the same order, the same springs.
TEST(MeshJelly, CubeModelIsTheCubeJelly) {
  JellyParams cubeParams;
  cubeParams.rotation_deg = 30;
  const Body jelly = buildJelly("j", cubeParams);
  MeshJellyParams p;
  p.cells = cubeParams.n - 1;
  p.placement = {cubeParams.center, 1, cubeParams.rotation_axis, cubeParams.rotation_deg};
  const Body mesh = buildMeshJelly("j", cube(cubeParams.size), p);
  ASSERT_EQ(mesh.particleCount(), jelly.particleCount());
  EXPECT_LT((mesh.x - jelly.x).lpNorm<Eigen::Infinity>(), 1e-12);
  ASSERT_EQ(mesh.springs.size(), jelly.springs.size());
  for (std::size_t s = 0; s < jelly.springs.size(); ++s) {
    EXPECT_EQ(mesh.springs.a[s], jelly.springs.a[s]);
    EXPECT_EQ(mesh.springs.b[s], jelly.springs.b[s]);
    EXPECT_NEAR(mesh.springs.rest[s], jelly.springs.rest[s], 1e-12);
  }
}

TEST(MeshCollider, ClosestPointOnAPlane) {
  ModelMesh square;
  square.points = {{-10, 1, -10}, {10, 1, -10}, {10, 1, 10}, {-10, 1, 10}};
  square.triangles = {{0, 2, 1}, {0, 3, 2}};  // front face up (+y)
  const MeshCollider plate("plate", {}, square.points, square.triangles, Vec3(0, 0.5, 0));
  for (const Vec3& x : {Vec3(0.3, 2.5, -4), Vec3(7, 0.2, 3), Vec3(-2, 1, 0)}) {
    const auto s = plate.query(2, x);  // at t = 2 the plate is at y = 2
    ASSERT_TRUE(s);
    EXPECT_NEAR(s->distance, x.y() - 2, 1e-12) << x.transpose();
    EXPECT_NEAR((s->normal - Vec3::UnitY()).norm(), 0, 1e-12);
    EXPECT_EQ(s->velocity, Vec3(0, 0.5, 0));
  }
}

// A tessellated sphere lies within the sagitta of the true one: its distances match |x| - r to that bound.
TEST(MeshCollider, ClosestPointOnASphere) {
  const ModelMesh sphere = uvSphere(1, 64, 128);
  const MeshCollider ball("ball", {}, sphere.points, sphere.triangles, Vec3::Zero());
  const double sagitta = 1 - std::cos(EIGEN_PI / 64);
  for (const Vec3& x : {Vec3(0.3, 1.4, -0.2), Vec3(2, -1, 0.5), Vec3(0.1, 0.2, 0.3), Vec3(-0.6, -0.5, 0.1)}) {
    const auto s = ball.query(0, x);
    ASSERT_TRUE(s);
    EXPECT_NEAR(s->distance, x.norm() - 1, sagitta) << x.transpose();
    EXPECT_GT(s->normal.dot(x.normalized()), 0.99) << x.transpose();
  }
  const auto box = ball.bounds(0);
  ASSERT_TRUE(box);
  EXPECT_NEAR(box->max().y(), 1, 1e-12);
}

// The mesh collider's near() skips the point query beyond the margin of its box. Oracle: the base class's near(), which
// queries every particle. On a closed, moving mesh the two lists are the same at every margin, particles inside the
// box, around it and far from it alike.
TEST(MeshCollider, NearSkipsOnlyWhatCannotTouch) {
  const ModelMesh sphere = uvSphere(1, 16, 32);
  const MeshCollider ball("ball", {}, sphere.points, sphere.triangles, Vec3(0.5, 0, 0));
  const int n = 2000;
  VecX x(3 * n);
  for (int i = 0; i < n; ++i)  // a deterministic spiral through [-3, 3]^3, dense near the sphere
    particle(x, i) = (0.2 + 2.8 * i / n) * Vec3(std::cos(0.37 * i), std::sin(0.91 * i), std::cos(1.3 * i)).normalized();
  std::vector<int> fast, all;
  for (const double margin : {0.0, 0.01, 0.3, 1.5})
    for (const double t : {0.0, 0.4}) {
      ball.near(t, x, margin, fast);
      ball.Collider::near(t, x, margin, all);
      EXPECT_EQ(fast, all) << "margin " << margin << ", t " << t;
      EXPECT_FALSE(all.empty());
    }
}

}  // namespace
}  // namespace wobble
