// The CIE76 colour difference (image/color_difference.h) against published L*a*b* values of the sRGB primaries
// (D65; Lindbloom's calculator, CIE 15:2004 formulas) and differences worked by hand: white against black is 100, a
// picture against itself 0, and a difference in half the pixels halves the mean.
#include <gtest/gtest.h>

#include "image/color_difference.h"

namespace wobble::image {
namespace {

Image8 filled(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Image8 image(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      image.at(x, y, 0) = r;
      image.at(x, y, 1) = g;
      image.at(x, y, 2) = b;
    }
  return image;
}

TEST(Cie76, LabOfTheSrgbPrimariesMatchesPublishedValues) {
  const auto expect = [](Eigen::Vector3d lab, double l, double a, double b) {
    EXPECT_NEAR(lab.x(), l, 0.01);
    EXPECT_NEAR(lab.y(), a, 0.01);
    EXPECT_NEAR(lab.z(), b, 0.01);
  };
  expect(srgb8ToLab(255, 0, 0), 53.2408, 80.0925, 67.2032);
  expect(srgb8ToLab(0, 255, 0), 87.7347, -86.1827, 83.1793);
  expect(srgb8ToLab(0, 0, 255), 32.2970, 79.1875, -107.8602);
  expect(srgb8ToLab(255, 255, 255), 100, 0, 0);
  expect(srgb8ToLab(0, 0, 0), 0, 0, 0);
}

TEST(Cie76, DifferencesWorkedByHand) {
  const Image8 white = filled(4, 2, 255, 255, 255), black = filled(4, 2, 0, 0, 0);
  EXPECT_NEAR(cie76(white, black).mean, 100, 0.01);
  EXPECT_EQ(cie76(white, white).mean, 0);
  Image8 half = white;  // the left half black: 4 of 8 pixels 100 apart
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x)
      for (int c = 0; c < 3; ++c) half.at(x, y, c) = 0;
  const ColorDifference d = cie76(half, white);
  EXPECT_NEAR(d.mean, 50, 0.01);
  EXPECT_NEAR(d.max, 100, 0.01);
  EXPECT_NEAR(d.p95, 100, 0.01);
  // Red against green: the distance between their published L*a*b* values.
  EXPECT_NEAR(cie76(filled(1, 1, 255, 0, 0), filled(1, 1, 0, 255, 0)).mean,
              (Eigen::Vector3d(53.2408, 80.0925, 67.2032) - Eigen::Vector3d(87.7347, -86.1827, 83.1793)).norm(), 0.02);
  EXPECT_THROW(cie76(white, filled(2, 2, 0, 0, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace wobble::image
