// Textures: texel lookup at texel centres, bilinear filtering, wrap modes, sRGB decoding, files, procedurals.
#include "render/image_texture.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "image/png_io.h"
#include "tests/render/test_util.h"

namespace wobble::render {
namespace {

// 4 x 2 texels, each a different colour: texel (x, y) = (x / 4, y / 2, 0.5).
ImageTexture madeUp(Wrap wrap) {
  std::vector<Color> texels;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) texels.emplace_back(x / 4.0f, y / 2.0f, 0.5f);
  return ImageTexture(4, 2, texels, wrap);
}

// UV of the centre of texel (x, y), row 0 at the top (v up).
Eigen::Vector2f centre(int x, int y, int w = 4, int h = 2) { return {(x + 0.5f) / w, 1.0f - (y + 0.5f) / h}; }

TEST(ImageTexture, TexelColourComesBackAtItsUv) {
  const ImageTexture t = madeUp(Wrap::Clamp);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      const Color c = t.eval(centre(x, y));
      EXPECT_NEAR((c - Color(x / 4.0f, y / 2.0f, 0.5f)).norm(), 0, 1e-6) << x << "," << y;
    }
  // v = 1 is the top row of the image (OBJ convention).
  EXPECT_NEAR(t.eval({0.125f, 0.75f}).y(), 0.0f, 1e-6);
  EXPECT_NEAR(t.eval({0.125f, 0.25f}).y(), 0.5f, 1e-6);
}

TEST(ImageTexture, BilinearHalfwayBetweenTwoTexelsIsTheirMean) {
  const ImageTexture t = madeUp(Wrap::Clamp);
  // Between texels (1, 0) and (2, 0) horizontally.
  const Color h = t.eval({0.5f, centre(1, 0).y()});
  EXPECT_NEAR(h.x(), (1 / 4.0f + 2 / 4.0f) / 2, 1e-6);
  EXPECT_NEAR(h.y(), 0, 1e-6);
  // Between texels (3, 0) and (3, 1) vertically.
  const Color v = t.eval({centre(3, 0).x(), 0.5f});
  EXPECT_NEAR(v.x(), 0.75f, 1e-6);
  EXPECT_NEAR(v.y(), 0.25f, 1e-6);
  // A quarter of the way: 3/4 of the nearer texel.
  const Color q = t.eval({centre(1, 0).x() + 0.25f / 4, centre(1, 0).y()});
  EXPECT_NEAR(q.x(), 0.75f * 0.25f + 0.25f * 0.5f, 1e-6);
}

TEST(ImageTexture, RepeatWrapsAndClampExtendsEdges) {
  const ImageTexture repeat = madeUp(Wrap::Repeat), clamp = madeUp(Wrap::Clamp);
  const Eigen::Vector2f uv = centre(1, 1);
  EXPECT_NEAR((repeat.eval(uv + Eigen::Vector2f(3, -2)) - repeat.eval(uv)).norm(), 0, 1e-5);
  // Left of texel 0's centre, Repeat blends with the last column, Clamp stays on texel 0.
  const Eigen::Vector2f left_edge(0.0f, centre(0, 0).y());
  EXPECT_NEAR(repeat.eval(left_edge).x(), (0.0f + 0.75f) / 2, 1e-6);
  EXPECT_NEAR(clamp.eval(left_edge).x(), 0.0f, 1e-6);
  EXPECT_NEAR(clamp.eval({-50.0f, 0.75f}).x(), 0.0f, 1e-6);
  EXPECT_NEAR(clamp.eval({1e9f, 0.75f}).x(), 0.75f, 1e-6);
}

