// Denoiser: on hand-made films it removes noise from flat lighting, keeps normal, albedo and sky edges sharp, is
// deterministic across thread counts and rejects bad input.
#include "render/denoiser.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "image/film.h"

namespace wobble::render {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Zero-mean noise of standard deviation sigma (uniform, so bounded by sigma sqrt(3)), from a fixed seed.
class Noise {
 public:
  explicit Noise(std::uint32_t seed) : rng_(seed) {}
  float operator()(float sigma) {
    const float u = static_cast<float>(rng_() >> 8) * 0x1p-24f - 0.5f;  // [-1/2, 1/2): variance 1/12
    return u * std::sqrt(12.0f) * sigma;
  }

 private:
  std::mt19937 rng_;
};

// A surface pixel lit by grey `lighting` (the diffuse part is albedo * lighting, nothing else reflected), with the
// variance of its demodulated luminance.
void setSurface(image::Film& film, int x, int y, const Color& albedo, const Eigen::Vector3f& normal, float depth,
                float lighting, float variance) {
  const std::size_t i = film.index(x, y);
  film.albedo[i] = albedo;
  film.normal[i] = normal;
  film.depth[i] = depth;
  film.diffuse[i] = albedo * lighting;
  film.color[i] = film.diffuse[i];
  film.variance_diffuse[i] = variance;
  film.variance_other[i] = 0;
  film.samples[i] = 16;
}

// Sky seen directly: no albedo, normal or depth; all of its colour is "other".
void setSky(image::Film& film, int x, int y, const Color& sky) {
  const std::size_t i = film.index(x, y);
  film.albedo[i] = Color::Zero();
  film.normal[i] = Eigen::Vector3f::Zero();
  film.depth[i] = kInf;
  film.diffuse[i] = Color::Zero();
  film.color[i] = sky;
  film.variance_diffuse[i] = 0;
  film.variance_other[i] = 0;
  film.samples[i] = 16;
}

// Root mean square over all channels of the pixels selected by `use` of (a - b).
template <typename Select>
double rmsDifference(const image::Film& film, const std::vector<Color>& a, const std::vector<Color>& b, Select use) {
  double sq = 0;
  long n = 0;
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      if (!use(x, y)) continue;
      const std::size_t i = film.index(x, y);
      sq += double((a[i] - b[i]).squaredNorm()), n += 3;
    }
  return std::sqrt(sq / double(n));
}

TEST(Denoiser, NormalEdgeStaysSharpWhileNoiseIsRemoved) {
  const int w = 48, h = 24, edge = 24;  // columns < edge face the camera, the others face +x
  // Noise large enough (for the 0.6 step) that the luminance weight alone would let the sides mix: the normals must
  // keep them apart (with sigma_normal = 0 the column means below are off by about 0.014).
  const float sigma = 0.1f, albedo = 0.5f;
  image::Film film(w, h);
  std::vector<Color> truth(std::size_t(w) * h);
  Noise noise(1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool left = x < edge;
      const float light = left ? 0.2f : 0.8f;
      setSurface(film, x, y, Color::Constant(albedo), left ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX(), 5,
                 light + noise(sigma), sigma * sigma);
      truth[film.index(x, y)] = Color::Constant(albedo * light);
    }
  const std::vector<Color> out = denoise(film);

  // The two columns at the edge: a filter that mixed the sides would pull them towards the mean of 0.1 and 0.4.
  for (const int x : {edge - 1, edge}) {
    const float expected = albedo * (x < edge ? 0.2f : 0.8f);
    double column_mean = 0;
    for (int y = 0; y < h; ++y) {
      const Color& c = out[film.index(x, y)];
      // Within the input noise's standard deviation (0.05): no leak from the other side, which is 0.3 away.
      EXPECT_NEAR(c.x(), expected, albedo * sigma) << x << "," << y;
      column_mean += c.x();
    }
    // On average over the column within 2% of the step.
    EXPECT_NEAR(column_mean / h, expected, 0.02 * albedo * 0.6) << "column " << x;
  }
  // Away from the edge, the noise is reduced at least twice.
  const auto away = [&](int x, int) { return std::abs(x - edge) >= 6 && std::abs(x - (edge - 1)) >= 6; };
  const double before = rmsDifference(film, film.color, truth, away), after = rmsDifference(film, out, truth, away);
  EXPECT_GT(before, 0.5 * albedo * sigma);  // there was noise to remove
  EXPECT_LT(after, before / 2);
}

