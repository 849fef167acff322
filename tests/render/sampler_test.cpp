// Sampler: Sobol points and their Owen-scrambled, shuffled per-pixel copies are (0, m, 2)-nets, differ per pixel and
// slot, repeat per seed, and integrate smooth functions faster than independent random numbers.
#include "render/sampler.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace wobble::render {
namespace {

// The top `bits` bits of a 32-bit fraction: the index of its interval [k / 2^bits, (k + 1) / 2^bits).
std::uint32_t topBits(std::uint32_t fraction, int bits) { return bits == 0 ? 0 : fraction >> (32 - bits); }

// The same for a float in [0, 1) (exact: the sampler's floats have 24 significant bits and bits <= 24).
std::uint32_t interval(float value, int bits) {
  const double scaled = std::ldexp(double(value), bits);
  return static_cast<std::uint32_t>(std::floor(scaled));
}

// Whether 2^m points (x, y), given as interval indices per resolution, put exactly one point in every elementary
// interval of area 2^-m: for every split a + b = m, the 2^a x 2^b grid has each cell hit once. On failure the message
// names the first split and cell that is wrong.
::testing::AssertionResult isNet(int m, const std::function<std::uint32_t(std::uint32_t, int)>& x_cell,
                                 const std::function<std::uint32_t(std::uint32_t, int)>& y_cell) {
  const std::uint32_t n = 1u << m;
  for (int a = 0; a <= m; ++a) {
    const int b = m - a;
    std::vector<int> count(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t cx = x_cell(i, a), cy = y_cell(i, b);
      if (cx >= (1u << a) || cy >= (1u << b))
        return ::testing::AssertionFailure() << "point " << i << " outside [0, 1)^2";
      ++count[(cx << b) | cy];
    }
    for (std::uint32_t c = 0; c < n; ++c)
      if (count[c] != 1)
        return ::testing::AssertionFailure() << "m = " << m << ", split " << a << " + " << b << ": cell (" << (c >> b)
                                             << ", " << (c & ((1u << b) - 1)) << ") holds " << count[c] << " points";
  }
  return ::testing::AssertionSuccess();
}

TEST(Sampler, RawSobolDimensionsZeroAndOneFormNets) {
  for (int m = 4; m <= 8; ++m) {
    EXPECT_TRUE(isNet(
        m, [](std::uint32_t i, int a) { return topBits(sobol::dimension0(i), a); },
        [](std::uint32_t i, int b) { return topBits(sobol::dimension1(i), b); }));
    // The same through toUnitFloat, the conversion the sampler uses.
    EXPECT_TRUE(isNet(
        m, [](std::uint32_t i, int a) { return interval(sobol::toUnitFloat(sobol::dimension0(i)), a); },
        [](std::uint32_t i, int b) { return interval(sobol::toUnitFloat(sobol::dimension1(i)), b); }));
  }
}

TEST(Sampler, DimensionOneIsTheXorOfItsDirectionNumbers) {
  // Sobol's definition for the polynomial x + 1 (m_1 = 1): v_0 = 1/2, v_k = v_{k-1} ^ v_{k-1} / 2, and point i is the
  // XOR of the v_k of i's set bits.
  std::uint32_t v[32];
  v[0] = 0x80000000u;
  for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
  std::uint64_t state = 7;
  for (int n = 0; n < 20000; ++n) {
    state = state * 6364136223846793005u + 1442695040888963407u;
    const std::uint32_t i = n < 4096 ? std::uint32_t(n) : std::uint32_t(state >> 32);
    std::uint32_t expected = 0;
    for (int k = 0; k < 32; ++k)
      if (i >> k & 1) expected ^= v[k];
    ASSERT_EQ(sobol::dimension1(i), expected) << "index " << i;
  }
}

TEST(Sampler, OwenScramblingKeepsTheNet) {
  for (const auto& [seed_x, seed_y] : {std::pair<std::uint32_t, std::uint32_t>{1u, 2u},
                                       {0xDEADBEEFu, 0x12345678u},
                                       {0u, 0xFFFFFFFFu},
                                       {sobol::hash(7, 8), sobol::hash(9, 10)}}) {
    for (int m = 4; m <= 8; ++m)
      EXPECT_TRUE(isNet(
          m,
          [sx = seed_x](std::uint32_t i, int a) { return topBits(sobol::owenScramble(sobol::dimension0(i), sx), a); },
          [sy = seed_y](std::uint32_t i, int b) { return topBits(sobol::owenScramble(sobol::dimension1(i), sy), b); }))
          << "seeds " << seed_x << ", " << seed_y;
    // And it does change the points (it is not the identity).
    int moved = 0;
    for (std::uint32_t i = 0; i < 16; ++i)
      moved += sobol::owenScramble(sobol::dimension0(i), seed_x) != sobol::dimension0(i);
    EXPECT_GT(moved, 0) << "seed " << seed_x;
  }
}

TEST(Sampler, PixelSamplerSobolSlotsAreNetsIn2DAndStratifiedIn1D) {
  for (const std::uint64_t pixel : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{917}, std::uint64_t{1} << 40})
    for (const std::uint32_t frame : {0u, 3u, 1000u})
      for (const int slot : {0, 1, 2, 7, 31, 40}) {  // 40: beyond the cached slots
        const PixelSampler sampler(SamplerKind::Sobol, pixel, frame);
        for (int m = 4; m <= 8; ++m) {
          EXPECT_TRUE(isNet(
              m, [&](std::uint32_t i, int a) { return interval(sampler.get2D(i, slot).x(), a); },
              [&](std::uint32_t i, int b) { return interval(sampler.get2D(i, slot).y(), b); }))
              << "pixel " << pixel << " frame " << frame << " slot " << slot;
          // 1D: one point in each interval [k / 2^m, (k + 1) / 2^m).
          std::vector<int> count(1u << m, 0);
          for (std::uint32_t i = 0; i < (1u << m); ++i) {
            const float v = sampler.get1D(i, slot);
            ASSERT_GE(v, 0.0f);
            ASSERT_LT(v, 1.0f);
            ++count[interval(v, m)];
          }
          for (std::size_t k = 0; k < count.size(); ++k)
            EXPECT_EQ(count[k], 1) << "m " << m << " interval " << k << " pixel " << pixel << " slot " << slot;
        }
      }
}