// The 8-bit encode is the number of code boundaries ((k + 1/2) / 255 decoded) at or below the value: checked by plain
// counting at a million values over [0, 1], both ends and beyond them, and NaN.
TEST(Srgb, EncodeCountsTheBoundariesBelow) {
  std::vector<float> bounds;
  for (int k = 0; k < 255; ++k) bounds.push_back(srgbToLinear((k + 0.5f) / 255.0f));
  const auto reference = [&](float v) {
    if (!(v > 0)) return 0;
    v = std::min(v, 1.0f);
    return int(std::count_if(bounds.begin(), bounds.end(), [&](float b) { return v >= b; }));
  };
  int wrong = 0;
  for (int i = -10; i <= (1 << 20) + 10; ++i) {
    const float v = float(i) / float(1 << 20);
    wrong += linearToSrgb8(v) != reference(v);
  }
  for (const float b : bounds)
    wrong += linearToSrgb8(b) != reference(b) ||
             linearToSrgb8(std::nextafter(b, 0.0f)) != reference(std::nextafter(b, 0.0f));
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(linearToSrgb8(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(linearToSrgb8(1e30f), 255);
}

TEST(Srgb, DecodesKnownValues) {
  EXPECT_NEAR(srgb8ToLinear(128), 0.2158605f, 1e-6);  // ((128/255 + 0.055) / 1.055)^2.4
  EXPECT_EQ(srgb8ToLinear(0), 0.0f);
  EXPECT_NEAR(srgb8ToLinear(255), 1.0f, 1e-6);
  EXPECT_NEAR(srgb8ToLinear(10), 10 / 255.0f / 12.92f, 1e-7);  // linear segment
  EXPECT_EQ(linearToSrgb8(0.2158605f), 128);
  for (int c = 0; c < 256; ++c) EXPECT_EQ(linearToSrgb8(srgb8ToLinear(std::uint8_t(c))), c);

  image::Image8 pixel(1, 1, 3);
  pixel.pixels = {128, 0, 255};
  const Color texel = ImageTexture::fromSrgb8(pixel).eval({0.5f, 0.5f});
  EXPECT_NEAR(texel.x(), 0.2158605f, 1e-6);
  EXPECT_EQ(texel.y(), 0.0f);
  EXPECT_NEAR(texel.z(), 1.0f, 1e-6);
}

TEST(ImageTexture, LoadsPngFileAndReportsMissingOnes) {
  test::TempDir dir;
  image::Image8 image(2, 2, 4);
  image.pixels = {255, 0, 0,   255, 0,   255, 0,   128,  // top row: red, green (alpha ignored)
                  0,   0, 255, 255, 128, 128, 128, 255};
  image::writePng(dir / "t.png", image);
  const ImageTexture t = ImageTexture::load(dir / "t.png", Wrap::Clamp);
  ASSERT_EQ(t.width(), 2);
  ASSERT_EQ(t.height(), 2);
  EXPECT_NEAR((t.eval(centre(0, 0, 2, 2)) - Color(1, 0, 0)).norm(), 0, 1e-6);
  EXPECT_NEAR((t.eval(centre(1, 0, 2, 2)) - Color(0, 1, 0)).norm(), 0, 1e-6);
  EXPECT_NEAR((t.eval(centre(0, 1, 2, 2)) - Color(0, 0, 1)).norm(), 0, 1e-6);
  EXPECT_NEAR(t.eval(centre(1, 1, 2, 2)).x(), 0.2158605f, 1e-6);

  try {
    ImageTexture::load(dir / "cat.png");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cat.png"), std::string::npos) << e.what();
  }
}

TEST(ProceduralTextures, CheckerAlternatesAndWoodStaysInItsColours) {
  const CheckerTexture checker(Color(1, 1, 1), Color(0, 0, 0), 4);
  EXPECT_EQ(checker.eval({0.1f, 0.1f}).x(), 1.0f);
  EXPECT_EQ(checker.eval({0.3f, 0.1f}).x(), 0.0f);
  EXPECT_EQ(checker.eval({0.3f, 0.3f}).x(), 1.0f);
  EXPECT_EQ(checker.eval({-0.1f, 0.1f}).x(), 0.0f);  // no mirrored square at the origin

  const Color light(0.6f, 0.4f, 0.2f), dark(0.3f, 0.2f, 0.1f);
  const WoodTexture wood(light, dark, 8, 4);
  float lo = 1, hi = 0;
  for (int i = 0; i < 50; ++i)
    for (int j = 0; j < 50; ++j) {
      const float r = wood.eval({i / 50.0f, j / 50.0f}).x();
      lo = std::min(lo, r), hi = std::max(hi, r);
    }
  // Between the joint colour (0.35 dark) and the lightest board tone (1.12 light).
  EXPECT_GE(lo, 0.35f * 0.3f - 1e-6f);
  EXPECT_LE(hi, 1.12f * 0.6f + 1e-6f);
  EXPECT_GT(hi - lo, 0.1f);  // it has grain, not a flat colour
}

}  // namespace
}  // namespace wobble::render
