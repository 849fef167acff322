// imageError: RMSE of display values and relative MSE, over the frame and its worst tile, against hand-computed values.
#include "image/image_error.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace wobble::image {
namespace {

// The value a linear colour channel shows with tone map `tm`: tone curve, then the sRGB encoding.
double display(float linear, const ToneMap& tm) { return linearToSrgb(tm.apply(linear)); }

std::vector<Color> gradient(int w, int h) {
  std::vector<Color> image;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) image.emplace_back(0.05f + 0.01f * x, 0.3f + 0.004f * y, 0.02f * ((x + y) % 9));
  return image;
}

TEST(ImageError, AnImageAgainstItselfIsZero) {
  const std::vector<Color> image = gradient(40, 24);
  const ImageError e = imageError(40, 24, image, image);
  EXPECT_EQ(e.rmse, 0);
  EXPECT_EQ(e.relmse, 0);
  EXPECT_EQ(e.worst_tile_rmse, 0);
  EXPECT_EQ(e.worst_tile_relmse, 0);
}

// With the Clamp curve and no exposure, display = sRGB encoding of the linear value: build both images from display
// values that differ by a constant, and the RMSE is that constant.
TEST(ImageError, ConstantDisplayOffsetIsTheRmse) {
  const int w = 20, h = 10;
  const double offset = 0.05;
  ToneMap clamp;
  clamp.curve = ToneMap::Curve::Clamp;
  std::vector<Color> image, reference;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Color r, i;
      for (int c = 0; c < 3; ++c) {
        const float shown = 0.1f + 0.03f * x + 0.02f * y + 0.05f * c;  // in [0.1, 0.87]
        r[c] = srgbToLinear(shown);
        i[c] = srgbToLinear(shown + float(offset));
      }
      reference.push_back(r), image.push_back(i);
    }
  const ImageError e = imageError(w, h, image, reference, clamp);
  EXPECT_NEAR(e.rmse, offset, 1e-5);
  EXPECT_NEAR(e.worst_tile_rmse, offset, 1e-5);  // the whole image is one tile
  // The same images with a filmic curve: compared after the curve, computed channel by channel here.
  const ToneMap aces;
  double sq = 0;
  for (std::size_t p = 0; p < image.size(); ++p)
    for (int c = 0; c < 3; ++c) sq += std::pow(display(image[p][c], aces) - display(reference[p][c], aces), 2);
  EXPECT_NEAR(imageError(w, h, image, reference, aces).rmse, std::sqrt(sq / (3.0 * w * h)), 1e-6);
  // Exposure counts: one stop up brightens both, changing the differences.
  ToneMap brighter;
  brighter.exposure = 1;
  EXPECT_NE(imageError(w, h, image, reference, brighter).rmse, imageError(w, h, image, reference, aces).rmse);
}

// relMSE = mean over all channels of (x - r)^2 / (r^2 + 0.01), on a 2 x 2 image worked by hand.
TEST(ImageError, RelativeMseFollowsItsFormula) {
  const std::vector<Color> reference{{0.1f, 0.1f, 0.1f}, {0.1f, 0.1f, 0.1f}, {0, 0, 0}, {1, 1, 1}};
  std::vector<Color> image = reference;
  image[0].x() = 0.2f;  // (0.1)^2 / (0.01 + 0.01) = 0.5
  image[1].z() = 0.3f;  // (0.2)^2 / 0.02 = 2
  image[2].y() = 0.1f;  // (0.1)^2 / (0 + 0.01) = 1
  image[3].x() = 0.0f;  // 1 / (1 + 0.01) = 0.990099...
  const double expected = (0.5 + 2 + 1 + 1 / 1.01) / 12;
  const ImageError e = imageError(2, 2, image, reference);
  EXPECT_NEAR(e.relmse, expected, 1e-6);
  EXPECT_NEAR(e.worst_tile_relmse, expected, 1e-6);
  // Symmetric in sign, not in which image is the reference.
  std::vector<Color> below = reference;
  below[0].x() = 0.0f;  // also 0.1 away from 0.1
  EXPECT_NEAR(imageError(2, 2, below, reference).relmse, 0.5 / 12, 1e-6);
  EXPECT_GT(imageError(2, 2, reference, image).relmse, 0);
}

// A 64 x 64 image cut into four 32 x 32 tiles, with an error in one tile only: that tile holds all the squared error
// on a quarter of the values, so its RMSE is sqrt(4) times the frame's and its relMSE 4 times.
TEST(ImageError, WorstTileIsWhereTheErrorIs) {
  const int w = 64, h = 64;
  const std::vector<Color> reference = gradient(w, h);
  std::vector<Color> image = reference;
  for (int y = 32; y < 64; ++y)
    for (int x = 0; x < 32; ++x) image[std::size_t(y) * w + x] += Color(0.1f, 0.0f, 0.05f * (x % 3));
  const ImageError e = imageError(w, h, image, reference);
  EXPECT_GT(e.rmse, 0.01);
  EXPECT_NEAR(e.worst_tile_rmse, 2 * e.rmse, 1e-9);
  EXPECT_NEAR(e.worst_tile_relmse, 4 * e.relmse, 1e-9);
  // With 16 x 16 tiles the error fills four of the sixteen: the worst is at least as bad (the error is not uniform).
  const ImageError fine = imageError(w, h, image, reference, {}, 16);
  EXPECT_NEAR(fine.rmse, e.rmse, 1e-12);
  EXPECT_GE(fine.worst_tile_rmse, e.worst_tile_rmse - 1e-9);
}

// Tiles cut by the right edge count when at least half a tile wide.
TEST(ImageError, EdgeSliversCountFromHalfATile) {
  const auto rightEdgeError = [](int w, int h) {
    const std::vector<Color> reference = gradient(w, h);
    std::vector<Color> image = reference;
    for (int y = 0; y < h; ++y)
      for (int x = 32; x < w; ++x) image[std::size_t(y) * w + x].y() += 0.1f;
    return imageError(w, h, image, reference);
  };
  // 48 wide: the second column of tiles is 16 wide (half a tile), holds all the error on 1/3 of the values.
  const ImageError half = rightEdgeError(48, 32);
  EXPECT_NEAR(half.worst_tile_rmse, std::sqrt(3.0) * half.rmse, 1e-9);
  // 40 wide: an 8-pixel sliver, ignored, and the full tile has no error.
  const ImageError sliver = rightEdgeError(40, 32);
  EXPECT_GT(sliver.rmse, 0);
  EXPECT_EQ(sliver.worst_tile_rmse, 0);
  EXPECT_EQ(sliver.worst_tile_relmse, 0);
  // An image smaller than one tile is its own tile.
  std::vector<Color> small = gradient(10, 6), shifted = small;
  shifted[7].x() += 0.2f;
  const ImageError tiny = imageError(10, 6, shifted, small);
  EXPECT_NEAR(tiny.worst_tile_rmse, tiny.rmse, 1e-12);
  EXPECT_GT(tiny.rmse, 0);
}

TEST(ImageError, RejectsMismatchedSizes) {
  const std::vector<Color> a = gradient(4, 4), b = gradient(4, 3);
  EXPECT_THROW(imageError(4, 4, a, b), std::invalid_argument);
  EXPECT_THROW(imageError(4, 3, a, b), std::invalid_argument);
  EXPECT_THROW(imageError(0, 0, {}, {}), std::invalid_argument);
  EXPECT_THROW(imageError(4, 4, a, a, {}, 0), std::invalid_argument);
}

}  // namespace
}  // namespace wobble::image
