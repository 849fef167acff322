// Multiple importance sampling, sky sampling and Russian roulette are unbiased: a diffuse floor lit by a finite sun, by
// the sky or by an area light renders the analytic radiance (or the light-sampling-only estimate) whichever strategies
// combine. And MIS earns its keep: on a glossy floor under a small and a large area light (Veach 1995's case) it has
// far less variance than light sampling alone or BSDF sampling alone, each poor on one of the lights.
#include <cmath>
#include <cstring>
#include <numbers>
#include <utility>
#include <vector>

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
  const image::Film film = render(scene, downwards(), s, stats);
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

// Veach's case: a glossy floor (a coat of GGX alpha 0.05 over a grey base) under a large dim area light (6 x 6 m,
// 2 m up) whose reflection fills much of the view, and a small bright one (5 x 5 cm, 1 m up) that lights the base.
// Light sampling alone is poor on the large light's reflection (its samples rarely fall in the narrow lobe); BSDF
// sampling alone is poor on the small light (its directions rarely find it, from the diffuse base least of all).
Scene glossyFloorUnderTwoLights() {
  Scene scene;
  Material glossy = Material::diffuse("glossy", Color::Constant(0.5f));
  glossy.coat = 1;
  glossy.roughness = 0.05f;
  scene.addQuad("floor", Quad{{0, 0, 0}, {0, 1, 0}, 200, 1}, scene.addMaterial(glossy));
  scene.lights.sky = Sky::black();
  RectLight large, small;  // edge_u x edge_v = -y: facing the floor
  large.corner = {-3, 2, -6};
  large.edge_u = {6, 0, 0};
  large.edge_v = {0, 0, 6};
  large.radiance = Color::Constant(1.0f);
  small.corner = {0.3f, 1, -0.3f};
  small.edge_u = {0.05f, 0, 0};
  small.edge_v = {0, 0, 0.05f};
  small.radiance = Color::Constant(400.0f);
  scene.lights.rects = {large, small};
  scene.commit();
  return scene;
}

Camera towardsTheHighlights() {
  CameraParams p;
  p.position = {0, 1, 3};
  p.look_at = {0, 0, 0};
  p.vfov_deg = 40;
  p.width = 32;
  p.height = 24;
  return Camera(p);
}

struct Spread {
  double mean = 0;            // over pixels and frames, of the RGB sum
  double variance = 0;        // of one frame's pixel value (RGB sum) over the frames, averaged over the pixels
  double standard_error = 0;  // of mean: sqrt(variance / (frames x pixels))
};

// kFrames renders of spp samples per pixel, each frame its own sample pattern: the pixels' variance from frame to
// frame (independent estimates) is the estimator's.
Spread spread(const Scene& scene, bool mis, bool light_samples, int spp = 4, int bounces = 1) {
  constexpr int kFrames = 16;
  const Camera camera = towardsTheHighlights();
  std::vector<double> sum, sq;
  for (int frame = 0; frame < kFrames; ++frame) {
    RenderSettings s;
    s.samples_per_pixel = spp;
    s.max_bounces = bounces;
    s.mis = mis;
    s.light_samples = light_samples;
    s.frame = std::uint32_t(frame);
    const image::Film film = render(scene, camera, s);
    sum.resize(film.color.size(), 0.0);
    sq.resize(film.color.size(), 0.0);
    for (std::size_t i = 0; i < film.color.size(); ++i) {
      const double v = film.color[i].sum();
      sum[i] += v, sq[i] += v * v;
    }
  }
  Spread r;
  for (std::size_t i = 0; i < sum.size(); ++i) {
    const double mean = sum[i] / kFrames;
    r.mean += mean;
    r.variance += (sq[i] - kFrames * mean * mean) / (kFrames - 1);
  }
  r.mean /= double(sum.size());
  r.variance /= double(sum.size());
  r.standard_error = std::sqrt(r.variance / (kFrames * double(sum.size())));
  return r;
}

// The switches the variance test relies on really switch: with MIS off, a continuation adds nothing from the lights
// (one bounce renders the bytes of none, the same light samples at full weight); with MIS on it does; with light
// samples off too, nothing is lit without a continuation.
TEST(Mis, SwitchingStrategiesOffRemovesTheirContribution) {
  const Scene scene = glossyFloorUnderTwoLights();
  const Camera camera = towardsTheHighlights();
  const auto film = [&](bool mis, bool light_samples, int bounces) {
    RenderSettings s;
    s.samples_per_pixel = 4;
    s.max_bounces = bounces;
    s.mis = mis;
    s.light_samples = light_samples;
    return render(scene, camera, s).color;
  };
  const auto same = [](const std::vector<Color>& a, const std::vector<Color>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Color)) == 0;
  };
  const std::vector<Color> direct = film(false, true, 0);
  EXPECT_TRUE(same(film(false, true, 1), direct));
  EXPECT_FALSE(same(film(true, true, 1), direct));
  EXPECT_TRUE(same(film(true, true, 0), direct));  // no continuation: light samples count fully either way
  for (const Color& c : film(true, false, 0)) EXPECT_EQ(c.sum(), 0.0f);
}

// Each strategy alone is unbiased (its mean within four standard errors of a 64-sample MIS render's) but has several
// times MIS's variance here. (Measured when written, at 4 samples per pixel: variance 0.027 with MIS, 0.17 with light
// sampling alone, 1.9 with BSDF sampling alone; at 64 samples each alone came within 1.1% of MIS's mean.)
TEST(Mis, HasLessVarianceThanEitherStrategyAloneOnAGlossyFloorUnderSmallAndLargeLights) {
  const Scene scene = glossyFloorUnderTwoLights();
  const Spread both = spread(scene, true, true), light = spread(scene, false, true), bsdf = spread(scene, true, false);
  const double reference = spread(scene, true, true, 64).mean;
  EXPECT_GT(reference, 0.1);
  for (const auto& [name, s] :
       {std::pair{"MIS", both}, std::pair{"light sampling", light}, std::pair{"BSDF sampling", bsdf}})
    EXPECT_NEAR(s.mean, reference, 4 * s.standard_error) << name;
  EXPECT_LT(3 * both.variance, light.variance) << both.variance << " (MIS) against " << light.variance;
  EXPECT_LT(3 * both.variance, bsdf.variance) << both.variance << " (MIS) against " << bsdf.variance;
}

}  // namespace
}  // namespace wobble::render
