// FLIP (image/flip.h) against what its papers state: identical images give 0 everywhere; the colour error is 1
// exactly for pure green against pure blue (the pair that defines its largest distance); black against white gives
// the value the colour pipeline's formula yields from the standard CIELAB values of black and white (no features in
// flat images); among greys it is the largest; the error grows with the width of a blur; HDR-FLIP picks its exposures
// from the reference's brightest and median luminance. The heatmap uses magma's ends.
#include "image/flip.h"

#include <cmath>

#include <gtest/gtest.h>

namespace wobble::image {
namespace {

ImageF flat(int w, int h, float r, float g, float b) {
  ImageF img(w, h, 3);
  for (std::size_t i = 0; i < img.pixels.size(); i += 3)
    img.pixels[i] = r, img.pixels[i + 1] = g, img.pixels[i + 2] = b;
  return img;
}

// A checkerboard of 8-pixel squares, values 0.1 and 0.9 (sRGB-encoded), and the same blurred by a box of radius r.
ImageF checker(int r) {
  ImageF sharp(64, 64, 3), out(64, 64, 3);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c) sharp.at(x, y, c) = ((x / 8 + y / 8) % 2) ? 0.9f : 0.1f;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c) {
        float s = 0;
        int n = 0;
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx) {
            s += sharp.at(std::clamp(x + dx, 0, 63), std::clamp(y + dy, 0, 63), c);
            ++n;
          }
        out.at(x, y, c) = s / float(n);
      }
  return out;
}

TEST(Flip, IdenticalImagesGiveZero) {
  const ImageF a = checker(1);
  for (float e : ldrFlip(a, a).pixels) EXPECT_EQ(e, 0.0f);
  ImageF hdr = flat(16, 16, 0.5f, 2.0f, 8.0f);
  hdr.at(3, 3, 0) = 40;
  for (float e : hdrFlip(hdr, hdr).pixels) EXPECT_EQ(e, 0.0f);
  EXPECT_EQ(flipStats(ldrFlip(a, a)).mean, 0.0);
}

TEST(Flip, GreenAgainstBlueIsTheLargestColourError) {
  for (float e : ldrFlip(flat(8, 8, 0, 1, 0), flat(8, 8, 0, 0, 1)).pixels) EXPECT_NEAR(e, 1.0f, 1e-5f);
}

TEST(Flip, BlackAgainstWhiteFollowsTheColourFormula) {
  // Hunt-adjusted CIELAB (D65) of sRGB green and blue: L*, a*, b* = (87.737, -86.185, 83.181) and
  // (32.303, 79.197, -107.864), chroma times 0.01 L*; HyAB = |dL*| + |d(a*, b*)|. Black and white: dL* = 100.
  const double gL = 87.737, ga = -86.185 * 0.01 * gL, gb = 83.181 * 0.01 * gL;
  const double bL = 32.303, ba = 79.197 * 0.01 * bL, bb = -107.864 * 0.01 * bL;
  const double cmax = std::pow(std::fabs(gL - bL) + std::hypot(ga - ba, gb - bb), 0.7);
  const double e = std::pow(100.0, 0.7);
  const double expected = e < 0.4 * cmax ? 0.95 * e / (0.4 * cmax) : 0.95 + (e - 0.4 * cmax) / (0.6 * cmax) * 0.05;
  const ImageF black = flat(8, 8, 0, 0, 0), white = flat(8, 8, 1, 1, 1);
  const FlipStats s = flipStats(ldrFlip(black, white));
  EXPECT_NEAR(s.mean, expected, 1e-3) << "expected " << expected;
  EXPECT_NEAR(s.min, s.max, 1e-6);  // flat images: the same everywhere
  // The largest error between greys, and symmetric.
  for (float g : {0.2f, 0.5f, 0.8f}) {
    EXPECT_LT(flipStats(ldrFlip(black, flat(8, 8, g, g, g))).mean, s.mean);
    EXPECT_LT(flipStats(ldrFlip(flat(8, 8, g, g, g), white)).mean, s.mean);
  }
  EXPECT_NEAR(flipStats(ldrFlip(white, black)).mean, s.mean, 1e-6);
}

