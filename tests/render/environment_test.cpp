// The environment map (render/environment.h), on small maps made here: its density integrates to 1 and is what
// sample() says; importance sampling keeps the mean of uniform sampling with far less variance (both against the
// map's irradiance integrated texel by texel in closed form); rotation turns a bright texel about the up axis the
// documented way; and in the path tracer, a white furnace: a diffuse sphere under a uniform map shows albedo x
// radiance, a clear gelatine sphere the radiance itself (the map seen through it and in its reflections), the map
// seen directly as it is.
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "render/environment.h"
#include "render/renderer.h"
#include "render/scene.h"

namespace wobble::render {
namespace {

using Eigen::Vector3f;
constexpr double kPi = std::numbers::pi;

// A dim sky with a gradient, darker ground and a small bright "sun" of 2 x 2 texels above the horizon.
image::ImageF sunnyMap(int width) {
  const int height = width / 2;
  image::ImageF map(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const bool sky = y < height / 2;
      const float grain = 0.8f + 0.4f * float((x * 7 + y * 13) % 5) / 4.0f;
      const Color c = sky ? Color(0.3f, 0.5f, 0.9f) * grain : Color(0.2f, 0.18f, 0.15f) * grain;
      for (int k = 0; k < 3; ++k) map.at(x, y, k) = c[k];
    }
  for (int y = height / 4; y < height / 4 + 2; ++y)
    for (int x = width / 3; x < width / 3 + 2; ++x)
      for (int k = 0; k < 3; ++k) map.at(x, y, k) = 400.0f;
  return map;
}

image::ImageF constantMap(int width, const Color& c) {
  image::ImageF map(width, width / 2, 3);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x)
      for (int k = 0; k < 3; ++k) map.at(x, y, k) = c[k];
  return map;
}

float lum(const image::ImageF& map, int x, int y) {
  return luminance(Color(map.at(x, y, 0), map.at(x, y, 1), map.at(x, y, 2)));
}

TEST(Environment, DensityIntegratesToOneAndIsWhatSampleReturns) {
  const EnvironmentMap env(sunnyMap(32), 30, 1.5f);
  // Midpoint rule on a grid uniform in azimuth and cos theta: every cell has solid angle 4 pi / (n m).
  const int n = 1024, m = 512;
  double integral = 0;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      const double z = 1 - 2 * (j + 0.5) / m, phi = 2 * kPi * (i + 0.5) / n, r = std::sqrt(1 - z * z);
      integral += env.pdf(Vector3f(float(r * std::cos(phi)), float(z), float(r * std::sin(phi))));
    }
  EXPECT_NEAR(integral * 4 * kPi / (double(n) * m), 1.0, 2e-3);

  std::mt19937 random(7);
  std::uniform_real_distribution<float> uniform(0, 1);
  int agree = 0;
  const int samples = 2000;
  for (int s = 0; s < samples; ++s) {
    float pdf = 0;
    const Vector3f d = env.sample(uniform(random), uniform(random), pdf);
    ASSERT_NEAR(d.norm(), 1.0f, 1e-5f);
    ASSERT_GT(pdf, 0);
    agree += std::abs(env.pdf(d) - pdf) <= 1e-4f * pdf;
  }
  EXPECT_GE(agree, samples - samples / 100);  // a direction on a texel's edge may be looked up in its neighbour
}

// Irradiance on an upward surface, E = integral of L cos theta over the upper hemisphere. Exactly: a texel of rows
// [z1, z0] in cos theta and width 2 pi / W contributes L (2 pi / W)(z0^2 - z1^2) / 2.
TEST(Environment, ImportanceSamplingKeepsTheMeanOfUniformSamplingWithLessVariance) {
  const image::ImageF map = sunnyMap(64);
  const EnvironmentMap env(map, 37, 1);
  double exact = 0;
  for (int y = 0; y < map.height / 2; ++y) {
    const double z0 = std::cos(kPi * y / map.height), z1 = std::max(0.0, std::cos(kPi * (y + 1) / map.height));
    for (int x = 0; x < map.width; ++x) exact += lum(map, x, y) * (2 * kPi / map.width) * (z0 * z0 - z1 * z1) / 2;
  }

  struct Estimate {
    double mean = 0, variance = 0;
  };
  const auto estimate = [](const auto& draw, int n) {
    double sum = 0, sum2 = 0;
    for (int s = 0; s < n; ++s) {
      const double f = draw();
      sum += f;
      sum2 += f * f;
    }
    Estimate e;
    e.mean = sum / n;
    e.variance = sum2 / n - e.mean * e.mean;
    return e;
  };
  std::mt19937 random(11);
  std::uniform_real_distribution<float> uniform(0, 1);
  const int n = 20000;
  const Estimate importance = estimate(
      [&] {
        float pdf = 0;
        const Vector3f d = env.sample(uniform(random), uniform(random), pdf);
        return d.y() > 0 ? double(luminance(env.eval(d))) * d.y() / pdf : 0.0;
      },
      n);
  const Estimate uniform_sphere = estimate(
      [&] {
        const float z = 1 - 2 * uniform(random), phi = 2 * float(kPi) * uniform(random);
        const float r = std::sqrt(std::max(0.0f, 1 - z * z));
        const Vector3f d(r * std::cos(phi), z, r * std::sin(phi));
        return d.y() > 0 ? double(luminance(env.eval(d))) * d.y() * 4 * kPi : 0.0;
      },
      n);
  // Each mean within 4 standard errors of the exact value.
  EXPECT_NEAR(importance.mean, exact, 4 * std::sqrt(importance.variance / n));
  EXPECT_NEAR(uniform_sphere.mean, exact, 4 * std::sqrt(uniform_sphere.variance / n));
  EXPECT_NEAR(importance.mean, exact, 0.01 * exact);
  // The sun (a 500th of the sky's solid angle, most of its light) makes uniform sampling very noisy.
  EXPECT_LT(importance.variance * 20, uniform_sphere.variance)
      << "importance " << importance.variance << ", uniform " << uniform_sphere.variance;
}

