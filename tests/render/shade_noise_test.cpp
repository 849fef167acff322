// The sky-lit shade under a low slab at the cloth scenes' sampling (adaptive up to 16 samples, denoised) against a
// converged picture of the same frame: the shade is lit through the gap between slab and floor by the sky and the
// sunlit floor beyond, so each of its samples is dim light or a bright gap, and adaptive sampling takes its pixels
// to the full 16. The denoiser must not then spread its wide iterations over them (denoiser.h, well-sampled pixels):
// their taps reach the sunlit floor past the slab's edge and pull the shade up.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "image/film.h"
#include "render/denoiser.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "tests/render/test_util.h"

namespace wobble::render {
namespace {

using Eigen::Vector3f;

// The slab: 1.6 m square, 4 cm thick, its underside 12 cm above the floor; a ball under it for a contact shadow.
constexpr float kSlabBottom = 0.12f, kSlabTop = 0.16f, kSlabHalf = 0.8f;

Scene slabOverFloor() {
  Scene scene;
  scene.addQuad("floor", Quad{{0, 0, 0}, {0, 1, 0}, 12, 6},
                scene.addMaterial(
                    Material::textured("checker", std::make_shared<CheckerTexture>(Color(0.8f, 0.8f, 0.8f),
                                                                                   Color(0.45f, 0.45f, 0.5f), 1))));
  scene.addBox("slab",
               Box{{0, 0.5f * (kSlabBottom + kSlabTop), 0}, {2 * kSlabHalf, kSlabTop - kSlabBottom, 2 * kSlabHalf}},
               scene.addMaterial(Material::diffuse("cloth", Color(0.25f, 0.45f, 0.8f))));
  scene.addSphere("ball", Sphere{{0.35f, 0.06f, 0.6f}, 0.06f},
                  scene.addMaterial(Material::diffuse("ball", Color(0.7f, 0.7f, 0.7f))));
  SunLight sun;
  sun.direction = Vector3f(0.3f, 1, 0.2f).normalized();
  scene.lights.suns = {sun};
  scene.commit();
  return scene;
}

Camera camera() {
  CameraParams cp;
  cp.position = {0.6f, 0.45f, 2.6f};
  cp.look_at = {0.1f, 0.05f, 0.4f};
  cp.vfov_deg = 30;
  cp.width = 96;
  cp.height = 64;
  return Camera(cp);
}

// Whether the camera ray through (x, y) meets the floor under the slab before anything else (the slab, the ball):
// by the ray's own intersections, not the renderer's.
bool floorUnderSlab(const Camera& cam, float x, float y) {
  const Ray r = cam.ray(x, y);
  if (!(r.direction.y() < 0)) return false;
  const float t_floor = -r.origin.y() / r.direction.y();
  const Vector3f p = r.at(t_floor);
  if (std::abs(p.x()) > kSlabHalf || std::abs(p.z()) > kSlabHalf) return false;
  // The slab's box (slabs method) and the ball.
  float t0 = 0, t1 = t_floor;
  const Vector3f lo(-kSlabHalf, kSlabBottom, -kSlabHalf), hi(kSlabHalf, kSlabTop, kSlabHalf);
  bool slab = true;
  for (int a = 0; a < 3 && slab; ++a) {
    const float inv = 1.0f / r.direction[a];
    float ta = (lo[a] - r.origin[a]) * inv, tb = (hi[a] - r.origin[a]) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    slab = t0 <= t1;
  }
  if (slab) return false;
  const Vector3f oc = r.origin - Vector3f(0.35f, 0.06f, 0.6f);
  const float b = oc.dot(r.direction), disc = b * b - (oc.squaredNorm() - 0.06f * 0.06f);
  return !(disc >= 0 && -b - std::sqrt(disc) < t_floor);
}

// The shade: pixels whose whole footprint (corners and centre) is the floor under the slab.
std::vector<char> shade(const Camera& cam) {
  std::vector<char> in(std::size_t(cam.width()) * cam.height(), 0);
  for (int y = 0; y < cam.height(); ++y)
    for (int x = 0; x < cam.width(); ++x)
      in[std::size_t(y) * cam.width() + x] =
          test::wholePixel(x, y, [&](float u, float v) { return floorUnderSlab(cam, u, v); });
  return in;
}

// scenes/cloth_drop.toml's sampling (render.samples = 16, the presets' threshold 0.1 from one sample), then the
// denoiser, against 256 samples a pixel (no adaptive stop, no denoiser). Measured on this frame: RMSE over the shade
// (479 pixels) 0.0302 denoised; 0.0406 with every pixel through all five iterations (well_sampled = 0), 0.0685 not
// denoised.
TEST(ShadeNoise, WellSampledShadeStaysAsSampledUnderTheDenoiser) {
  const Scene scene = slabOverFloor();
  const Camera cam = camera();
  const std::vector<char> region = shade(cam);
  RenderSettings reference;
  reference.samples_per_pixel = 256;
  const image::Film converged = render(scene, cam, reference);

  RenderSettings settings;
  settings.samples_per_pixel = 16;
  settings.min_samples = 1;
  settings.noise_threshold = 0.1f;
  settings.frame = 5;
  const image::Film film = render(scene, cam, settings);
  int pixels = 0, full = 0;
  for (std::size_t i = 0; i < region.size(); ++i)
    if (region[i]) ++pixels, full += film.samples[i] == 16u;
  ASSERT_GT(pixels, 300);
  EXPECT_GT(full, 9 * pixels / 10) << "adaptive sampling takes the shade to the full count";
  const auto in = [&](int x, int y) { return region[std::size_t(y) * cam.width() + x] != 0; };
  const double noisy = test::displayRmse(cam.width(), cam.height(), film.color, converged.color, in);
  const double denoised = test::displayRmse(cam.width(), cam.height(), denoise(film), converged.color, in);
  EXPECT_LT(denoised, 0.034) << "not denoised: " << noisy;
}

}  // namespace
}  // namespace wobble::render