TEST(Sampler, IndependentPointsAreNotNets) {
  // The check above can fail: 256 independent uniform points are a (0, 8, 2)-net with negligible probability (the
  // 1D projection alone: 256! / 256^256, about 1e-110).
  const PixelSampler sampler(SamplerKind::Independent, 917, 3);
  EXPECT_FALSE(isNet(
      8, [&](std::uint32_t i, int a) { return interval(sampler.get2D(i, 2).x(), a); },
      [&](std::uint32_t i, int b) { return interval(sampler.get2D(i, 2).y(), b); }));
}

// Pearson's chi-square of `points` over a 16 x 16 grid of the unit square (255 degrees of freedom: mean 255, standard
// deviation 22.6).
double chiSquare16(const std::vector<Eigen::Vector2f>& points) {
  std::vector<int> count(256, 0);
  for (const Eigen::Vector2f& p : points) ++count[interval(p.x(), 4) * 16 + interval(p.y(), 4)];
  const double expected = double(points.size()) / 256;
  double chi2 = 0;
  for (const int c : count) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

TEST(Sampler, IndependentPairsAreUniformAndUncorrelated) {
  // 64 pixels x 64 samples x 8 slots: 32 768 points, 128 a cell. Each pair is uniform on the square only if its two
  // numbers are uniform and independent: a slot's x and y, x of neighbouring slots, x of consecutive samples, x of
  // neighbouring pixels. The seeds are fixed, so this is deterministic; a sound hash stays near 255, and the bound
  // (255 + 6 standard deviations) fails a coordinate copied, offset or correlated with another.
  std::vector<Eigen::Vector2f> within, slots, samples, pixels;
  for (std::uint64_t pixel = 0; pixel < 64; ++pixel) {
    const PixelSampler s(SamplerKind::Independent, pixel, 5), next(SamplerKind::Independent, pixel + 1, 5);
    for (std::uint32_t i = 0; i < 64; ++i)
      for (int slot = 0; slot < 8; ++slot) {
        within.push_back(s.get2D(i, slot));
        slots.emplace_back(s.get2D(i, slot).x(), s.get2D(i, slot + 1).x());
        samples.emplace_back(s.get2D(i, slot).x(), s.get2D(i + 1, slot).x());
        pixels.emplace_back(s.get2D(i, slot).x(), next.get2D(i, slot).x());
        EXPECT_EQ(s.get1D(i, slot), s.get2D(i, slot).x());
      }
  }
  EXPECT_LT(chiSquare16(within), 391);
  EXPECT_LT(chiSquare16(slots), 391);
  EXPECT_LT(chiSquare16(samples), 391);
  EXPECT_LT(chiSquare16(pixels), 391);
  // And the test can fail: the diagonal (x, x) leaves 240 of the 256 cells empty.
  std::vector<Eigen::Vector2f> diagonal;
  for (const Eigen::Vector2f& p : within) diagonal.emplace_back(p.x(), p.x());
  EXPECT_GT(chiSquare16(diagonal), 391);
}

std::vector<Eigen::Vector2f> first16(const PixelSampler& sampler, int slot) {
  std::vector<Eigen::Vector2f> points;
  for (std::uint32_t i = 0; i < 16; ++i) points.push_back(sampler.get2D(i, slot));
  return points;
}

TEST(Sampler, ScramblesDifferPerPixelFrameAndSlot) {
  const PixelSampler a(SamplerKind::Sobol, 10, 0), b(SamplerKind::Sobol, 11, 0), c(SamplerKind::Sobol, 10, 1);
  EXPECT_NE(first16(a, 2), first16(b, 2));  // neighbouring pixels
  EXPECT_NE(first16(a, 2), first16(c, 2));  // next frame
  EXPECT_NE(first16(a, 2), first16(a, 3));  // another slot
  EXPECT_NE(first16(a, 0), first16(a, 1));
  EXPECT_NE(first16(a, 33), first16(a, 34));  // uncached slots too
  // Not just a permutation of the same points either: the sets differ.
  std::vector<float> xa, xb;
  for (const auto& p : first16(a, 2)) xa.push_back(p.x());
  for (const auto& p : first16(b, 2)) xb.push_back(p.x());
  std::sort(xa.begin(), xa.end());
  std::sort(xb.begin(), xb.end());
  EXPECT_NE(xa, xb);
  // Independent samples differ per pixel and slot as well.
  const PixelSampler ia(SamplerKind::Independent, 10, 0), ib(SamplerKind::Independent, 11, 0);
  EXPECT_NE(first16(ia, 2), first16(ib, 2));
  EXPECT_NE(first16(ia, 2), first16(ia, 3));
}

TEST(Sampler, SameSeedRepeatsWhateverTheOrderOfQueries) {
  constexpr int kSamples = 64, kSlots = 40;  // slots beyond kCachedSlots too
  for (const SamplerKind kind : {SamplerKind::Sobol, SamplerKind::Independent}) {
    // Sample-major, ascending.
    std::vector<Eigen::Vector2f> forward(kSamples * kSlots);
    std::vector<float> forward1(kSamples * kSlots);
    {
      const PixelSampler s(kind, 4242, 17);
      for (int i = 0; i < kSamples; ++i)
        for (int slot = 0; slot < kSlots; ++slot) {
          forward[i * kSlots + slot] = s.get2D(i, slot);
          forward1[i * kSlots + slot] = s.get1D(i, slot);
        }
    }
    // A second sampler of the same pixel and frame, slot-major, descending, 1D before 2D.
    const PixelSampler s(kind, 4242, 17);
    for (int slot = kSlots - 1; slot >= 0; --slot)
      for (int i = kSamples - 1; i >= 0; --i) {
        EXPECT_EQ(s.get1D(i, slot), forward1[i * kSlots + slot])
            << toString(kind) << " sample " << i << " slot " << slot;
        EXPECT_EQ(s.get2D(i, slot), forward[i * kSlots + slot])
            << toString(kind) << " sample " << i << " slot " << slot;
      }
  }
}

TEST(Sampler, IndependentValuesAreUniformInUnitInterval) {
  double sum = 0;
  long n = 0;
  for (std::uint64_t pixel = 0; pixel < 64; ++pixel) {
    const PixelSampler s(SamplerKind::Independent, pixel, 5);
    for (std::uint32_t i = 0; i < 256; ++i)
      for (int slot = 0; slot < 4; ++slot) {
        const Eigen::Vector2f p = s.get2D(i, slot);
        const float q = s.get1D(i, slot + 4);
        for (const float v : {p.x(), p.y(), q}) {
          ASSERT_GE(v, 0.0f);
          ASSERT_LT(v, 1.0f);
          sum += v, ++n;
        }
      }
  }
  // Uniform on [0, 1): mean 1/2, standard deviation 1 / sqrt(12); four standard errors of the mean.
  const double standard_error = 1.0 / std::sqrt(12.0 * double(n));
  EXPECT_NEAR(sum / double(n), 0.5, 4 * standard_error);
}

// Least-squares slope of log(error) against log(n).
double logLogSlope(const std::vector<double>& n, const std::vector<double>& error) {
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n.size(); ++i) mx += std::log(n[i]), my += std::log(error[i]);
  mx /= double(n.size()), my /= double(n.size());
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const double dx = std::log(n[i]) - mx;
    sxy += dx * (std::log(error[i]) - my), sxx += dx * dx;
  }
  return sxy / sxx;
}

