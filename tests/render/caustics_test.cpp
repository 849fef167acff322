// Shadow caustics by the caustic photon map (render/caustic_photons.h): the light in a gelatine body's shadow against
// a brute-force reference (plain path tracing, many samples, no clamp, no map), the clamped default without the map
// failing the same check, no light counted twice, and the map's determinism across thread counts and tile sizes.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "render/caustic_photons.h"
#include "render/dielectric.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "render/sampler.h"
#include "render/scene.h"

namespace wobble::render {
namespace {

using Eigen::Vector3f;

Sky uniformSky(float value) { return {Color::Constant(value), Color::Constant(value), Color::Constant(value)}; }

// A strawberry-coloured gelatine body over a grey floor under a sun a little off the zenith, 10 degrees in radius (a
// larger sun than the default 2, so that brute force finds it often enough to converge; the same sun for both) and
// no sky: the floor in the body's shadow gets light only through the body.
constexpr float kAlbedo = 0.5f;
void litFloor(Scene& scene) {
  scene.addQuad("floor", Quad{{0, 0, 0}, {0, 1, 0}, 40, 1},
                scene.addMaterial(Material::diffuse("floor", Color::Constant(kAlbedo))));
  SunLight sun;
  sun.direction = Vector3f(0.15f, 1, 0.1f);
  sun.irradiance = Color(10, 9, 8);
  sun.angular_radius_deg = 10;
  scene.lights.suns = {sun};
  scene.lights.sky = uniformSky(0);
}
Material strawberry() { return Material::gelatine("strawberry", 1.4f, 0, Color(0.3f, 2.0f, 1.6f)); }

// Mean radiance over a grid of floor points in [-half, half]^2 around (cx, 0, cz), seen from low down beside the body
// (under it, so the camera ray meets only the floor), `samples` paths each.
struct RegionMean {
  Color mean = Color::Zero();
  Color standard_error = Color::Zero();  // of the mean, over all paths
};
RegionMean regionMean(const PathContext& context, float cx, float cz, float half, int samples) {
  const int grid = 8;
  Color sum = Color::Zero(), sq = Color::Zero();
  std::uint64_t n = 0;
  for (int gz = 0; gz < grid; ++gz)
    for (int gx = 0; gx < grid; ++gx) {
      const Vector3f at(cx + half * (2 * (gx + 0.5f) / grid - 1), 0, cz + half * (2 * (gz + 0.5f) / grid - 1));
      const Vector3f from(at.x() + 4, 0.3f, at.z() + 0.5f);
      const Ray ray{from, (at - from).normalized()};
      const PixelSampler sampler(SamplerKind::Independent, std::uint64_t(gz * grid + gx), 7);
      for (int s = 0; s < samples; ++s) {
        const Color c = tracePath(context, ray, CameraSample{}, sampler, std::uint32_t(s)).radiance;
        sum += c, sq += c.cwiseProduct(c), ++n;
      }
    }
  RegionMean m;
  m.mean = sum / float(n);
  const Color variance = (sq / float(n) - m.mean.cwiseProduct(m.mean)).cwiseMax(0.0f);
  m.standard_error = (variance / float(n)).cwiseSqrt();
  return m;
}

// The largest relative difference over R, G, B and luminance.
float relativeError(const Color& a, const Color& reference) {
  float e = std::abs(luminance(a) - luminance(reference)) / luminance(reference);
  for (int c = 0; c < 3; ++c) e = std::max(e, std::abs(a[c] - reference[c]) / reference[c]);
  return e;
}

// The shadow's mean by each estimator, against brute force: the reference (no clamp, no map, many samples) is
// converged well within `tolerance`; the default (clamp 10 and the map, 16 samples a point) agrees with it within
// `tolerance` in R, G, B and luminance; the clamp without the map (the default before it) does not, by far.
RegionMean expectShadowMatchesBruteForce(const Scene& scene, float cx, float cz, float half, int reference_samples,
                                         float tolerance) {
  CausticSettings caustic_settings;
  caustic_settings.photons = 50000;
  caustic_settings.radius = 0.1f;
  CausticMaps map(scene, caustic_settings, 3, false);
  map.cover(16);
  PathSettings brute;
  brute.clamp_indirect = 0;
  PathSettings clamped;
  clamped.clamp_indirect = 10;
  const RegionMean reference = regionMean(PathContext(scene, brute), cx, cz, half, reference_samples);
  const RegionMean with_map = regionMean(PathContext(scene, clamped, &map), cx, cz, half, 16);
  const RegionMean clamped_only = regionMean(PathContext(scene, clamped), cx, cz, half, 1024);
  std::printf(
      "shadow mean RGB: brute force %.4f %.4f %.4f (+- %.4f), map + clamp %.4f %.4f %.4f, clamp alone "
      "%.4f %.4f %.4f\n",
      reference.mean.x(), reference.mean.y(), reference.mean.z(), reference.standard_error.maxCoeff(),
      with_map.mean.x(), with_map.mean.y(), with_map.mean.z(), clamped_only.mean.x(), clamped_only.mean.y(),
      clamped_only.mean.z());
  EXPECT_LT((reference.standard_error.array() / reference.mean.array()).maxCoeff(), tolerance / 4);
  EXPECT_LT(relativeError(with_map.mean, reference.mean), tolerance);
  EXPECT_GT(relativeError(clamped_only.mean, reference.mean), 3 * tolerance);
  return reference;
}

// A slab (2.4 x 0.4 x 2.4 m) 0.8 m over the floor: its shadow is lit through two parallel faces, tinted by 0.4 m of
// gelatine and the internal reflections.
TEST(Caustics, SlabShadowMatchesBruteForce) {
  Scene scene;
  scene.addBox("slab", Box{{0, 1, 0}, {2.4f, 0.4f, 2.4f}}, scene.addMaterial(strawberry()));
  litFloor(scene);
  scene.commit();
  const RegionMean reference = expectShadowMatchesBruteForce(scene, -0.15f, -0.1f, 0.6f, 16384, 0.03f);
  EXPECT_GT(reference.mean.x(), 1.3f * reference.mean.y());  // a red shadow
}

// A ball (radius 1, its centre 1.5 m up) focuses the sun into a bright spot under it: the mean over its shadow.
TEST(Caustics, BallShadowMatchesBruteForce) {
  Scene scene;
  scene.addSphere("ball", Sphere{Vector3f(0, 1.5f, 0), 1}, scene.addMaterial(strawberry()));
  litFloor(scene);
  scene.commit();
  const RegionMean reference = expectShadowMatchesBruteForce(scene, -0.22f, -0.15f, 0.5f, 8192, 0.04f);
  EXPECT_GT(reference.mean.x(), 10 * reference.mean.y());
}

// The same map and the same pixels with one thread or two, and with tiles of any size.
TEST(Caustics, SameBytesWhateverThreadsAndTiles) {
  Scene scene;
  scene.addSphere("ball", Sphere{Vector3f(0, 1.5f, 0), 1}, scene.addMaterial(strawberry()));
  litFloor(scene);
  scene.commit();
  CameraParams params;
  params.position = Vector3f(0, 4, 5);
  params.look_at = Vector3f(0, 0, 0);
  params.width = 40, params.height = 30;
  RenderSettings settings;
  settings.samples_per_pixel = 2;
  settings.clamp_indirect = 10;
  settings.caustics.photons = 20000;
  std::vector<image::Film> films;
  for (const auto& [threads, tile] : {std::pair{1, 16}, std::pair{2, 16}, std::pair{2, 7}}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    settings.tile_size = tile;
    films.push_back(render(scene, Camera(params), settings));
  }
  for (std::size_t i = 1; i < films.size(); ++i) EXPECT_TRUE(films[i].color == films[0].color) << i;
  const CausticMap one = [&] {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    return CausticMap::shoot(scene, CausticTarget::of(scene), settings.caustics, 0, false);
  }();
  const CausticMap two = CausticMap::shoot(scene, CausticTarget::of(scene), settings.caustics, 0, false);
  ASSERT_GT(one.size(), 1000u);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) ASSERT_TRUE(one.photons()[i].p == two.photons()[i].p) << i;
}

}  // namespace
}  // namespace wobble::render
