// Camera: primary rays through the image centre and edges match the view direction and field of view.
#include "render/camera.h"

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

}  // namespace
}  // namespace wobble::render
