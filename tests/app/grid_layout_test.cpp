// The grid of `wobble compare` (app/compare/grid_layout.h): for 1, 2, 3, 4 and 2 x 3 variants in the default
// 1280 x 720 frame, the arrangement and tile sizes worked out by hand; in odd boxes every size is even (yuv420p) and
// the tiles keep the box's aspect and fit in it.
#include <gtest/gtest.h>

#include <cmath>

#include "app/compare/grid_layout.h"

namespace wobble {
namespace {

void expectGrid(const GridLayout& g, int rows, int cols, int tile_w, int tile_h) {
  EXPECT_EQ(g.rows, rows);
  EXPECT_EQ(g.cols, cols);
  EXPECT_EQ(g.tile_width, tile_w);
  EXPECT_EQ(g.tile_height, tile_h);
  EXPECT_EQ(g.width(), cols * tile_w);
  EXPECT_EQ(g.height(), rows * tile_h);
}

TEST(GridLayout, OneToFourVariantsAndTwoByThreeIn720p) {
  expectGrid(gridLayout(1, 1280, 720), 1, 1, 1280, 720);
  expectGrid(gridLayout(2, 1280, 720), 1, 2, 640, 360);  // side by side: 1280 x 360
  expectGrid(gridLayout(3, 1280, 720), 2, 2, 640, 360);  // one cell empty beats three tiles of 426 x 240
  expectGrid(gridLayout(4, 1280, 720), 2, 2, 640, 360);
  expectGrid(gridLayout(2, 3, 1280, 720), 2, 3, 426, 240);  // 1280 / 3 = 426.7, 426 * 9 / 16 = 239.6 -> 240 even
  expectGrid(gridLayout(3, 2, 1280, 720), 3, 2, 426, 240);  // 720 / 3 = 240 rows, 240 * 16 / 9 = 426.7
  expectGrid(gridLayout(5, 1280, 720), 2, 3, 426, 240);
  expectGrid(gridLayout(2, 1, 1280, 720), 2, 1, 640, 360);
  // Tile positions, row by row.
  const GridLayout g = gridLayout(2, 3, 1280, 720);
  EXPECT_EQ(g.tileX(4), 426);
  EXPECT_EQ(g.tileY(4), 240);
  EXPECT_EQ(g.tileX(2), 852);
  EXPECT_EQ(g.tileY(2), 0);
}

TEST(GridLayout, EvenSizesThatFitAndKeepTheAspect) {
  for (const auto& [w, h] : {std::pair{1001, 563}, {640, 360}, {333, 187}, {1920, 1080}, {129, 73}, {64, 36}})
    for (int rows = 1; rows <= 4; ++rows)
      for (int cols = 1; cols <= 4; ++cols) {
        const GridLayout g = gridLayout(rows, cols, w, h);
        const std::string where = std::to_string(rows) + " x " + std::to_string(cols) + " in " + std::to_string(w) +
                                  " x " + std::to_string(h);
        EXPECT_EQ(g.tile_width % 2, 0) << where;
        EXPECT_EQ(g.tile_height % 2, 0) << where;
        EXPECT_EQ(g.width() % 2, 0) << where;
        EXPECT_EQ(g.height() % 2, 0) << where;
        EXPECT_LE(g.width(), w) << where;
        EXPECT_LE(g.height(), h) << where;
        // On the side that fills the box, under 2 pixels a tile lost: the division's remainder (under one a tile) and
        // the even rounding (at most one a tile).
        EXPECT_TRUE(g.width() > w - 2 * cols || g.height() > h - 2 * rows) << where;
        // The aspect, but for the even rounding (up to 2 pixels each way, which matters on tiny tiles).
        const double aspect = double(w) / h;
        EXPECT_NEAR(double(g.tile_width) / g.tile_height, aspect, (aspect + 1) * 2.0 / g.tile_height) << where;
      }
  EXPECT_THROW(gridLayout(4, 4, 6, 4), std::invalid_argument);  // tiles under 2 x 2
  EXPECT_THROW(gridLayout(0, 1280, 720), std::invalid_argument);
}

}  // namespace
}  // namespace wobble
