// Scene: ray queries against meshes, quads, boxes and spheres; per-frame updates; input validation.
#include "render/scene.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "render/path_tracer.h"
#include "render/renderer.h"

namespace wobble::render {
namespace {

using Eigen::Vector2f;
using Eigen::Vector3f;

TriangleMesh triangle() {
  TriangleMesh m;
  m.name = "tri";
  m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  m.uv = {{0.1f, 0.2f}, {0.9f, 0.3f}, {0.4f, 0.8f}};
  m.triangles = {{0, 1, 2}};
  return m;
}

Ray down(float x, float y, float z) { return Ray{{x, y, z}, {0, 0, -1}}; }

TEST(Scene, RayHitsKnownTriangleAtKnownPointWithInterpolatedUv) {
  Scene scene;
  const auto mat = scene.addMaterial(Material::diffuse("grey", Color::Constant(0.5f)));
  const auto id = scene.addMesh(triangle(), mat);
  scene.commit();

  const auto hit = scene.intersect(down(0.5f, 1.0f, 5.0f));
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->shape, id);
  EXPECT_EQ(hit->primitive, 0);
  EXPECT_EQ(hit->material, mat);
  EXPECT_NEAR(hit->t, 5.0f, 1e-5);
  EXPECT_NEAR((hit->p - Vector3f(0.5f, 1.0f, 0)).norm(), 0, 1e-6);
  // Barycentrics (b0, b1, b2) = (0.25, 0.25, 0.5) for (0.5, 1) in this triangle.
  const Vector2f uv = 0.25f * Vector2f(0.1f, 0.2f) + 0.25f * Vector2f(0.9f, 0.3f) + 0.5f * Vector2f(0.4f, 0.8f);
  EXPECT_NEAR((hit->uv - uv).norm(), 0, 1e-6);
  EXPECT_NEAR((hit->ng - Vector3f(0, 0, 1)).norm(), 0, 1e-6);  // counter-clockwise seen from +z
  EXPECT_NEAR((hit->ns - hit->ng).norm(), 0, 1e-6);            // no vertex normals: flat

  EXPECT_FALSE(scene.intersect(down(1.5f, 1.5f, 5.0f)));  // outside the hypotenuse
  EXPECT_FALSE(scene.intersect(Ray{{0.5f, 1, 5}, {0, 0, 1}}));
  Ray short_ray = down(0.5f, 1.0f, 5.0f);
  short_ray.tfar = 4.9f;
  EXPECT_FALSE(scene.intersect(short_ray));
  EXPECT_FALSE(scene.occluded(short_ray));
  EXPECT_TRUE(scene.occluded(down(0.5f, 1.0f, 5.0f)));
}

TEST(Scene, UpdatedVerticesAndNormalsAreUsedAfterCommit) {
  Scene scene;
  const auto id = scene.addMesh(triangle(), scene.addMaterial(Material::diffuse("grey", Color::Constant(0.5f))));
  scene.commit();
  const std::vector<Vector3f> moved = {{0, 0, 1}, {2, 0, 1}, {0, 2, 1}};
  const Vector3f tilted = Vector3f(1, 0, 1).normalized();
  const std::vector<Vector3f> normals(3, tilted);
  scene.updateMesh(id, moved, normals);
  EXPECT_FALSE(scene.committed());
  EXPECT_THROW(render(scene, Camera(CameraParams{})), std::logic_error);
  scene.commit();
  const auto hit = scene.intersect(down(0.5f, 1.0f, 5.0f));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 4.0f, 1e-5);
  EXPECT_NEAR((hit->ns - tilted).norm(), 0, 1e-6);
}

TEST(Scene, NanVertexIsRejectedWithAClearError) {
  Scene scene;
  const auto mat = scene.addMaterial(Material::diffuse("grey", Color::Constant(0.5f)));
  TriangleMesh bad = triangle();
  bad.name = "cloth";
  bad.positions[1].y() = std::numeric_limits<float>::quiet_NaN();
  try {
    scene.addMesh(bad, mat);
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("mesh 'cloth'"), std::string::npos) << what;
    EXPECT_NE(what.find("vertex 1 position"), std::string::npos) << what;
    EXPECT_NE(what.find("not finite"), std::string::npos) << what;
  }

  const auto id = scene.addMesh(triangle(), mat);
  scene.commit();
  std::vector<Vector3f> frame = triangle().positions;
  frame[2].x() = std::numeric_limits<float>::infinity();
  EXPECT_THROW(scene.updateMesh(id, frame), std::invalid_argument);
  // The rejected frame left the previous geometry in place.
  EXPECT_TRUE(scene.committed());
  EXPECT_TRUE(scene.intersect(down(0.5f, 1.0f, 5.0f)));
  std::vector<Vector3f> bad_normals(3, Vector3f(0, 0, std::numeric_limits<float>::quiet_NaN()));
  EXPECT_THROW(scene.updateMesh(id, triangle().positions, bad_normals), std::invalid_argument);
}

