// What a tile of `wobble compare` shows frame by frame (app/compare/tile_label.h): the variant's own frames while its
// run lasts, then its last frame frozen with a red "blew up at t = ... s (step ...)" from the first frame it did not
// reach; an orange mark from the first frame over the strain bound; nothing (0) when the run reached no frame of
// the range. And the label as pixels: drawn where its box is, nowhere else, the status in its colour.
#include <gtest/gtest.h>

#include "app/compare/tile_label.h"
#include "image/font_file.h"

namespace wobble {
namespace {

TEST(TileLabel, BlownUpVariantIsFrozenFromTheFirstFrameItDidNotReach) {
  VariantTrack t;
  t.first_frame = 1;
  t.last_frame = 25;  // the run wrote frames 1..25, then blew up at t = 0.84 s, step 700
  t.blow_up_time = 0.84;
  t.blow_up_step = 700;
  for (int k = 1; k <= 25; ++k) {
    const TileView v = tileView(t, k, (k - 1) / 30.0);
    EXPECT_EQ(v.picture, k);
    EXPECT_FALSE(v.frozen);
    EXPECT_EQ(v.color, (image::Rgb8{255, 255, 255}));
  }
  EXPECT_EQ(tileView(t, 25, 0.8).status, "t = 0.80 s");
  for (int k : {26, 27, 300}) {
    const TileView v = tileView(t, k, (k - 1) / 30.0);
    EXPECT_EQ(v.picture, 25) << k;
    EXPECT_TRUE(v.frozen);
    EXPECT_EQ(v.color, kBlewUpColor);
    EXPECT_EQ(v.status, "blew up at t = 0.84 s (step 700)");
  }
  t.first_frame = 30;  // --frames 30:60 and it blew up before: nothing to show
  EXPECT_EQ(tileView(t, 30, 1).picture, 0);
  EXPECT_EQ(tileView(t, 30, 1).color, kBlewUpColor);
}

TEST(TileLabel, LostShapeIsMarkedFromItsFrame) {
  VariantTrack t;
  t.last_frame = 300;
  t.lost_shape_frame = 40;
  t.lost_shape_time = 1.3;
  t.lost_shape_strain = 1.98;
  t.strain_bound = 0.5;
  EXPECT_EQ(tileView(t, 39, 1.27).color, (image::Rgb8{255, 255, 255}));
  const TileView v = tileView(t, 40, 1.3);
  EXPECT_EQ(v.picture, 40);
  EXPECT_FALSE(v.frozen);
  EXPECT_EQ(v.color, kLostShapeColor);
  EXPECT_EQ(v.status, "t = 1.30 s, lost its shape at 1.30 s (strain 1.98 > 0.5)");
  EXPECT_EQ(tileView(t, 300, 9.97).color, kLostShapeColor);
  EXPECT_EQ(tileView(t, 300, 9.97).status, "t = 9.97 s, lost its shape at 1.30 s (strain 1.98 > 0.5)");
}

TEST(TileLabel, NumbersAsInReports) {
  EXPECT_EQ(shortNumber(1.2e-3), "1.2e-3");
  EXPECT_EQ(shortNumber(0.001), "1e-3");
  EXPECT_EQ(shortNumber(5e4), "5e4");
  EXPECT_EQ(shortNumber(1e5), "1e5");
  EXPECT_EQ(shortNumber(1400), "1400");
  EXPECT_EQ(shortNumber(1.0 / 30), "0.0333");
  EXPECT_EQ(shortNumber(-2.5e-6), "-2.5e-6");
  EXPECT_EQ(shortNumber(0), "0");
  EXPECT_EQ(labelSeconds(0.8424), "0.84");
  EXPECT_EQ(labelSeconds(12.3), "12.30");
  EXPECT_EQ(labelSeconds(0.0036), "0.0036");
  EXPECT_EQ(labelSeconds(0), "0.00");
}

TEST(TileLabel, LabelIsDrawnInItsBoxInItsColours) {
  const auto file = image::findFontFile();
  ASSERT_TRUE(file) << "install fonts-dejavu-core (setup.sh does)";
  const image::Font font = image::Font::load(*file);
  image::Image8 tile(320, 180, 3);
  for (auto& v : tile.pixels) v = 128;  // a grey picture
  const image::Image8 before = tile;
  VariantTrack t;
  t.last_frame = 5;
  t.blow_up_time = 0.2;
  t.blow_up_step = 100;
  const TileView view = tileView(t, 9, 0.3);
  const std::string title = "explicit-euler, dt = 2e-3";
  drawLabel(tile, font, title, view);

  const float px = labelPixels(tile.height);
  const int line = font.lineHeight(px);
  const int box_w = std::max(font.width(title, px), font.width(view.status, px)) + 2 * std::max(2, int(px / 4));
  const int box_h = 2 * line + 2 * std::max(2, int(px / 4));
  int changed = 0, white = 0, red = 0;
  for (int y = 0; y < tile.height; ++y)
    for (int x = 0; x < tile.width; ++x) {
      const bool moved = tile.at(x, y, 0) != before.at(x, y, 0) || tile.at(x, y, 1) != before.at(x, y, 1);
      if (x >= box_w || y >= box_h) {
        EXPECT_FALSE(moved) << "changed outside the label at " << x << "," << y;
        continue;
      }
      changed += moved;
      const int r = tile.at(x, y, 0), g = tile.at(x, y, 1);
      if (r > 200 && g > 200 && y < box_h / 2 + 2) ++white;  // the title, on the first line
      if (r > 180 && g < 100 && y > line / 2) ++red;         // the status, on the second
    }
  EXPECT_EQ(changed, box_w * box_h) << "the box is shaded all over";
  EXPECT_GT(white, 30);
  EXPECT_GT(red, 30);
}

}  // namespace
}  // namespace wobble