// One bright texel, the one the unrotated map shows looking along +Z (column 3/4 of the width, beside the horizon).
TEST(Environment, RotationTurnsABrightTexelAboutTheUpAxis) {
  const int width = 64, height = 32;
  image::ImageF map(width, height, 3);
  const int column = 3 * width / 4, row = height / 2 - 1;  // just above the horizon
  for (int k = 0; k < 3; ++k) map.at(column, row, k) = 100;
  // The texel's centre direction in the unrotated map: azimuth atan2(z, x) = 2 pi u - pi, polar angle pi v from +Y.
  const double u = (column + 0.5) / width, v = (row + 0.5) / height;
  const double phi = 2 * kPi * u - kPi, theta = kPi * v;
  const Vector3f centre(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                        float(std::sin(theta) * std::sin(phi)));
  ASSERT_GT(centre.z(), 0.99f);  // along +Z, as documented
  for (const float degrees : {0.0f, 90.0f, -90.0f, 200.0f}) {
    const EnvironmentMap env(map, degrees, 1);
    // Right-handed about +Y: (x, z) -> (x cos a + z sin a, -x sin a + z cos a); at 90, +Z goes to +X.
    const double a = degrees * kPi / 180;
    const Vector3f expected(float(centre.x() * std::cos(a) + centre.z() * std::sin(a)), centre.y(),
                            float(-centre.x() * std::sin(a) + centre.z() * std::cos(a)));
    EXPECT_FLOAT_EQ(env.eval(expected).x(), 100) << degrees;
    EXPECT_FLOAT_EQ(env.eval(-expected).x(), 0) << degrees;
    float pdf = 0;
    const Vector3f d = env.sample(0.3f, 0.6f, pdf);  // every sample lands in the one bright texel
    EXPECT_GT(d.dot(expected), std::cos(2 * kPi / width)) << degrees;
  }
  const EnvironmentMap quarter(map, 90, 1);
  EXPECT_FLOAT_EQ(quarter.eval(Vector3f(1, 0.02f, 0).normalized()).x(), 100);
}

TEST(Environment, RefusesAMapThatIsNotTwiceAsWideAsHighOrHasNonFiniteValues) {
  EXPECT_THROW(EnvironmentMap(image::ImageF(30, 16, 3), 0, 1), std::invalid_argument);
  image::ImageF map = constantMap(8, Color::Ones());
  map.at(3, 2, 1) = std::numeric_limits<float>::infinity();
  EXPECT_THROW(EnvironmentMap(map, 0, 1), std::invalid_argument);
  EXPECT_THROW(EnvironmentMap(constantMap(8, Color::Ones()), 0, -1), std::invalid_argument);
  EXPECT_TRUE(EnvironmentMap(constantMap(8, Color::Zero()), 0, 1).empty());
}

// A sphere filling most of a small frame under a map of one radiance L everywhere (strength s).
image::Film furnace(const Material& material, const Color& radiance, float strength, int spp) {
  Scene scene;
  scene.addSphere("ball", Sphere{Vector3f::Zero(), 1}, scene.addMaterial(material));
  scene.lights.environment = std::make_shared<EnvironmentMap>(constantMap(16, radiance), 25, strength);
  scene.commit();
  CameraParams p;
  p.position = {0, 0.5f, 4};
  p.look_at = {0, 0, 0};
  p.vfov_deg = 35;
  p.width = p.height = 24;
  RenderSettings s;
  s.samples_per_pixel = spp;
  s.sample_sky = true;
  s.max_bounces = 2;
  return render(scene, Camera(p), s);
}

// A convex body sees only the environment: a Lambertian surface of albedo a reflects a L whatever the lighting's
// direction, and the map seen past it is L exactly.
TEST(Environment, WhiteFurnaceDiffuseSphereShowsAlbedoTimesRadiance) {
  const Color radiance(0.5f, 1.0f, 2.0f);
  const float strength = 1.5f, albedo = 0.6f;
  const image::Film film = furnace(Material::diffuse("matte", Color::Constant(albedo)), radiance, strength, 16);
  Color on_sphere = Color::Zero();
  int hits = 0, misses = 0;
  for (std::size_t i = 0; i < film.color.size(); ++i) {
    if (std::abs(film.albedo[i].x() - albedo) < 1e-5f) {  // every sample of the pixel met the sphere
      on_sphere += film.color[i];
      ++hits;
    } else if (std::isinf(film.depth[i])) {  // every sample of the pixel escaped
      for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(film.color[i][k], strength * radiance[k]);
      ++misses;
    }
  }
  ASSERT_GT(hits, 100);
  ASSERT_GT(misses, 50);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(on_sphere[k] / hits, albedo * strength * radiance[k], 0.01 * radiance[k]);
}

// A smooth clear dielectric loses and gains nothing: every path, reflected or refracted any number of times, ends in
// the map, so every pixel on the sphere is L as well (to the paths cut after 64 interfaces).
TEST(Environment, WhiteFurnaceClearGelatineShowsTheMapThroughItAndInItsReflections) {
  const Color radiance(0.5f, 1.0f, 2.0f);
  const image::Film film = furnace(Material::gelatine("clear", 1.4f, 0, Color::Zero()), radiance, 1, 4);
  for (std::size_t i = 0; i < film.color.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(film.color[i][k], radiance[k], 1e-3 * radiance[k]) << i;
}

}  // namespace
}  // namespace wobble::render
