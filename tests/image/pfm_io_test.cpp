// PFM files: writePfm then readPfm gives back the same floats in the same rows, the file follows the format (rows
// bottom to top), writing leaves no temporary file, and bad files throw naming the file.
#include "image/pfm_io.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/temp_dir.h"

namespace wobble::image {
namespace {

using test::TempDir;

// 3 x 2 pixels, all channels different, with zeros, values above 1, a tiny and a huge one.
std::vector<Color> sample() {
  return {{0, 0.5f, 1}, {1.5f, 2.25f, 100},        {1e-30f, 3.4e38f, 0.1f},
          {0.3f, 0, 7}, {-0.0f, 65504, 0.333333f}, {std::numeric_limits<float>::denorm_min(), 12.5f, 0.7f}};
}

bool sameBits(const Color& a, const Color& b) { return std::memcmp(a.data(), b.data(), sizeof(float) * 3) == 0; }

std::string readAll(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Pfm, RoundTripIsBitExactWithTheTopRowOnTop) {
  const TempDir dir;
  const auto file = dir / "image.pfm";
  const std::vector<Color> pixels = sample();
  writePfm(file, 3, 2, pixels);
  EXPECT_EQ(dir.entries(), 1);  // no temporary file left behind

  const FloatImage back = readPfm(file);
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  ASSERT_EQ(back.pixels.size(), pixels.size());
  for (std::size_t i = 0; i < pixels.size(); ++i)
    EXPECT_TRUE(sameBits(back.pixels[i], pixels[i])) << "pixel " << i << ": " << back.pixels[i].transpose();
}

// The file itself: header "PF", width height, a negative scale (little endian), then rows bottom to top.
TEST(Pfm, FileStoresRowsBottomToTopLittleEndian) {
  const TempDir dir;
  const auto file = dir / "layout.pfm";
  const std::vector<Color> pixels = sample();
  writePfm(file, 3, 2, pixels);
  const std::string bytes = readAll(file);
  const std::string header = "PF\n3 2\n";
  ASSERT_EQ(bytes.compare(0, header.size(), header), 0) << bytes.substr(0, 16);
  // The scale line: a negative number, then a newline, then 2 rows of 3 RGB floats.
  const std::size_t scale_end = bytes.find('\n', header.size());
  ASSERT_NE(scale_end, std::string::npos);
  EXPECT_LT(std::stod(bytes.substr(header.size(), scale_end - header.size())), 0);
  const std::size_t data = scale_end + 1;
  ASSERT_EQ(bytes.size() - data, 2 * 3 * 3 * sizeof(float));
  for (int row = 0; row < 2; ++row)
    for (int x = 0; x < 3; ++x) {
      Color stored;
      std::memcpy(stored.data(), bytes.data() + data + (std::size_t(row) * 3 + x) * 3 * sizeof(float),
                  3 * sizeof(float));
      const int image_row = 1 - row;  // the file's first row is the image's bottom row
      EXPECT_TRUE(sameBits(stored, pixels[std::size_t(image_row) * 3 + x])) << "file row " << row << " x " << x;
    }
}

TEST(Pfm, OverwritingReplacesTheFile) {
  const TempDir dir;
  const auto file = dir / "again.pfm";
  writePfm(file, 3, 2, sample());
  const std::vector<Color> one{{0.25f, 0.5f, 0.75f}};
  writePfm(file, 1, 1, one);
  EXPECT_EQ(dir.entries(), 1);
  const FloatImage back = readPfm(file);
  EXPECT_EQ(back.width, 1);
  EXPECT_EQ(back.height, 1);
  ASSERT_EQ(back.pixels.size(), 1u);
  EXPECT_TRUE(sameBits(back.pixels[0], one[0]));
}

// The exception's message names the file.
template <typename F>
void expectRuntimeErrorNaming(F&& f, const std::filesystem::path& file) {
  try {
    f();
    ADD_FAILURE() << "no exception for " << file;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file.filename().string()), std::string::npos) << e.what();
  }
}

TEST(Pfm, BadFilesThrowNamingTheFile) {
  const TempDir dir;
  // Truncated: the header and half of the data.
  const auto truncated = dir / "truncated.pfm";
  writePfm(truncated, 3, 2, sample());
  std::filesystem::resize_file(truncated, std::filesystem::file_size(truncated) - 3 * 3 * sizeof(float) - 1);
  expectRuntimeErrorNaming([&] { readPfm(truncated); }, truncated);
  // Only the header.
  const auto header_only = dir / "header_only.pfm";
  std::ofstream(header_only, std::ios::binary) << "PF\n3 2\n-1.0\n";
  expectRuntimeErrorNaming([&] { readPfm(header_only); }, header_only);
  // Not a PFM: a binary PPM header, a greyscale PFM ("Pf"), a big-endian scale, text.
  const auto ppm = dir / "picture.ppm";
  std::ofstream(ppm, std::ios::binary) << "P6\n1 1\n255\n" << std::string(3, '\x7f');
  expectRuntimeErrorNaming([&] { readPfm(ppm); }, ppm);
  const auto grey = dir / "grey.pfm";
  std::ofstream(grey, std::ios::binary) << "Pf\n1 1\n-1.0\n" << std::string(4, '\0');
  expectRuntimeErrorNaming([&] { readPfm(grey); }, grey);
  const auto big_endian = dir / "big_endian.pfm";
  std::ofstream(big_endian, std::ios::binary) << "PF\n1 1\n1.0\n" << std::string(12, '\0');
  expectRuntimeErrorNaming([&] { readPfm(big_endian); }, big_endian);
  const auto text = dir / "notes.txt";
  std::ofstream(text) << "hello, world\n";
  expectRuntimeErrorNaming([&] { readPfm(text); }, text);
  // Missing.
  expectRuntimeErrorNaming([&] { readPfm(dir / "missing.pfm"); }, dir / "missing.pfm");
}

}  // namespace
}  // namespace wobble::image
