// PNG writing (libpng container, libdeflate image data): what stb's own decoder reads back is the image written, for
// every channel count; text chunks come back; the bytes are the same every time.
#include "image/png_io.h"

#include <fstream>
#include <iterator>
#include <random>

#include <gtest/gtest.h>

#include "tests/temp_dir.h"

namespace wobble::image {
namespace {

Image8 noise(int w, int h, int channels, unsigned seed) {
  Image8 image(w, h, channels);
  std::mt19937 rng(seed);
  // Half the rows random, half smooth ramps: both the literal and the match paths of the compressor.
  for (int y = 0; y < h; ++y)
    for (int i = 0; i < w * channels; ++i)
      image.pixels[std::size_t(y) * w * channels + i] = y % 2 ? std::uint8_t(rng()) : std::uint8_t(i / channels + y);
  return image;
}

std::string bytesOf(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(PngIo, EveryChannelCountReadsBackExactly) {
  const test::TempDir dir;
  for (int channels = 1; channels <= 4; ++channels)
    for (const auto& [w, h] : {std::pair{1, 1}, std::pair{7, 3}, std::pair{333, 41}}) {
      const Image8 image = noise(w, h, channels, unsigned(channels * 1000 + w));
      std::string name = "c";  // appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "c" + a temporary
      name += std::to_string(channels);
      name += '_';
      name += std::to_string(w);
      const auto file = dir / (name + ".png");
      writePng(file, image);
      const Image8 back = readImage(file);  // stb's decoder: its own inflate, not libdeflate's
      EXPECT_EQ(back.width, w);
      EXPECT_EQ(back.height, h);
      EXPECT_EQ(back.channels, channels);
      EXPECT_EQ(back.pixels, image.pixels) << channels << " channels, " << w << " x " << h;
    }
}

TEST(PngIo, TextChunksComeBackAndBytesRepeat) {
  const test::TempDir dir;
  const Image8 image = noise(64, 16, 3, 7);
  const std::map<std::string, std::string> text{{"wobble-settings", "abc123"}, {"wobble-frame", "def456"}};
  writePng(dir / "a.png", image, text);
  writePng(dir / "b.png", image, text);
  EXPECT_EQ(readPngText(dir / "a.png"), text);
  EXPECT_EQ(readImage(dir / "a.png").pixels, image.pixels);
  EXPECT_EQ(bytesOf(dir / "a.png"), bytesOf(dir / "b.png"));
}

}  // namespace
}  // namespace wobble::image
