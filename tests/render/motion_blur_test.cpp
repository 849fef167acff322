// Motion blur against analytic answers: an edge sweeping across the image at constant speed covers pixel column i
// for the fraction of the shutter after the edge has passed it, so the pixel keeps 1 - coverage of the sky behind;
// the same whether the shape moves (Embree's multi-segment motion blur, any number of poses on the line) or the
// camera does the opposite; a sphere's and a mesh's hit point and normals follow the pose at the ray's time; a
// texture sliding under a pixel is filtered over its motion, so one sample already gives the blurred texture.
#include <cmath>

#include <gtest/gtest.h>

#include "render/renderer.h"
#include "render/scene.h"
#include "render/texture.h"

namespace wobble::render {
namespace {

constexpr int kWidth = 32, kHeight = 4, kSpp = 64;
constexpr float kDepth = 10, kSize = 200;

CameraParams camera() {
  CameraParams cp;
  cp.position = {0, 0, 0};
  cp.look_at = {0, 0, -1};
  cp.vfov_deg = 20;
  cp.width = kWidth;
  cp.height = kHeight;
  return cp;
}

// Half the image's width at the quad's depth.
float halfWidth() {
  const float tan_y = std::tan(0.5f * 20 * float(M_PI) / 180);
  return kDepth * tan_y * float(kWidth) / float(kHeight);
}

// A black quad facing the camera whose right edge is at x = edge (at the quad's depth); no light, so it is black.
Quad quadWithEdgeAt(float edge) { return Quad{{edge - kSize / 2, 0, -kDepth}, {0, 0, 1}, kSize, 1}; }

image::Film renderScene(Scene& scene, const CameraParams& cp, bool blur) {
  scene.lights.sky = Sky{};
  scene.commit();
  RenderSettings s;
  s.samples_per_pixel = kSpp;
  s.max_bounces = 0;
  s.motion_blur = blur;
  return render(scene, Camera(cp), s);
}

image::Film skyOnly() {
  Scene scene;
  const auto black = scene.addMaterial(Material::diffuse("black", Color::Zero()));
  scene.addQuad("behind", Quad{{0, 0, 10}, {0, 0, -1}, 1, 1}, black);  // behind the camera: never seen
  return renderScene(scene, camera(), false);
}

// The fraction of the sky each pixel of row 1 lost, against the sky-only picture.
std::vector<float> coverage(const image::Film& film, const image::Film& sky) {
  std::vector<float> c;
  for (int x = 0; x < kWidth; ++x) {
    const std::size_t i = film.index(x, 1);
    c.push_back(1 - film.color[i].sum() / sky.color[i].sum());
  }
  return c;
}

// The edge sweeps from the left border (time 0) to the right one (time 1): column i's centre at (i + 1/2) / W of the
// way, so the pixel is covered for the rest of the shutter: 1 - (i + 1/2) / W (the linear ramp of a pixel's partial
// coverage averages to its centre's).
// Tolerance: a pixel's samples are stratified in time and in position, but not jointly, so the few (kSpp / kWidth)
// whose time falls while the edge is inside the pixel are covered by chance: up to about two samples' worth off each.
// Over all columns those errors average out.
void expectSweepCoverage(const std::vector<float>& c) {
  double error = 0;
  for (int x = 0; x < kWidth; ++x) {
    const float expected = 1 - (x + 0.5f) / kWidth;
    EXPECT_NEAR(c[x], expected, 2.5f / kSpp) << "column " << x;
    error += c[x] - expected;
  }
  EXPECT_NEAR(error / kWidth, 0, 0.005);
}

TEST(MotionBlur, SweepingEdgeCoversEachPixelForTheFractionOfTheShutterItIsOver) {
  const image::Film sky = skyOnly();
  for (const int poses : {2, 3, 5}) {
    Scene scene;
    const auto black = scene.addMaterial(Material::diffuse("black", Color::Zero()));
    const auto id = scene.addQuad("edge", quadWithEdgeAt(0), black);
    std::vector<Quad> path;
    for (int j = 0; j < poses; ++j) path.push_back(quadWithEdgeAt(-halfWidth() + 2 * halfWidth() * j / (poses - 1)));
    scene.updateQuadMotion(id, path);
    EXPECT_TRUE(scene.moving(id));
    SCOPED_TRACE(std::to_string(poses) + " poses");
    expectSweepCoverage(coverage(renderScene(scene, camera(), true), sky));
  }
}

TEST(MotionBlur, CameraMovingTheOtherWayBlursAlike) {
  const image::Film sky = skyOnly();
  Scene scene;
  const auto black = scene.addMaterial(Material::diffuse("black", Color::Zero()));
  scene.addQuad("edge", quadWithEdgeAt(0), black);
  // The eye goes from +w to -w (x): the still edge at 0 moves across the image from the left border to the right.
  CameraParams cp = camera();
  cp.position.x() = -halfWidth();
  cp.look_at.x() = -halfWidth();
  cp.shutter_motion = {-2 * halfWidth(), 0, 0};
  expectSweepCoverage(coverage(renderScene(scene, cp, true), sky));
}

TEST(MotionBlur, WithoutMotionBlurRaysSeeTheOpeningPose) {
  const image::Film sky = skyOnly();
  Scene scene;
  const auto black = scene.addMaterial(Material::diffuse("black", Color::Zero()));
  const auto id = scene.addQuad("edge", quadWithEdgeAt(0), black);
  const Quad path[] = {quadWithEdgeAt(-halfWidth()), quadWithEdgeAt(0)};
  scene.updateQuadMotion(id, path);
  // Without motion blur every ray is at time 0, the shutter's opening: the edge at the left border, nothing covered.
  for (const float c : coverage(renderScene(scene, camera(), false), sky)) EXPECT_NEAR(c, 0, 1e-6f);
  // With it, the left half is covered for the fraction of the shutter after the edge passed its column.
  const std::vector<float> c = coverage(renderScene(scene, camera(), true), sky);
  for (int x = 0; x < kWidth / 2; ++x) EXPECT_NEAR(c[x], 1 - (x + 0.5f) / (kWidth / 2), 2.5f / kSpp) << "column " << x;
  for (int x = kWidth / 2; x < kWidth; ++x) EXPECT_NEAR(c[x], 0, 1e-6f) << "column " << x;
}

// A checker floor seen from above while the camera slides 6 pixels along it: at one sample per pixel every sample
// sees the texture filtered over the pixel and its motion (path_tracer.cpp, blurFootprint), so the first-hit albedo
// (the texture, without lighting noise) is near the converged blur of 256 samples; point-sampled at a random
// instant it would be one square or the other, 0.3 from the mean on average where the squares alternate. The
// footprint's box along the motion is not the converged filter (the pixel's box swept along the motion: a
// trapezoid), hence the bound.
TEST(MotionBlur, OneSampleSeesTheTextureBlurredAlongTheMotion) {
  Scene scene;
  const auto checker =
      scene.addMaterial(Material::textured("checker", std::make_shared<CheckerTexture>(Color::Constant(0.8f),
                                                                                       Color::Constant(0.2f), 8.0f)));
  scene.addQuad("floor", Quad{{0, 0, 0}, {0, 1, 0}, 4, 1}, checker);
  scene.lights.suns = {SunLight{}};
  scene.commit();
  CameraParams cp;
  cp.position = {0, 3, 0};
  cp.look_at = {0, 0, 0};
  cp.up = {0, 0, -1};
  cp.vfov_deg = 40;
  cp.width = 48;
  cp.height = 32;
  const float pixel = 2 * 3 * std::tan(0.5f * 40 * float(M_PI) / 180) / cp.height;  // at the floor
  cp.shutter_motion = {6 * pixel, 0, 0};
  RenderSettings s;
  s.motion_blur = true;
  s.max_bounces = 0;
  s.samples_per_pixel = 256;
  const image::Film converged = render(scene, Camera(cp), s);
  s.samples_per_pixel = 1;
  const image::Film one = render(scene, Camera(cp), s);
  double error = 0, spread = 0;
  for (std::size_t i = 0; i < one.albedo.size(); ++i) {
    error += std::abs(one.albedo[i].x() - converged.albedo[i].x());
    spread += std::min(converged.albedo[i].x() - 0.2f, 0.8f - converged.albedo[i].x());  // not one square alone
  }
  error /= double(one.albedo.size());
  spread /= double(one.albedo.size());
  EXPECT_GT(spread, 0.1) << "the motion blurs the squares";
  EXPECT_LT(error, 0.03);
}

TEST(MotionBlur, SphereHitFollowsItsPoseAtTheRayTime) {
  Scene scene;
  const auto grey = scene.addMaterial(Material::diffuse("grey", Color::Constant(0.5f)));
  const auto id = scene.addSphere("ball", Sphere{{0, 0, 0}, 1}, grey);
  const Sphere path[] = {{{0, 0, 0}, 1}, {{4, 0, 0}, 1}, {{4, 4, 0}, 2}};
  scene.updateSphereMotion(id, path);
  scene.commit();
  for (const float time : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) {
    // The pose at `time`: linear between the two around it.
    const float f = 2 * time;
    const int i = std::min(int(f), 1);
    const float w = f - float(i);
    const Eigen::Vector3f centre = (1 - w) * path[i].center + w * path[i + 1].center;
    const float radius = (1 - w) * path[i].radius + w * path[i + 1].radius;
    Ray ray{{centre.x(), centre.y(), 10}, {0, 0, -1}};
    ray.time = time;
    const auto hit = scene.intersect(ray);
    ASSERT_TRUE(hit) << "time " << time;
    EXPECT_NEAR(hit->p.z(), radius, 1e-3f) << "time " << time;
    EXPECT_NEAR(hit->ng.z(), 1, 1e-3f);
    Ray beside = ray;
    beside.origin.x() += radius + 0.1f;  // just past its silhouette then
    EXPECT_FALSE(scene.intersect(beside)) << "time " << time;
  }
}

TEST(MotionBlur, MeshHitInterpolatesPositionsAndNormals) {
  Scene scene;
  const auto grey = scene.addMaterial(Material::diffuse("grey", Color::Constant(0.5f)));
  TriangleMesh m;
  m.name = "tri";
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}};
  const auto id = scene.addMesh(m, grey);
  std::vector<Eigen::Vector3f> lifted = m.positions, tilted = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  for (auto& p : lifted) p.z() += 2;
  const Scene::MeshPose poses[] = {{m.positions, m.normals}, {lifted, tilted}};
  scene.updateMeshMotion(id, poses);
  scene.commit();
  Ray ray{{0, 0, 10}, {0, 0, -1}};
  ray.time = 0.25f;
  const auto hit = scene.intersect(ray);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 10 - 0.5f, 1e-4f);
  EXPECT_NEAR(hit->p.z(), 0.5f, 1e-4f);
  EXPECT_NEAR(hit->ns.dot(Eigen::Vector3f(0, 0.25f, 0.75f).normalized()), 1, 1e-4f);
}

TEST(MotionBlur, PosesMustMatchTheMesh) {
  Scene scene;
  const auto grey = scene.addMaterial(Material::diffuse("grey", Color::Constant(0.5f)));
  TriangleMesh m;
  m.name = "tri";
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  const auto id = scene.addMesh(m, grey);
  const std::vector<Eigen::Vector3f> two = {{0, 0, 0}, {1, 0, 0}};
  const Scene::MeshPose poses[] = {{m.positions, {}}, {two, {}}};
  EXPECT_THROW(scene.updateMeshMotion(id, poses), std::invalid_argument);
  EXPECT_THROW(scene.updateMeshMotion(id, {}), std::invalid_argument);
}

}  // namespace
}  // namespace wobble::render