// RMS error over `pixels` independent replicas (pixels) of the n-sample estimate of the integral of
// f(x, y) = x y e^x over [0, 1]^2, which is (integral of x e^x) (integral of y) = 1 * 1/2.
double rmsError(SamplerKind kind, std::uint32_t n, int pixels) {
  constexpr double kExact = 0.5;
  double sq = 0;
  for (int p = 0; p < pixels; ++p) {
    const PixelSampler sampler(kind, std::uint64_t(p) * 7919 + 3, 2);
    double sum = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      const Eigen::Vector2f u = sampler.get2D(i, 5);
      sum += double(u.x()) * u.y() * std::exp(double(u.x()));
    }
    const double e = sum / double(n) - kExact;
    sq += e * e;
  }
  return std::sqrt(sq / pixels);
}

TEST(Sampler, SobolConvergesFasterThanIndependentOnASmoothIntegrand) {
  constexpr int kPixels = 256;
  const std::vector<double> counts{16, 64, 256, 1024};
  std::vector<double> sobol_error, independent_error;
  for (const double n : counts) {
    sobol_error.push_back(rmsError(SamplerKind::Sobol, std::uint32_t(n), kPixels));
    independent_error.push_back(rmsError(SamplerKind::Independent, std::uint32_t(n), kPixels));
  }
  const double sobol_slope = logLogSlope(counts, sobol_error);
  const double independent_slope = logLogSlope(counts, independent_error);
  // Owen-scrambled nets: about n^-1.5 on smooth integrands; independent samples: n^-0.5.
  EXPECT_LT(sobol_slope, -0.75);
  EXPECT_GT(independent_slope, -0.65);
  EXPECT_LT(independent_slope, -0.35);
  // And at every count the nets are better.
  for (std::size_t k = 0; k < counts.size(); ++k)
    EXPECT_LT(sobol_error[k], independent_error[k]) << "n = " << counts[k];
}

}  // namespace
}  // namespace wobble::render
