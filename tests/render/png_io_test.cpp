// PNG files: round trip, text chunks, atomic replacement, and errors that name the file.
#include "render/image/png_io.h"

#include <fstream>
#include <iterator>
#include <map>

#include <gtest/gtest.h>

#include "render/image/film.h"
#include "tests/render/test_util.h"

namespace wobble::render {
namespace {

TEST(Png, RoundTripKeepsEveryByteAndLeavesNoTemporaryFile) {
  test::TempDir dir;
  for (int channels = 1; channels <= 4; ++channels) {
    Image8 image(7, 5, channels);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = std::uint8_t(i * 37 % 256);
    const auto file = dir / (std::to_string(channels) + "channels.png");
    writePng(file, image);
    const Image8 back = readImage(file);
    EXPECT_TRUE(back.sameShape(image)) << channels;
    EXPECT_EQ(back.pixels, image.pixels) << channels;
  }
  writePng(dir / "3channels.png", Image8(2, 2, 3));  // replaces the existing file
  EXPECT_EQ(readImage(dir / "3channels.png").width, 2);
  EXPECT_EQ(dir.entries(), 4);
}

// Text chunks: tEXt as the PNG specification lays it out (keyword, a zero byte, the text), before the image data, and
// read back without the pixels; the pixels are the same as without them.
TEST(Png, TextChunksRoundTripBeforeTheImageData) {
  test::TempDir dir;
  Image8 image(5, 3, 3);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = std::uint8_t(i * 11);
  const std::map<std::string, std::string> text = {{"wobble-frame", "0123abcd"}, {"Comment", "two words"}};
  writePng(dir / "text.png", image, text);
  writePng(dir / "plain.png", image);
  EXPECT_EQ(readPngText(dir / "text.png"), text);
  EXPECT_TRUE(readPngText(dir / "plain.png").empty());
  EXPECT_EQ(readImage(dir / "text.png").pixels, image.pixels);
  std::ifstream in(dir / "text.png", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto chunk =
      bytes.find(std::string("tEXtwobble-frame\0"
                             "0123abcd",
                             25));
  ASSERT_NE(chunk, std::string::npos);
  EXPECT_LT(chunk, bytes.find("IDAT"));
  // Not a PNG, or no file: no text (and no message from libpng).
  std::ofstream(dir / "broken.png") << "PNG? no";
  EXPECT_TRUE(readPngText(dir / "broken.png").empty());
  EXPECT_TRUE(readPngText(dir / "missing.png").empty());
  EXPECT_THROW(writePng(dir / "bad.png", image, {{"", "empty keyword"}}), std::invalid_argument);
}

TEST(Png, ErrorsNameTheFile) {
  test::TempDir dir;
  try {
    writePng(dir / "nowhere" / "frame.png", Image8(2, 2, 3));
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nowhere"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "broken.png") << "PNG? no";
  try {
    readImage(dir / "broken.png");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("broken.png"), std::string::npos) << e.what();
  }
  EXPECT_THROW(writePng(dir / "empty.png", Image8{}), std::invalid_argument);
}

TEST(ToneMapping, CurvesAreMonotonicAndEncodeToSrgb) {
  for (auto curve : {ToneMap::Curve::Aces, ToneMap::Curve::Reinhard, ToneMap::Curve::Clamp}) {
    const ToneMap tm{0, curve};
    EXPECT_EQ(tm.apply(0), 0.0f);
    float previous = 0;
    for (float x = 0.01f; x < 100; x *= 1.5f) {
      const float y = tm.apply(x);
      EXPECT_GE(y, previous);
      EXPECT_LE(y, 1.0f);
      previous = y;
    }
  }
  EXPECT_NEAR(ToneMap({0, ToneMap::Curve::Reinhard}).apply(1), 0.5f, 1e-6);
  EXPECT_NEAR(ToneMap({1, ToneMap::Curve::Reinhard}).apply(0.5f), 0.5f, 1e-6);  // +1 stop doubles
  Film film(2, 1);
  film.color = {Color(0.2158605f, 0, 1), Color(-1, 5, std::nanf(""))};
  const Image8 image = develop(film, {0, ToneMap::Curve::Clamp});
  EXPECT_EQ(image.pixels, (std::vector<std::uint8_t>{128, 0, 255, 0, 255, 0}));
}

}  // namespace
}  // namespace wobble::render