TEST(Denoiser, AlbedoCheckerSurvivesDemodulation) {
  const int w = 40, h = 32;
  const float sigma = 0.05f, lighting = 0.6f;
  image::Film film(w, h);
  std::vector<Color> truth(std::size_t(w) * h);
  Noise noise(2);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // One-pixel squares of two quite different colours.
      const Color albedo = (x + y) % 2 == 0 ? Color(0.9f, 0.8f, 0.1f) : Color(0.1f, 0.3f, 0.7f);
      setSurface(film, x, y, albedo, Eigen::Vector3f::UnitZ(), 3, lighting + noise(sigma), sigma * sigma);
      truth[film.index(x, y)] = albedo * lighting;
    }
  const std::vector<Color> out = denoise(film);
  const auto all = [](int, int) { return true; };
  const double before = rmsDifference(film, film.color, truth, all), after = rmsDifference(film, out, truth, all);
  EXPECT_GT(before, 0.2 * sigma);
  // Blurring the texture would cost about half the colours' difference times the lighting (0.2 and more); smoothing
  // the lighting alone reduces the error several times.
  EXPECT_LT(after, before / 3);
  // Every pixel is its own albedo times a lighting close to the true one.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = film.index(x, y);
      const Color ratio = out[i].cwiseQuotient(film.albedo[i]);
      EXPECT_NEAR(ratio.x(), ratio.z(), 1e-4) << x << "," << y;  // the same lighting in every channel
      EXPECT_NEAR(ratio.x(), lighting, sigma) << x << "," << y;
    }
}

TEST(Denoiser, FlatLitPlaneKeepsItsMeanAndLosesItsNoise) {
  const int w = 48, h = 40;
  const float sigma = 0.08f, lighting = 0.5f;
  const Color albedo(0.7f, 0.6f, 0.5f);
  image::Film film(w, h);
  std::vector<Color> truth(std::size_t(w) * h, albedo * lighting);
  Noise noise(3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      setSurface(film, x, y, albedo, Eigen::Vector3f(0, 0.6f, 0.8f), 7, lighting + noise(sigma), sigma * sigma);
  const std::vector<Color> out = denoise(film);
  Color noisy_mean = Color::Zero(), denoised_mean = Color::Zero();
  for (std::size_t i = 0; i < out.size(); ++i) noisy_mean += film.color[i], denoised_mean += out[i];
  noisy_mean /= float(out.size()), denoised_mean /= float(out.size());
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(denoised_mean[c], noisy_mean[c], 0.01f * noisy_mean[c]) << "channel " << c;
    EXPECT_NEAR(denoised_mean[c], truth[0][c], 0.01f * truth[0][c]) << "channel " << c;
  }
  const auto all = [](int, int) { return true; };
  EXPECT_LT(rmsDifference(film, out, truth, all), rmsDifference(film, film.color, truth, all) / 3);
}

// A grey disc of surface, noisy and with a coat reflection (so both of the filter's signals run next to the sky), in
// the middle of a bright blue sky: no sky in the surface, no surface in the sky.
TEST(Denoiser, SkyAndSurfacesDoNotMix) {
  const int w = 40, h = 40;
  const float sigma = 0.05f, lighting = 0.4f;
  const Color sky(0.3f, 0.5f, 1.5f);
  const auto inDisc = [](int x, int y) {
    return (x - 19.5f) * (x - 19.5f) + (y - 19.5f) * (y - 19.5f) < 14.0f * 14.0f;
  };
  image::Film film(w, h);
  Noise noise(4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!inDisc(x, y)) {
        setSky(film, x, y, sky);
        continue;
      }
      setSurface(film, x, y, Color::Constant(0.6f), Eigen::Vector3f::UnitZ(), 4, lighting + noise(sigma),
                 sigma * sigma);
      const std::size_t i = film.index(x, y);
      film.color[i] += Color::Constant(0.1f + noise(sigma));  // a grey coat reflection on top
      film.variance_other[i] = sigma * sigma;
    }
  const std::vector<Color> out = denoise(film);
  int boundary = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Color& c = out[film.index(x, y)];
      if (!inDisc(x, y)) {
        // Exact up to float rounding of a weighted mean of equal values (a few ulp of 1.5).
        EXPECT_NEAR((c - sky).cwiseAbs().maxCoeff(), 0, 1e-6) << "sky " << x << "," << y;
        continue;
      }
      // Everything on the surface is grey, so any sky in it would show as blue over red.
      EXPECT_NEAR(c.z() - c.x(), 0, 1e-5) << "surface " << x << "," << y;
      EXPECT_NEAR(c.x(), 0.6f * lighting + 0.1f, 2 * sigma) << "surface " << x << "," << y;
      bool next_to_sky = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) next_to_sky |= !inDisc(x + dx, y + dy);
      boundary += next_to_sky;
    }
  EXPECT_GT(boundary, 50);  // the checks above did cover the boundary
}

