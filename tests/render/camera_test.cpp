// Camera: primary rays through the image centre and edges match the view direction and field of view.
#include "render/camera.h"

#include "render/renderer.h"
#include "render/scene.h"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

namespace wobble::render {
namespace {

constexpr float kDeg = std::numbers::pi_v<float> / 180.0f;

CameraParams params() {
  CameraParams p;
  p.position = {1, 2, 3};
  p.look_at = {4, 2, -1};  // forward (0.6, 0, -0.8)
  p.up = {0, 1, 0};
  p.vfov_deg = 60;
  p.width = 200;
  p.height = 100;
  return p;
}

TEST(Camera, CentreRayLooksAlongViewDirection) {
  const Camera cam(params());
  const Ray r = cam.ray(100, 50);
  EXPECT_TRUE(r.origin.isApprox(Eigen::Vector3f(1, 2, 3)));
  EXPECT_NEAR((r.direction - Eigen::Vector3f(0.6f, 0, -0.8f)).norm(), 0, 1e-6);
  EXPECT_NEAR(r.direction.norm(), 1, 1e-6);
}

TEST(Camera, EdgeRaysAreAtHalfFieldOfView) {
  const Camera cam(params());
  const Eigen::Vector3f f(0.6f, 0, -0.8f), up(0, 1, 0);
  const Eigen::Vector3f right = f.cross(up);  // (0.8, 0, 0.6)
  const float half_v = 30 * kDeg;
  const float half_h = std::atan(2.0f * std::tan(half_v));  // aspect 2

  const Ray top = cam.ray(100, 0);
  EXPECT_NEAR(std::acos(top.direction.dot(f)), half_v, 1e-5);
  EXPECT_GT(top.direction.dot(up), 0);
  EXPECT_NEAR(top.direction.dot(right), 0, 1e-6);

  const Ray bottom = cam.ray(100, 100);
  EXPECT_NEAR(std::acos(bottom.direction.dot(f)), half_v, 1e-5);
  EXPECT_LT(bottom.direction.dot(up), 0);

  const Ray left = cam.ray(0, 50);
  EXPECT_NEAR(std::acos(left.direction.dot(f)), half_h, 1e-5);
  EXPECT_LT(left.direction.dot(right), 0);

  const Ray right_edge = cam.ray(200, 50);
  EXPECT_NEAR(std::acos(right_edge.direction.dot(f)), half_h, 1e-5);
  EXPECT_GT(right_edge.direction.dot(right), 0);

  // The top-left corner: tangents of both half angles in the image plane.
  const Ray corner = cam.ray(0, 0);
  const float along = corner.direction.dot(f);
  EXPECT_NEAR(corner.direction.dot(up) / along, std::tan(half_v), 1e-5);
  EXPECT_NEAR(corner.direction.dot(right) / along, -std::tan(half_h), 1e-5);
}

TEST(Camera, DepthIsDistanceAlongOpticalAxis) {
  const Camera cam(params());
  EXPECT_NEAR(cam.depth(Eigen::Vector3f(1, 2, 3) + 5 * Eigen::Vector3f(0.6f, 0, -0.8f) + Eigen::Vector3f(0, 7, 0)), 5,
              1e-5);
}

TEST(Camera, RejectsDegenerateViews) {
  auto p = params();
  p.look_at = p.position;
  EXPECT_THROW(Camera{p}, std::invalid_argument);
  p = params();
  p.up = {0.6f, 0, -0.8f};
  EXPECT_THROW(Camera{p}, std::invalid_argument);
  p = params();
  p.vfov_deg = 180;
  EXPECT_THROW(Camera{p}, std::invalid_argument);
  p = params();
  p.width = 0;
  EXPECT_THROW(Camera{p}, std::invalid_argument);
}

// Depth of field: a small lit sphere off the focus plane, seen through a thin lens of radius R, is blurred by a
// uniform disc whose radius on the film plane at distance 1 is R |1/focus - 1/z| (the circle of confusion). A
// disc of radius c adds c^2 / 4 to the picture's variance along each axis, so the blurred picture's horizontal
// variance minus the pinhole's gives c: checked against the formula, in pixels. In focus, nothing changes.
double horizontalVariance(float aperture, float focus) {
  Scene scene;
  scene.addSphere("dot", Sphere{Eigen::Vector3f(0, 0, -10), 0.1f},
                  scene.addMaterial(Material::diffuse("white", Color::Ones())));
  scene.lights.sky = Sky::black();
  SunLight sun;
  sun.direction = {0, 0, 1};  // from behind the camera: the whole visible face is lit
  sun.angular_radius_deg = 0;
  scene.lights.suns = {sun};
  scene.commit();
  CameraParams p;
  p.position = {0, 0, 0};
  p.look_at = {0, 0, -1};
  p.vfov_deg = 20;
  p.width = p.height = 64;
  p.aperture = aperture;
  p.focus = focus;
  RenderSettings settings;
  settings.samples_per_pixel = 1024;
  settings.max_bounces = 0;
  const image::Film film = render(scene, Camera(p), settings);
  double sum = 0, sx = 0, sxx = 0;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      const double v = film.color[film.index(x, y)].mean(), cx = x + 0.5;
      sum += v, sx += v * cx, sxx += v * cx * cx;
    }
  const double mean = sx / sum;
  return sxx / sum - mean * mean;
}

TEST(Camera, ThinLensBlursByTheCircleOfConfusion) {
  const double pinhole = horizontalVariance(0, 0);
  const double pixel = 2 * std::tan(10 * std::numbers::pi / 180) / 64;  // film-plane size of a pixel
  for (const float focus : {5.0f, 20.0f}) {
    const float radius = 0.3f;
    const double coc = radius * std::abs(1.0 / focus - 1.0 / 10) / pixel;  // pixels
    const double measured = 2 * std::sqrt(horizontalVariance(radius, focus) - pinhole);
    EXPECT_NEAR(measured, coc, 0.03 * coc) << "focus " << focus;
  }
  EXPECT_NEAR(horizontalVariance(0.3f, 10), pinhole, 0.02 * pinhole);  // in focus: as sharp as the pinhole
}

}  // namespace
}  // namespace wobble::render