TEST(Scene, RejectsInconsistentInput) {
  Scene scene;
  const auto mat = scene.addMaterial(Material::diffuse("grey", Color::Constant(0.5f)));
  TriangleMesh m = triangle();
  m.triangles.push_back({0, 1, 3});
  EXPECT_THROW(scene.addMesh(m, mat), std::invalid_argument);
  m = triangle();
  m.uv.pop_back();
  EXPECT_THROW(scene.addMesh(m, mat), std::invalid_argument);
  EXPECT_THROW(scene.addMesh(triangle(), mat + 1), std::invalid_argument);
  const auto id = scene.addMesh(triangle(), mat);
  EXPECT_THROW(scene.updateMesh(id, std::vector<Vector3f>(2, Vector3f::Zero())), std::invalid_argument);
  EXPECT_THROW(scene.updateSphere(id, Sphere{}), std::invalid_argument);  // it is a mesh
  EXPECT_THROW(scene.addSphere("ball", Sphere{{0, 0, 0}, -1}, mat), std::invalid_argument);
  Material shiny = Material::jelly("jelly", Color::Ones());
  shiny.ior = 0.5f;
  EXPECT_THROW(scene.addMaterial(shiny), std::invalid_argument);
}

TEST(Scene, SphereIsAnalyticAndMoves) {
  Scene scene;
  const auto id = scene.addSphere("ball", Sphere{{0, 0, 0}, 1}, scene.addMaterial(Material::diffuse("r", {1, 0, 0})));
  scene.commit();
  for (float x : {0.0f, 0.3f, 0.7f, 0.95f}) {
    const auto hit = scene.intersect(down(x, 0.2f, 5));
    ASSERT_TRUE(hit) << x;
    EXPECT_NEAR(hit->p.norm(), 1, 1e-5);
    EXPECT_NEAR(hit->t, 5 - std::sqrt(1 - x * x - 0.04f), 1e-4);
    EXPECT_NEAR((hit->ng - hit->p).norm(), 0, 1e-5);
  }
  scene.updateSphere(id, Sphere{{3, 0, 0}, 0.5f});
  scene.commit();
  EXPECT_FALSE(scene.intersect(down(0, 0, 5)));
  const auto hit = scene.intersect(down(3, 0, 5));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 4.5f, 1e-5);
}

TEST(Scene, QuadAndBoxFaceOutwardsAndMove) {
  Scene scene;
  const auto mat = scene.addMaterial(Material::diffuse("grey", Color::Constant(0.5f)));
  scene.addQuad("floor", Quad{{0, 0, 0}, {0, 1, 0}, 10, 2}, mat);
  const auto box = scene.addBox("platform", Box{{5, 1, 0}, {2, 0.5f, 2}}, mat);
  scene.commit();

  const Ray onto_floor{{1, 3, 1}, {0, -1, 0}};
  const auto floor = scene.intersect(onto_floor);
  ASSERT_TRUE(floor);
  EXPECT_NEAR(floor->t, 3, 1e-5);
  EXPECT_NEAR((floor->ng - Vector3f(0, 1, 0)).norm(), 0, 1e-6);
  // u runs along +x, v along -z; 10 m with uv_repeat 2: u = 2 (x + 5) / 10, v = 2 (5 - z) / 10.
  EXPECT_NEAR(floor->uv.x(), (1 + 5) / 10.0f * 2, 1e-5);
  EXPECT_NEAR(floor->uv.y(), (5 - 1) / 10.0f * 2, 1e-5);

  const auto top = scene.intersect(Ray{{5, 3, 0}, {0, -1, 0}});
  ASSERT_TRUE(top);
  EXPECT_NEAR(top->p.y(), 1.25f, 1e-5);
  EXPECT_NEAR((top->ng - Vector3f(0, 1, 0)).norm(), 0, 1e-6);
  const auto side = scene.intersect(Ray{{8, 1, 0}, {-1, 0, 0}});
  ASSERT_TRUE(side);
  EXPECT_NEAR(side->p.x(), 6, 1e-5);
  EXPECT_NEAR((side->ng - Vector3f(1, 0, 0)).norm(), 0, 1e-6);

  scene.updateBox(box, Box{{5, 2, 0}, {2, 0.5f, 2}});  // the elevator rises
  scene.commit();
  EXPECT_NEAR(scene.intersect(Ray{{5, 3, 0}, {0, -1, 0}})->p.y(), 2.25f, 1e-5);
}