// The sky seen directly is exact up to anti-aliasing (denoiser.cpp), so the filter should leave it as it is. Here the
// sky brightens by 0.01 per row, and its pixels must come back unchanged wherever they are.
// (Sky pixels inside the bounding box of the surfaces were once filtered with each other, blurring the sky near a
// surface by up to 0.01 here.)
TEST(Denoiser, SkySeenDirectlyIsLeftAsRendered) {
  const int w = 40, h = 40;
  const float sigma = 0.05f;
  const auto skyColor = [](int y) { return Color(0.3f, 0.5f + 0.01f * y, 1.5f); };
  const auto inDisc = [](int x, int y) {
    return (x - 19.5f) * (x - 19.5f) + (y - 19.5f) * (y - 19.5f) < 14.0f * 14.0f;
  };
  image::Film film(w, h);
  Noise noise(6);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!inDisc(x, y)) {
        setSky(film, x, y, skyColor(y));
        continue;
      }
      setSurface(film, x, y, Color::Constant(0.6f), Eigen::Vector3f::UnitZ(), 4, 0.4f + noise(sigma), sigma * sigma);
      const std::size_t i = film.index(x, y);
      film.color[i] += Color::Constant(0.1f + noise(sigma));
      film.variance_other[i] = sigma * sigma;
    }
  const std::vector<Color> out = denoise(film);
  int changed = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (!inDisc(x, y)) changed += (out[film.index(x, y)] - skyColor(y)).cwiseAbs().maxCoeff() > 2e-6f;
  EXPECT_EQ(changed, 0) << "sky pixels changed by the filter";
}

// The film of SameBytesWithOneAndTwoThreads: surfaces with noisy light and a coat, a corner of sky, and a few
// single-sample pixels.
image::Film mixedFilm(int w, int h, std::uint32_t seed, int sky_x) {
  image::Film film(w, h);
  Noise noise(seed);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (y < 10 && x > sky_x) {
        setSky(film, x, y, Color(0.3f, 0.5f, 1.0f));
        continue;
      }
      const Eigen::Vector3f n = Eigen::Vector3f(std::sin(0.1f * x), 0.3f, 1.0f).normalized();
      setSurface(film, x, y, Color(0.2f + 0.01f * x, 0.5f, 0.3f), n, 2 + 0.05f * y, 0.5f + noise(0.1f), 0.01f);
      const std::size_t i = film.index(x, y);
      film.color[i] += Color::Constant(0.05f + noise(0.02f));
      film.variance_other[i] = (x % 7 == 0) ? -1.0f : 0.0004f;  // a few single-sample pixels
    }
  return film;
}

TEST(Denoiser, SameBytesWithOneAndTwoThreads) {
  const image::Film film = mixedFilm(64, 48, 5, 20);
  DenoiseSettings settings;
  settings.radius = 2;
  std::vector<Color> one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = denoise(film, settings);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = denoise(film, settings);
  }
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(Color)), 0);
  // It did something.
  EXPECT_NE(std::memcmp(one.data(), film.color.data(), one.size() * sizeof(Color)), 0);
}

// denoise() keeps its planes from one call to the next on each thread: a film denoised after others of other sizes
// and contents (sky where it had surface, surface where it had sky) gives the bytes a fresh thread gives.
TEST(Denoiser, EarlierFilmsLeaveNoTrace) {
  const image::Film film = mixedFilm(64, 48, 5, 20);
  std::vector<Color> fresh;
  std::thread([&] { fresh = denoise(film); }).join();  // a new thread: nothing kept yet
  denoise(mixedFilm(40, 30, 6, 5));
  image::Film all_sky(64, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) setSky(all_sky, x, y, Color(5.0f, 0.1f, 0.1f));
  denoise(all_sky);
  denoise(mixedFilm(64, 48, 7, 50));  // same size, other sky and noise
  const std::vector<Color> again = denoise(film);
  ASSERT_EQ(fresh.size(), again.size());
  EXPECT_EQ(std::memcmp(fresh.data(), again.data(), fresh.size() * sizeof(Color)), 0);
}

TEST(Denoiser, RejectsBadInput) {
  image::Film film(8, 6);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) setSurface(film, x, y, Color::Constant(0.5f), Eigen::Vector3f::UnitZ(), 1, 0.5f, 0.01f);
  EXPECT_NO_THROW(denoise(film));

  image::Film short_albedo = film;
  short_albedo.albedo.pop_back();
  EXPECT_THROW(denoise(short_albedo), std::invalid_argument);
  image::Film short_variance = film;
  short_variance.variance_other.resize(3);
  EXPECT_THROW(denoise(short_variance), std::invalid_argument);
  image::Film wrong_size = film;
  wrong_size.width = 9;
  EXPECT_THROW(denoise(wrong_size), std::invalid_argument);
  EXPECT_THROW(denoise(image::Film{}), std::invalid_argument);

  DenoiseSettings negative;
  negative.iterations = -1;
  EXPECT_THROW(denoise(film, negative), std::invalid_argument);
  DenoiseSettings radius;
  radius.radius = 3;
  EXPECT_THROW(denoise(film, radius), std::invalid_argument);
  DenoiseSettings sigma;
  sigma.sigma_luminance = 0;
  EXPECT_THROW(denoise(film, sigma), std::invalid_argument);
  DenoiseSettings held;
  held.well_sampled = -1;
  EXPECT_THROW(denoise(film, held), std::invalid_argument);
  // Zero iterations is allowed and leaves the colour as it was.
  DenoiseSettings none;
  none.iterations = 0;
  const std::vector<Color> same = denoise(film, none);
  for (std::size_t i = 0; i < same.size(); ++i) EXPECT_NEAR((same[i] - film.color[i]).norm(), 0, 1e-6);
}

}  // namespace
}  // namespace wobble::render
