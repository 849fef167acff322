// An environment map through `wobble run` (render.environment, environment_rotation, environment_strength): camera
// rays that miss see the map's texel in their direction times the strength, turned by the rotation; the map replaces
// the sun (a floor under a constant map shows albedo times its radiance and nothing more); and it is sampled by its
// luminance (a floor lit by a small bright patch is far less noisy than with sky_sampling off). Oracles: the
// equirectangular mapping written out (the top row looks up, the centre column along +X, azimuth atan2(z, x)), the
// white furnace, and the irradiance of a small source, E = L * solid angle * cos.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "image/image_file.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

constexpr int kW = 16, kH = 8;  // the map's texels: 22.5 degrees each way

class EnvironmentScene : public testing::ScratchDir {
 protected:
  // Renders frame 1 with the map `map` and the given [camera] and [render] lines; returns the linear colour (EXR
  // half floats: three significant digits).
  image::ImageF render(const image::ImageF& map, const std::string& camera, const std::string& extra) {
    image::writeExrImage(dir() / "env.exr", map, {"R", "G", "B"}, false);
    const fs::path scene = write("env.toml", R"([simulation]
dt = 0.01
duration = 0.01
fps = 100

[bodies.jelly]
type = "jelly"
n = 2
size = 0.2
center = [0, 50, 0]

[colliders.floor]
type = "plane"
texture = "none"
color = [0.5, 0.5, 0.5]

[camera]
)" + camera + R"(

[render]
environment = "env.exr"
noise_threshold = 0
denoise = false
)" + extra + "\n");
    const fs::path out = dir() / "out";
    fs::remove_all(out);
    const int status =
        testing::runWobble("run " + scene.string() + " --render exr --out " + out.string(), dir() / "log.txt");
    EXPECT_EQ(status, 0) << testing::slurpFile(dir() / "log.txt");
    return image::readImageFile(out / "exr/env_0001.exr").image;
  }
  // A map whose every texel has its own colour: R its column, G its row.
  static image::ImageF labelled() {
    image::ImageF map(kW, kH, 3);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) map.at(x, y, 0) = 0.1f + x, map.at(x, y, 1) = 0.2f + y, map.at(x, y, 2) = 0.5f;
    return map;
  }
  // The camera at (0, 1, 0) looking at the centre of texel (x, y) of a map turned by rotation_deg, with a field of
  // view narrow enough that every pixel sees that texel.
  static std::string lookAtTexel(int x, int y, double rotation_deg) {
    const double phi = 2 * M_PI * (x + 0.5) / kW - M_PI - rotation_deg * M_PI / 180, theta = M_PI * (y + 0.5) / kH;
    char s[200];
    std::snprintf(s, sizeof s, "position = [0, 1, 0]\nlook_at = [%.9f, %.9f, %.9f]\nfov = 4\nresolution = [6, 6]",
                  std::sin(theta) * std::cos(phi), 1 + std::cos(theta), std::sin(theta) * std::sin(phi));
    return s;
  }
};

TEST_F(EnvironmentScene, MissedRaysSeeTheTexelInTheirDirectionTurnedAndScaled) {
  const image::ImageF map = labelled();
  for (const auto& [x, y, rotation, strength] :
       {std::tuple{3, 2, 0.0, 1.0}, {12, 1, 0.0, 2.5}, {5, 3, 90.0, 1.0}, {9, 2, -135.0, 0.5}}) {
    const image::ImageF img = render(map, lookAtTexel(x, y, rotation),
                                     "environment_rotation = " + std::to_string(rotation) +
                                         "\nenvironment_strength = " + std::to_string(strength));
    for (int p = 0; p < img.width * img.height; ++p)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(img.pixels[std::size_t(p) * 3 + c], strength * map.at(x, y, c), 1e-3 * strength * map.at(x, y, c))
            << "texel " << x << ", " << y << " turned by " << rotation << ", pixel " << p << ", channel " << c;
  }
}

TEST_F(EnvironmentScene, AConstantMapLightsTheFloorAloneWithoutTheSun) {
  // A grey floor (albedo 0.5) under a constant map of radiance L, strength 2: it reflects 0.5 * 2 * L, as in a white
  // furnace; the scene's default sun would add to it.
  image::ImageF map(kW, kH, 3);
  for (int i = 0; i < kW * kH; ++i)
    map.pixels[std::size_t(i) * 3] = 0.2f, map.pixels[std::size_t(i) * 3 + 1] = 0.4f,
                                map.pixels[std::size_t(i) * 3 + 2] = 0.8f;
  const image::ImageF img = render(map, "position = [0, 1, 0]\nlook_at = [0.1, 0, 0]\nfov = 30\nresolution = [8, 8]",
                                   "environment_strength = 2\nsamples = 16");
  const double expected[3] = {0.2, 0.4, 0.8};
  const int n = img.width * img.height;
  for (int c = 0; c < 3; ++c) {
    double mean = 0;
    for (int p = 0; p < n; ++p) mean += img.pixels[std::size_t(p) * 3 + c] / double(n);
    EXPECT_NEAR(mean, 0.5 * 2 * expected[c], 0.02 * expected[c]) << "channel " << c;
  }
}

TEST_F(EnvironmentScene, TheMapIsSampledByItsLuminance) {
  // One bright texel straight overhead (at the top row, radiance 400) in a black map: the floor's irradiance is
  // L * solid angle * cos. Found by sampling the map, every sample of every pixel sees it; found by the BSDF's cosine
  // samples alone, a few in a hundred do, and four samples a pixel scatter far around the mean.
  image::ImageF map(kW, kH, 3);
  for (int x = 0; x < kW; ++x)
    for (int c = 0; c < 3; ++c) map.at(x, 0, c) = 400;
  // The top row's texels: polar angle up to pi / kH, all kW of them: solid angle 2 pi (1 - cos(pi / kH)); their cosine
  // to the floor's normal from cos(0) to cos(pi / kH), mean (1 + cos(pi / kH)) / 2 over that cap.
  const double cap = 2 * M_PI * (1 - std::cos(M_PI / kH));
  const double irradiance = 400 * cap * (1 + std::cos(M_PI / kH)) / 2;
  const double radiance = 0.5 * irradiance / M_PI;  // the grey floor's
  const std::string camera = "position = [0, 1, 0]\nlook_at = [0.1, 0, 0]\nfov = 30\nresolution = [16, 16]";
  const auto spread = [&](const image::ImageF& img) {
    double mean = 0, var = 0;
    const int n = img.width * img.height;
    for (int p = 0; p < n; ++p) mean += img.pixels[std::size_t(p) * 3] / n;
    for (int p = 0; p < n; ++p) var += std::pow(img.pixels[std::size_t(p) * 3] - mean, 2) / n;
    return std::pair{mean, std::sqrt(var)};
  };
  const auto [sampled_mean, sampled_spread] = spread(render(map, camera, "samples = 4"));
  EXPECT_NEAR(sampled_mean, radiance, 0.03 * radiance);
  EXPECT_LT(sampled_spread, 0.05 * radiance);
  const auto [unsampled_mean, unsampled_spread] = spread(render(map, camera, "samples = 4\nsky_sampling = false"));
  EXPECT_GT(unsampled_spread, 0.5 * radiance);  // the same picture found by chance: the sampling is what made it clean
}

}  // namespace
}  // namespace wobble