TEST(Flip, ErrorGrowsWithTheWidthOfABlur) {
  const ImageF sharp = checker(0);
  double previous = 0;
  for (int r = 1; r <= 4; ++r) {
    const double mean = flipStats(ldrFlip(sharp, checker(r))).mean;
    EXPECT_GT(mean, previous) << "box blur of radius " << r;
    previous = mean;
  }
  EXPECT_LE(previous, 1.0);
}

TEST(Flip, HdrExposuresComeFromTheReference) {
  // A uniform luminance of 1: the start and stop put 1 at 0.85 of the tone curve, two exposures; 4x brighter: two
  // stops earlier.
  const FlipExposures one = hdrFlipExposures(flat(4, 4, 1, 1, 1)), four = hdrFlipExposures(flat(4, 4, 4, 4, 4));
  EXPECT_NEAR(one.start, one.stop, 1e-9);
  EXPECT_EQ(one.count, 2);
  EXPECT_NEAR(one.start - four.start, 2.0, 1e-6);
  // The tone curve at 2^start maps 1 to 0.85: start is log2 of the curve's inverse at 0.85.
  const double x = std::exp2(one.start);
  const double y = (0.6 * 0.6 * 2.51 * x * x + 0.6 * 0.03 * x) / (0.6 * 0.6 * 2.43 * x * x + 0.6 * 0.59 * x + 0.14);
  EXPECT_NEAR(y, 0.85, 1e-6);
  // A brighter spot in a dim image: more exposures, starting darker.
  ImageF spot = flat(16, 16, 0.1f, 0.1f, 0.1f);
  spot.at(2, 2, 0) = spot.at(2, 2, 1) = spot.at(2, 2, 2) = 100;
  const FlipExposures e = hdrFlipExposures(spot);
  EXPECT_NEAR(e.stop - e.start, std::log2(1000.0), 1e-4);
  EXPECT_EQ(e.count, int(std::ceil(std::log2(1000.0))));
  // A difference hidden by the tone curve at one exposure shows at another.
  ImageF test = spot;
  test.at(10, 10, 1) = 0.15f;
  EXPECT_GT(hdrFlip(spot, test).at(10, 10), 0.1f);
}

TEST(Flip, PooledValuesAndHeatmap) {
  ImageF map(4, 1, 1);
  map.pixels = {0.1f, 0.2f, 0.3f, 0.4f};
  const FlipStats s = flipStats(map);
  EXPECT_NEAR(s.mean, 0.25, 1e-7);
  EXPECT_NEAR(s.min, 0.1, 1e-7);
  EXPECT_NEAR(s.max, 0.4, 1e-7);
  // Running sums 0.1, 0.3, 0.6, 1.0 of 1.0: half is reached at 0.3 (index 2), the value between it and the next.
  EXPECT_NEAR(s.weighted_median, 0.35, 1e-7);
  EXPECT_NEAR(flipPercentile(map, 50), 0.25, 1e-7);
  EXPECT_NEAR(flipPercentile(map, 100), 0.4, 1e-7);
  ImageF ends(2, 1, 1);
  ends.pixels = {0.0f, 1.0f};
  const Image8 heat = magmaHeatmap(ends);
  EXPECT_EQ(heat.at(0, 0, 0), 0);  // magma starts near black (0.001462, 0.000466, 0.013866)...
  EXPECT_EQ(heat.at(0, 0, 2), 4);
  EXPECT_EQ(heat.at(1, 0, 0), 252);  // ...and ends pale yellow (0.987053, 0.991438, 0.749504)
  EXPECT_EQ(heat.at(1, 0, 1), 253);
  EXPECT_EQ(heat.at(1, 0, 2), 191);
  EXPECT_THROW(ldrFlip(flat(4, 4, 0, 0, 0), flat(5, 4, 0, 0, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace wobble::image
