// Text through stb_truetype (image/font.h) with the labels' font (font_file.h: DejaVu Sans, which setup.sh
// installs): drawn text changes pixels where it is and nowhere else, its ink lies within the measured width and the
// line, a longer text is wider, colour is the colour asked for, and a missing or non-font file is a clear error.
#include <gtest/gtest.h>

#include <fstream>

#include "image/font.h"
#include "image/font_file.h"
#include "tests/temp_dir.h"

namespace wobble::image {
namespace {

Font labelFont() {
  const auto file = findFontFile();
  if (!file) throw std::runtime_error("DejaVu Sans not found: install fonts-dejavu-core (setup.sh)");
  return Font::load(*file);
}

TEST(Font, FindsDejaVuSans) {
  const auto file = findFontFile();
  ASSERT_TRUE(file) << "install fonts-dejavu-core (setup.sh does)";
  EXPECT_NE(file->filename().string().find("DejaVuSans"), std::string::npos) << *file;
  EXPECT_FALSE(findFontFile("No Such Family 12345", "/nonexistent/font.ttf"));
}

TEST(Font, TextInksItsBoxOnly) {
  const Font font = labelFont();
  const float px = 20;
  const std::string text = "rk4, dt = 1.2e-3";
  const int x0 = 7, y0 = 5, width = font.width(text, px), line = font.lineHeight(px);
  EXPECT_GT(width, int(text.size()) * 5);  // about half an em per character
  EXPECT_LT(width, int(text.size()) * 20);
  EXPECT_GE(line, 20);
  EXPECT_LT(line, 30);
  EXPECT_GT(font.width(text + " s", px), width);

  Image8 image(width + 20, line + 15, 3);  // black
  font.draw(image, x0, y0, text, px, {255, 60, 60});
  int inked = 0, pure = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const int r = image.at(x, y, 0), g = image.at(x, y, 1), b = image.at(x, y, 2);
      if (r == 0 && g == 0 && b == 0) continue;
      ++inked;
      EXPECT_TRUE(x >= x0 && x <= x0 + width && y >= y0 && y < y0 + line)
          << "ink outside the text at " << x << "," << y;
      EXPECT_EQ(g, b);
      EXPECT_GE(r, g);  // the colour blended over black: red leads
      if (r == 255 && g == 60) ++pure;
    }
  EXPECT_GT(inked, 100);
  EXPECT_GT(pure, 20) << "fully covered pixels take the colour itself";
}

TEST(Font, ClipsAtTheImageEdges) {
  // Text hanging over every edge of a small image draws exactly the part of it that a large canvas shows there.
  const Font font = labelFont();
  const auto clippedEqualsCropped = [&](int x, int y, const std::string& text, float px) {
    Image8 image(12, 6, 3);
    font.draw(image, x, y, text, px, {255, 255, 255});
    constexpr int kMargin = 64;
    Image8 canvas(12 + 2 * kMargin, 6 + 2 * kMargin, 3);
    font.draw(canvas, x + kMargin, y + kMargin, text, px, {255, 255, 255});
    int inked = 0, different = 0;
    for (int py = 0; py < 6; ++py)
      for (int px_ = 0; px_ < 12; ++px_)
        for (int c = 0; c < 3; ++c) {
          inked += image.at(px_, py, c) > 0;
          different += image.at(px_, py, c) != canvas.at(px_ + kMargin, py + kMargin, c);
        }
    EXPECT_GT(inked, 0) << text << ": nothing drawn inside the image";
    EXPECT_EQ(different, 0) << text;
  };
  clippedEqualsCropped(-5, -8, "blew up at t = 0.84 s", 14);  // over the left and top edges
  clippedEqualsCropped(6, -8, "WWW", 30);                     // over the top, right and bottom edges
  Image8 grey(4, 4, 1);
  EXPECT_THROW(font.draw(grey, 0, 0, "x", 10, {255, 255, 255}), std::invalid_argument);
}

TEST(Font, MissingOrBrokenFileIsAClearError) {
  test::TempDir dir;
  try {
    Font::load(dir / "none.ttf");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("none.ttf: cannot read"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "fake.ttf") << "not a font at all";
  EXPECT_THROW(Font::load(dir / "fake.ttf"), std::runtime_error);
}

}  // namespace
}  // namespace wobble::image
