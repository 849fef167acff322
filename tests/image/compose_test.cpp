// Composing pictures (image/compose.h): pasting a tile lands its pixels at the right place, clipped at the
// edges; fill and blend change exactly their rectangle, blend by the given fraction.
#include <gtest/gtest.h>

#include "image/compose.h"

namespace wobble::image {
namespace {

Image8 solid(int w, int h, Rgb8 c) {
  Image8 image(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < 3; ++k) image.at(x, y, k) = c[k];
  return image;
}

TEST(Compose, PasteCopiesTheTileAndClipsAtTheEdges) {
  Image8 canvas = solid(10, 6, {0, 0, 0});
  Image8 tile(4, 3, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) tile.at(x, y, 0) = std::uint8_t(10 * y + x + 1);
  paste(canvas, tile, 8, 4);  // only its top-left 2 x 2 fits
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 10; ++x) {
      const bool inside = x >= 8 && y >= 4;
      EXPECT_EQ(canvas.at(x, y, 0), inside ? tile.at(x - 8, y - 4, 0) : 0) << x << "," << y;
    }
  paste(canvas, tile, -2, -1);  // its bottom-right part at the top-left corner
  EXPECT_EQ(canvas.at(0, 0, 0), tile.at(2, 1, 0));
  EXPECT_EQ(canvas.at(1, 1, 0), tile.at(3, 2, 0));
  EXPECT_EQ(canvas.at(2, 0, 0), 0);
  EXPECT_THROW(paste(canvas, Image8(2, 2, 4), 0, 0), std::invalid_argument);
}

TEST(Compose, FillAndBlendChangeTheirRectangleOnly) {
  Image8 image = solid(8, 8, {200, 100, 0});
  fill(image, {2, 2, 3, 2}, {1, 2, 3});
  blend(image, {-5, 6, 100, 10}, {0, 0, 0}, 0.25f);  // the bottom two rows, clipped
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const bool filled = x >= 2 && x < 5 && y >= 2 && y < 4, blended = y >= 6;
      const Rgb8 expected = filled ? Rgb8{1, 2, 3} : blended ? Rgb8{150, 75, 0} : Rgb8{200, 100, 0};
      for (int k = 0; k < 3; ++k) EXPECT_EQ(image.at(x, y, k), expected[k]) << x << "," << y << " channel " << k;
    }
}

}  // namespace
}  // namespace wobble::image
