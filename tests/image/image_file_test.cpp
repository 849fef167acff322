// readImageFile (image/image_file.h): every format wobble writes, EXR channel and layer choice, and bad files:
// each refused with a message naming the file and the reason, before anything large is allocated.
#include "image/image_file.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "image/exr_writer.h"
#include "image/pfm_io.h"
#include "image/png_io.h"
#include "tests/temp_dir.h"

namespace wobble::image {
namespace {

ImageF ramp(int w, int h, int c) {
  ImageF img(w, h, c);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = 0.25f * float(i % 17) - 1.0f;
  return img;
}

std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string errorOf(const std::filesystem::path& file, const ChannelChoice& choice = {}) {
  try {
    readImageFile(file, choice);
  } catch (const ImageFileError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ImageFile, ExrFloatAndHalfReadBack) {
  test::TempDir dir;
  const ImageF img = ramp(5, 3, 4);
  writeExrImage(dir / "f.exr", img, {"R", "G", "B", "A"}, false);
  writeExrImage(dir / "h.exr", img, {"R", "G", "B", "A"}, true);  // quarter steps: exact in half too
  for (const char* name : {"f.exr", "h.exr"}) {
    const ImageFile f = readImageFile(dir / name);
    EXPECT_EQ(f.format, "EXR");
    EXPECT_TRUE(f.linear);
    EXPECT_EQ(f.channels, (std::vector<std::string>{"R", "G", "B", "A"}));  // R, G, B, A first, not alphabetical
    EXPECT_EQ(f.image.pixels, img.pixels) << name;
  }
}

TEST(ImageFile, ExrLayersAndChannels) {
  test::TempDir dir;
  Film film(3, 2);
  for (std::size_t i = 0; i < film.color.size(); ++i) {
    film.color[i] = Color(1, 2, 3);
    film.albedo[i] = Eigen::Vector3f(0.25f, 0.5f, 0.75f);
  }
  std::vector<Color> denoised(film.color.size(), Color(4, 5, 6));
  writeExr(dir / "frame.exr", film, denoised);
  const ImageFile rgb = readImageFile(dir / "frame.exr");  // the unnamed layer: the denoised colour
  EXPECT_EQ(rgb.channels, (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_EQ(rgb.image.at(2, 1, 0), 4);
  const ImageFile albedo = readImageFile(dir / "frame.exr", {"albedo", {}});
  EXPECT_EQ(albedo.channels, (std::vector<std::string>{"albedo.R", "albedo.G", "albedo.B"}));
  EXPECT_EQ(albedo.image.at(0, 0, 1), 0.5f);
  const ImageFile noisy = readImageFile(dir / "frame.exr", {"", splitChannelList("noisy.R,G,B")});
  EXPECT_EQ(noisy.channels, (std::vector<std::string>{"noisy.R", "noisy.G", "noisy.B"}));
  EXPECT_EQ(noisy.image.at(1, 1, 2), 3);
  const ImageFile depth = readImageFile(dir / "frame.exr", {"depth", {}});
  EXPECT_EQ(depth.channels, (std::vector<std::string>{"depth.Z"}));

  const std::string no_layer = errorOf(dir / "frame.exr", {"specular", {}});
  EXPECT_NE(no_layer.find("frame.exr"), std::string::npos) << no_layer;
  EXPECT_NE(no_layer.find("no layer 'specular'"), std::string::npos) << no_layer;
  EXPECT_NE(no_layer.find("albedo"), std::string::npos) << no_layer;  // what there is
  const std::string no_channel = errorOf(dir / "frame.exr", {"", {"albedo.Q"}});
  EXPECT_NE(no_channel.find("no channel 'albedo.Q'"), std::string::npos) << no_channel;
  writePng(dir / "a.png", Image8(2, 2, 3));
  EXPECT_NE(errorOf(dir / "a.png", {"albedo", {}}).find("has no layers"), std::string::npos);
  EXPECT_EQ(readImageFile(dir / "a.png", {"", {"G"}}).channels, std::vector<std::string>{"G"});
}

TEST(ImageFile, PfmBothByteOrdersAndGrey) {
  test::TempDir dir;
  writePfm(dir / "rgb.pfm", 2, 1, std::vector<Color>{Color(1, 2, 3), Color(4, 5, 6)});
  const ImageFile rgb = readImageFile(dir / "rgb.pfm");
  EXPECT_EQ(rgb.image.pixels, (std::vector<float>{1, 2, 3, 4, 5, 6}));
  // Grey, big-endian (positive scale), two rows stored bottom first.
  std::string bytes = "Pf\n1 2\n1.0\n";
  for (float v : {7.0f, 8.0f}) {  // bottom row 7, top row 8
    unsigned char b[4];
    std::memcpy(b, &v, 4);
    bytes += std::string{char(b[3]), char(b[2]), char(b[1]), char(b[0])};
  }
  std::ofstream(dir / "grey.pfm", std::ios::binary) << bytes;
  const ImageFile grey = readImageFile(dir / "grey.pfm");
  EXPECT_EQ(grey.channels, std::vector<std::string>{"Y"});
  EXPECT_EQ(grey.image.pixels, (std::vector<float>{8, 7}));
}

// Radiance RGBE (Ward 1991): a pixel's channels are its mantissas times 2^(exponent - 136), linear radiance, with no
// colour decoding; rows top to bottom ("-Y H +X W"). Written byte by byte here, flat (no run-length encoding: under 8
// pixels wide), with values that need the exponent: 0.75 * 2^11, 2^-1 and 0.
TEST(ImageFile, RadianceHdrIsMantissaTimesTwoToTheExponent) {
  test::TempDir dir;
  const unsigned char pixels[2][3][4] = {{{192, 64, 0, 139}, {128, 128, 128, 128}, {0, 0, 0, 0}},
                                         {{255, 1, 16, 120}, {32, 64, 96, 130}, {200, 100, 50, 136}}};
  {
    std::ofstream out(dir / "t.hdr", std::ios::binary);
    out << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 3\n";
    out.write(reinterpret_cast<const char*>(pixels), sizeof pixels);
  }
  const ImageFile f = readImageFile(dir / "t.hdr");
  EXPECT_EQ(f.format, "HDR");
  EXPECT_TRUE(f.linear);
  ASSERT_EQ(f.image.width, 3);
  ASSERT_EQ(f.image.height, 2);
  ASSERT_EQ(f.image.channels, 3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < 3; ++c) {
        const unsigned char* p = pixels[y][x];
        const float expected = p[3] == 0 ? 0.0f : std::ldexp(float(p[c]), int(p[3]) - 136);
        EXPECT_EQ(f.image.at(x, y, c), expected) << x << ", " << y << ", channel " << c;
      }
  EXPECT_EQ(f.image.at(0, 0, 0), 1536.0f);  // 192 * 2^3: 0.75 * 2^11
  EXPECT_EQ(f.image.at(1, 0, 2), 0.5f);     // 128 * 2^-8
}

TEST(ImageFile, BadFilesNameTheFileAndTheReason) {
  test::TempDir dir;
  std::ofstream(dir / "text.png") << "not an image at all";
  std::ofstream(dir / "empty.exr");
  writePng(dir / "good.png", Image8(64, 64, 3));
  const std::string png = slurp(dir / "good.png");
  std::ofstream(dir / "truncated.png", std::ios::binary) << png.substr(0, png.size() / 2);
  writeExrImage(dir / "good.exr", ramp(64, 64, 3), {"R", "G", "B"}, false);
  const std::string exr = slurp(dir / "good.exr");
  std::ofstream(dir / "truncated.exr", std::ios::binary) << exr.substr(0, exr.size() / 2);
  std::ofstream(dir / "huge.pfm", std::ios::binary) << "PF\n20000 20000\n-1.0\n";
  std::ofstream(dir / "truncated.pfm", std::ios::binary) << "PF\n4 4\n-1.0\n" << std::string(20, '\0');

  const std::pair<const char*, const char*> cases[] = {
      {"text.png", "not an image"},     {"empty.exr", "empty"},        {"truncated.png", "truncated"},
      {"truncated.exr", "cannot read"}, {"huge.pfm", "at most 16384"}, {"truncated.pfm", "truncated"},
      {"missing.png", "cannot open"},
  };
  for (const auto& [name, reason] : cases) {
    const std::string e = errorOf(dir / name);
    EXPECT_NE(e.find(name), std::string::npos) << e;
    EXPECT_NE(e.find(reason), std::string::npos) << name << ": " << e;
  }
  EXPECT_NE(errorOf(dir.path()).find("is a folder"), std::string::npos);
}

}  // namespace
}  // namespace wobble::image
