// EXR output: every layer written comes back from OpenEXR with the right names, types and values.
#include "image/exr_writer.h"

#include <cmath>
#include <fstream>
#include <limits>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <gtest/gtest.h>

#include "tests/temp_dir.h"

namespace wobble::image {
namespace {

Film madeUpFilm() {
  Film film(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      const std::size_t i = film.index(x, y);
      const float f = static_cast<float>(i);
      film.color[i] = Color(0.1f * f, 2.5f + f, 1000.0f / (1 + f));  // above 1 too: EXR keeps HDR values
      film.albedo[i] = Color(0.01f * f, 0.5f, 1 - 0.05f * f);
      film.normal[i] = Eigen::Vector3f(std::sin(f), std::cos(f), -0.5f).normalized();
      film.depth[i] = 3.14159f + 10.123456f * f;
    }
  film.depth[film.index(4, 2)] = std::numeric_limits<float>::infinity();  // sky
  return film;
}

// Reads one channel as float (OpenEXR converts from half).
std::vector<float> readChannel(Imf::InputFile& file, const std::string& name) {
  const Imath::Box2i dw = file.header().dataWindow();
  const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
  std::vector<float> values(std::size_t(w) * h, -1.0f);
  Imf::FrameBuffer fb;
  fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data() - dw.min.x - dw.min.y * w),
                             sizeof(float), sizeof(float) * w));
  file.setFrameBuffer(fb);
  file.readPixels(dw.min.y, dw.max.y);
  return values;
}

float asHalf(float v) { return static_cast<float>(half(v)); }

TEST(Exr, EveryLayerRoundTrips) {
  test::TempDir dir;
  const Film film = madeUpFilm();
  writeExr(dir / "frame.exr", film);
  EXPECT_EQ(dir.entries(), 1);  // no temporary file left

  Imf::InputFile file((dir / "frame.exr").c_str());
  const Imath::Box2i dw = file.header().dataWindow();
  EXPECT_EQ(dw.max.x - dw.min.x + 1, 5);
  EXPECT_EQ(dw.max.y - dw.min.y + 1, 3);
  int count = 0;
  for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
    ++count;
    EXPECT_EQ(it.channel().type, std::string(it.name()) == "depth.Z" ? Imf::FLOAT : Imf::HALF) << it.name();
  }
  EXPECT_EQ(count, 10);
  for (std::string_view name : kExrChannels)
    EXPECT_NE(file.header().channels().findChannel(std::string(name)), nullptr) << name;

  const auto expectLayer = [&](const std::vector<Color>& values, const std::string& prefix, const char* names) {
    for (int k = 0; k < 3; ++k) {
      const std::string name = prefix + names[k];
      ASSERT_NE(file.header().channels().findChannel(name), nullptr) << name;
      const std::vector<float> got = readChannel(file, name);
      for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(got[i], asHalf(values[i][k])) << name << " " << i;
    }
  };
  expectLayer(film.color, "", "RGB");
  expectLayer(film.albedo, "albedo.", "RGB");
  expectLayer(film.normal, "normal.", "XYZ");
  const std::vector<float> depth = readChannel(file, "depth.Z");
  for (std::size_t i = 0; i < depth.size(); ++i) EXPECT_EQ(depth[i], film.depth[i]) << i;  // float: exact
}

// With a denoised colour, R, G, B hold it and the film's own (noisy) colour moves to the noisy layer.
TEST(Exr, DenoisedColourGoesToRgbAndTheNoisyOneIsKept) {
  test::TempDir dir;
  const Film film = madeUpFilm();
  std::vector<Color> denoised(film.color.size());
  for (std::size_t i = 0; i < denoised.size(); ++i) denoised[i] = Color(0.5f, 0.25f, 2.0f) * float(i + 1);
  writeExr(dir / "frame.exr", film, denoised);
  Imf::InputFile file((dir / "frame.exr").c_str());
  int count = 0;
  for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) ++count;
  EXPECT_EQ(count, 13);
  for (const auto& [values, prefix] : {std::pair{static_cast<const std::vector<Color>*>(&denoised), std::string()},
                                       std::pair{&film.color, std::string("noisy.")}})
    for (int k = 0; k < 3; ++k) {
      const std::string name = prefix + "RGB"[k];
      ASSERT_NE(file.header().channels().findChannel(name), nullptr) << name;
      const std::vector<float> got = readChannel(file, name);
      for (std::size_t i = 0; i < values->size(); ++i) EXPECT_EQ(got[i], asHalf((*values)[i][k])) << name << " " << i;
    }
  EXPECT_THROW(writeExr(dir / "bad.exr", film, std::vector<Color>(3)), std::invalid_argument);
}

// String attributes in the header, as OpenEXR itself reads them, and back through readExrText.
TEST(Exr, TextAttributesRoundTrip) {
  test::TempDir dir;
  writeExr(dir / "frame.exr", madeUpFilm(), {}, {{"wobble-frame", "0123abcd"}});
  const Imf::InputFile file((dir / "frame.exr").c_str());
  const auto* attribute = file.header().findTypedAttribute<Imf::StringAttribute>("wobble-frame");
  ASSERT_NE(attribute, nullptr);
  EXPECT_EQ(attribute->value(), "0123abcd");
  EXPECT_EQ(readExrText(dir / "frame.exr").at("wobble-frame"), "0123abcd");
  EXPECT_TRUE(readExrText(dir / "missing.exr").empty());
  std::ofstream(dir / "broken.exr") << "EXR? no";
  EXPECT_TRUE(readExrText(dir / "broken.exr").empty());
}

TEST(Exr, OverwritesAtomicallyAndReportsBadPaths) {
  test::TempDir dir;
  writeExr(dir / "frame.exr", madeUpFilm());
  Film other(2, 2);
  writeExr(dir / "frame.exr", other);
  EXPECT_EQ(dir.entries(), 1);
  Imf::InputFile file((dir / "frame.exr").c_str());
  EXPECT_EQ(file.header().dataWindow().max.x, 1);
  try {
    writeExr(dir / "missing" / "frame.exr", other);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace wobble::image
