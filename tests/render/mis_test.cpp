// Multiple importance sampling, sky sampling and Russian roulette are unbiased: a diffuse floor lit by a finite sun, by
// the sky or by an area light renders the analytic radiance (or the light-sampling-only estimate) whichever strategies
// combine.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "render/renderer.h"
#include "render/scene.h"

namespace wobble::render {
namespace {

constexpr float kAlbedo = 0.5f;

// A 200 m grey floor at y = 0 seen straight down from 3 m: every pixel sees the floor, nothing else is there.
Scene floorScene() {
  Scene scene;
  scene.addQuad("floor", Quad{{0, 0, 0}, {0, 1, 0}, 200, 1},
                scene.addMaterial(Material::diffuse("grey", Color::Constant(kAlbedo))));
  scene.lights.sky = Sky::black();
  return scene;
}

Camera downwards() {
  CameraParams p;
  p.position = {0, 3, 0};
  p.look_at = {0, 0, 0};
  p.up = {0, 0, -1};
  p.vfov_deg = 30;
  p.width = p.height = 24;
  return Camera(p);
}

Color meanColor(const Scene& scene, int bounces, int spp, bool sample_sky = false, bool roulette = false,
                RenderStats* stats = nullptr) {
  RenderSettings s;
  s.samples_per_pixel = spp;
  s.max_bounces = bounces;
  s.sample_sky = sample_sky;
  s.roulette = roulette;
  const Film film = render(scene, downwards(), s, stats);
  Color sum = Color::Zero();
  for (const Color& c : film.color) sum += c;
  return sum / float(film.color.size());
}

// A sun disc of half-angle c whose centre is theta from the normal: irradiance E cos(theta) (1 + cos c) / 2 (the
// mean cosine over a uniformly sampled cap), reflected as albedo / pi of it.
TEST(Mis, FiniteSunOnAFloorIsTheAnalyticRadianceWithAndWithoutBsdfSampling) {
  Scene scene = floorScene();
  SunLight sun;
  const float theta = 30 * std::numbers::pi_v<float> / 180;
  sun.direction = {std::sin(theta), std::cos(theta), 0};
  sun.irradiance = Color::Constant(2.0f);
  sun.angular_radius_deg = 25;  // wide: BSDF samples find it often and carry a few % of the MIS weight
  scene.lights.suns = {sun};
  scene.commit();
  const float c = 25 * std::numbers::pi_v<float> / 180;
  const float expected = kAlbedo / std::numbers::pi_v<float> * 2.0f * std::cos(theta) * (1 + std::cos(c)) / 2;
  // No continuation: light sampling alone, full weight. Two bounces: light and BSDF samples of the sun, MIS-weighted.
  EXPECT_NEAR(meanColor(scene, 0, 16).x(), expected, 0.003f * expected);
  EXPECT_NEAR(meanColor(scene, 2, 64).x(), expected, 0.01f * expected);
}

// The sky alone on an upward floor: radiance albedo / pi * integral of sky(e) cos over the hemisphere, where
// sky(e) = horizon + sqrt(e) (zenith - horizon) at elevation sine e: albedo (horizon + 0.8 (zenith - horizon)).
TEST(Mis, SkyLightIsTheSameWithAndWithoutSkySampling) {
  Scene scene = floorScene();
  scene.lights.sky = Sky{};
  scene.commit();
  const Color h = scene.lights.sky.horizon, z = scene.lights.sky.zenith;
  const Color expected = kAlbedo * (h + 0.8f * (z - h));
  for (const bool sample_sky : {false, true}) {
    const Color got = meanColor(scene, 1, 64, sample_sky);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], expected[k], 0.01f * expected[k]) << "sample_sky " << sample_sky;
  }
}

// A square area light 2 m above the floor: light sampling alone (no continuation) and light plus BSDF sampling with
// MIS (a continuation that may hit the light) estimate the same radiance.
TEST(Mis, AreaLightEstimatesAgreeWithAndWithoutBsdfSampling) {
  Scene scene = floorScene();
  RectLight light;
  light.corner = {-0.5f, 2, -0.5f};
  light.edge_u = {1, 0, 0};
  light.edge_v = {0, 0, 1};  // edge_u x edge_v = -y: facing the floor
  light.radiance = Color::Constant(10.0f);
  scene.lights.rects = {light};
  scene.commit();
  const float light_only = meanColor(scene, 0, 64).x(), combined = meanColor(scene, 1, 64).x();
  EXPECT_GT(light_only, 0.01f);
  EXPECT_NEAR(combined, light_only, 0.01f * light_only);
}

// Russian roulette is unbiased: with light bouncing between the floor and a grey wall beside it (three bounces, lit
// by the sky and a sun), the floor's mean radiance is the same with and without it, for fewer rays.
TEST(RussianRoulette, KeepsTheMeanAndTracesFewerRays) {
  Scene scene = floorScene();
  scene.addQuad("wall", Quad{{1.5f, 1, 0}, {-1, 0, 0}, 4, 1},
                scene.addMaterial(Material::diffuse("wall", Color::Constant(0.8f))));
  scene.lights.sky = Sky{};
  SunLight sun;
  sun.direction = Eigen::Vector3f(-1, 1, 0.3f).normalized();
  scene.lights.suns = {sun};
  scene.commit();
  RenderStats always, roulette;
  const Color plain = meanColor(scene, 3, 256, false, false, &always);
  const Color rr = meanColor(scene, 3, 256, false, true, &roulette);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(rr[k], plain[k], 0.01f * plain[k]) << "channel " << k;
  EXPECT_LT(double(roulette.rays), 0.97 * double(always.rays));  // 6.6% fewer here: most floor paths escape to the sky
}

}  // namespace
}  // namespace wobble::render