// Rays leaving a shape (as the path tracer's bounce and shadow rays do) give the same answer with and without the
// shortcut (Scene::provablyMisses), and the shortcut is taken where it should be: below the floor always, often above.
TEST(Scene, RaysLeavingAShapeGetTheSameAnswerWithTheShortcut) {
  Scene scene;
  const auto mat = scene.addMaterial(Material::diffuse("grey", Color::Constant(0.5f)));
  const auto floor = scene.addQuad("floor", Quad{{0, 0, 0}, {0, 1, 0}, 20, 1}, mat);
  const auto box = scene.addBox("platform", Box{{5, 1, 0}, {2, 0.5f, 2}}, mat);
  const auto ball = scene.addSphere("ball", Sphere{{-5, 2, 0}, 1}, mat);
  TriangleMesh sheet = triangle();
  for (Vector3f& p : sheet.positions) p += Vector3f(0, 3, 5);
  const auto mesh = scene.addMesh(sheet, mat);
  scene.commit();

  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(-1, 1);
  const auto direction = [&](const Vector3f& n) {  // uniform over the hemisphere around n
    Vector3f d;
    do d = Vector3f(uniform(rng), uniform(rng), uniform(rng));
    while (d.squaredNorm() > 1 || d.squaredNorm() < 1e-4f);
    d.normalize();
    return d.dot(n) >= 0 ? d : Vector3f(-d);
  };
  const auto leave = [&](ShapeId shape, const Vector3f& p, const Vector3f& n) {
    const Ray ray{offsetFromSurface(p, n), direction(n)};
    const auto plain = scene.intersect(ray), shortcut = scene.intersect(ray, shape);
    EXPECT_EQ(plain.has_value(), shortcut.has_value());
    if (plain && shortcut) {
      EXPECT_EQ(plain->shape, shortcut->shape);
      EXPECT_EQ(plain->t, shortcut->t);
    }
    EXPECT_EQ(scene.occluded(ray), scene.occluded(ray, shape));
    const bool skipped = scene.provablyMisses(ray, shape);
    if (skipped) {
      EXPECT_FALSE(plain) << "shape " << shape;
    }
    return skipped;
  };
  constexpr int kRays = 2000;
  int above = 0, below = 0, from_box = 0, from_ball = 0, from_mesh = 0;
  for (int i = 0; i < kRays; ++i) {
    const Vector3f on_floor(9 * uniform(rng), 0, 9 * uniform(rng));
    above += leave(floor, on_floor, Vector3f::UnitY());
    below += leave(floor, on_floor, -Vector3f::UnitY());
    from_box += leave(box, Vector3f(5 + uniform(rng), 1.25f, uniform(rng)), Vector3f::UnitY());
    from_box += leave(box, Vector3f(6, 1 + 0.25f * uniform(rng), uniform(rng)), Vector3f::UnitX());
    const Vector3f n = direction(Vector3f::UnitY());
    from_ball += leave(ball, Vector3f(-5, 2, 0) + n, n);
    from_mesh += leave(mesh, Vector3f(0.5f, 3.5f, 5), Vector3f::UnitZ());
  }
  EXPECT_EQ(below, kRays);  // nothing below the floor
  EXPECT_GT(above, kRays / 4);
  EXPECT_GT(from_box, kRays / 4);
  EXPECT_GT(from_ball, kRays / 4);
  EXPECT_EQ(from_mesh, 0);  // a mesh may fold back onto itself: never skipped
}

}  // namespace
}  // namespace wobble::render
