// Lighting: shadows from the sun and area lights, and a rendered sphere that obeys Lambert's cosine law.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "render/path_tracer.h"
#include "render/renderer.h"
#include "render/scene.h"

namespace wobble::render {
namespace {

using Eigen::Vector3f;

// A floor at y = 0 and a 1 m blocker floating at y = 1 above the origin.
Scene floorWithBlocker() {
  Scene scene;
  const auto grey = scene.addMaterial(Material::diffuse("grey", Color::Constant(0.5f)));
  scene.addQuad("floor", Quad{{0, 0, 0}, {0, 1, 0}, 20, 1}, grey);
  scene.addQuad("blocker", Quad{{0, 1, 0}, {0, 1, 0}, 1, 1}, grey);
  scene.commit();
  return scene;
}

Vector3f onFloor(float x, float z) { return offsetFromSurface(Vector3f(x, 0, z), Vector3f::UnitY()); }

// A light sample as the path tracer uses it: its value where the shadow ray is unoccluded, zero where it is not.
LightSample visible(const Scene& scene, LightSample s) {
  if (!s.value.isZero() && !unoccluded(scene, s.shadow)) s.value = Color::Zero();
  return s;
}
Color seen(const Scene& scene, const LightSample& s) { return visible(scene, s).value; }

TEST(Lighting, SunShadowOnUnderABlockerAndOffBesideIt) {
  const Scene scene = floorWithBlocker();
  SunLight sun;
  sun.direction = {0, 1, 0};
  sun.irradiance = {2, 2, 2};
  sun.angular_radius_deg = 0;
  const Vector3f up = Vector3f::UnitY();
  EXPECT_TRUE(seen(scene, sampleSun(sun, onFloor(0, 0), up, 0.5f, 0.5f)).isZero());
  const LightSample lit = visible(scene, sampleSun(sun, onFloor(3, 0), up, 0.5f, 0.5f));
  EXPECT_TRUE(lit.value.isApprox(Color(2, 2, 2)));
  EXPECT_NEAR((lit.wi - up).norm(), 0, 1e-6);
  // A low sun from +x moves the shadow: the point at x = -1 is now under it, the origin is lit.
  sun.direction = {1, 1, 0};
  EXPECT_TRUE(seen(scene, sampleSun(sun, onFloor(-1, 0), up, 0.5f, 0.5f)).isZero());
  EXPECT_FALSE(seen(scene, sampleSun(sun, onFloor(0.6f, 0), up, 0.5f, 0.5f)).isZero());
  // A sun below the horizon lights nothing.
  sun.direction = {0, -1, 0};
  EXPECT_TRUE(seen(scene, sampleSun(sun, onFloor(3, 0), up, 0.5f, 0.5f)).isZero());
}

TEST(Lighting, SoftSunGivesPenumbraAtTheShadowEdge) {
  const Scene scene = floorWithBlocker();
  SunLight sun;
  sun.direction = {0, 1, 0};
  sun.angular_radius_deg = 10;
  // At the shadow's geometric edge (x = 0.5), about half the sun disc is hidden.
  int lit = 0;
  const int n = 32;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      lit += !seen(scene, sampleSun(sun, onFloor(0.5f, 0), Vector3f::UnitY(), (i + 0.5f) / n, (j + 0.5f) / n)).isZero();
  EXPECT_GT(lit, n * n / 4);
  EXPECT_LT(lit, 3 * n * n / 4);
}

TEST(Lighting, AreaLightIsShadowedAndFallsOffWithDistance) {
  const Scene scene = floorWithBlocker();
  // A small 0.2 m square light facing down, 10 m above the floor.
  RectLight light;
  light.corner = {-0.1f, 10, -0.1f};
  light.edge_u = {0.2f, 0, 0};
  light.edge_v = {0, 0, 0.2f};  // edge_u x edge_v = -y: emits downwards
  light.radiance = {100, 100, 100};
  const Vector3f up = Vector3f::UnitY();
  EXPECT_TRUE(seen(scene, sampleRect(light, onFloor(0, 0), up, 0.5f, 0.5f)).isZero());
  // Beside the blocker, at (3, 0, 0): one sample at the light's centre gives L cos_light A / d^2.
  const LightSample s = visible(scene, sampleRect(light, onFloor(3, 0), up, 0.5f, 0.5f));
  const float d2 = 9 + 100, cos_light = 10 / std::sqrt(d2);
  EXPECT_NEAR(s.value.x(), 100 * cos_light * 0.04f / d2, 1e-4);
  // Facing away: a light emitting upwards does not light the floor.
  std::swap(light.edge_u, light.edge_v);
  EXPECT_TRUE(seen(scene, sampleRect(light, onFloor(3, 0), up, 0.5f, 0.5f)).isZero());
}

// Oracle: a white diffuse sphere under a sun with irradiance pi and no sky has radiance albedo * max(0, n.l) at the
// point with normal n. Checked per pixel for pixels whose whole footprint lies on the sphere.
TEST(Lighting, LitSphereHasLambertianBrightAndDarkSides) {
  Scene scene;
  const float albedo = 0.8f;
  scene.addSphere("ball", Sphere{{0, 0, 0}, 1}, scene.addMaterial(Material::diffuse("white", Color::Constant(albedo))));
  const Vector3f l = Vector3f(1, 0.5f, 0.8f).normalized();
  SunLight sun;
  sun.direction = l;
  sun.irradiance = Color::Constant(std::numbers::pi_v<float>);
  sun.angular_radius_deg = 0;
  scene.lights.suns = {sun};
  scene.lights.sky = Sky::black();
  scene.commit();

  CameraParams cp;
  cp.position = {0, 0, 4};
  cp.look_at = {0, 0, 0};
  cp.vfov_deg = 36;
  cp.width = cp.height = 40;
  const Camera camera(cp);
  RenderSettings settings;
  settings.samples_per_pixel = 8;
  const image::Film film = render(scene, camera, settings);

  // Where a camera ray through film point (x, y) meets the unit sphere, if it does.
  const auto normalAt = [&](float x, float y) -> std::optional<Vector3f> {
    const Ray r = camera.ray(x, y);
    const float b = r.origin.dot(r.direction), c = r.origin.squaredNorm() - 1;
    const float disc = b * b - c;
    if (disc < 0) return std::nullopt;
    return r.at(-b - std::sqrt(disc)).normalized();
  };
  int bright = 0, dark = 0, checked = 0;
  for (int y = 0; y < cp.height; ++y)
    for (int x = 0; x < cp.width; ++x) {
      const float value = film.color[film.index(x, y)].x();
      // The footprint on a 5 x 5 grid (its corners included): n.l varies smoothly, so its extremes over the pixel
      // are within a hair of the grid's.
      float lo = 1, hi = -1;
      int hits = 0;
      for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j)
          if (const auto n = normalAt(x + i / 4.0f, y + j / 4.0f)) {
            ++hits;
            lo = std::min(lo, n->dot(l)), hi = std::max(hi, n->dot(l));
          }
      if (hits == 0) {
        EXPECT_EQ(value, 0.0f) << "background pixel " << x << "," << y;
        continue;
      }
      if (hits < 25) continue;  // silhouette pixel, partly background
      ++checked;
      // The pixel's value is a mean of albedo max(0, n.l) over its footprint, so it lies between the extremes.
      EXPECT_GE(value, albedo * std::max(0.0f, lo) - 2e-3f) << x << "," << y;
      EXPECT_LE(value, albedo * std::max(0.0f, hi) + 2e-3f) << x << "," << y;
      if (lo > 0.5f) ++bright;
      if (hi < 0) {
        ++dark;
        EXPECT_EQ(value, 0.0f) << "shadowed side " << x << "," << y;
      }
    }
  EXPECT_GT(checked, 600);
  EXPECT_GT(bright, 100);
  EXPECT_GT(dark, 50);
}

}  // namespace
}  // namespace wobble::render
