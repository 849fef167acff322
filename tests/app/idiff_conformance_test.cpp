// `wobble diff` against the real OpenImageIO idiff (Debian 12's openimageio-tools, idiff 2.4): the same image pairs
// with the same options must give the same exit code, and for same-size pairs the same printed report.
// PNG pairs made here: equal, a few pixels off by a little, many off, one far off, right at a threshold, and pairs of
// different size or channel count (which idiff compares over both, the missing values as black); 16-bit PNG.
// EXR pairs (half and float): equal, noise, a shifted edge, different sizes, different channel counts, NaN and
// infinity pixels; Radiance HDR and PFM pairs; -p (idiff's perceptual test) on colour and brightness differences.
// Options: the defaults, only --fail, --warn below --fail, percentages, hard limits, --allowfailures, relative limits.
// Every option set runs in both spellings: idiff's own (one dash, -fail 0.02), given to idiff and to wobble diff, and
// the two-dash one (--fail 0.02), given to wobble diff: the same exit code and report from all three.
// Skipped, saying why, where idiff is not installed. Prints the table of exit codes it compared.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <map>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <png.h>

#include "app/output/external_program.h"
#include "image/image_file.h"
#include "image/pfm_io.h"
#include "image/png_io.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using image::Image8;
using image::ImageF;

Image8 gradient(int w, int h, int channels) {
  Image8 img(w, h, channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c) img.at(x, y, c) = std::uint8_t(c == 3 ? 255 : 20 + 9 * x + 7 * y + 30 * c);
  return img;
}

// The first n pixels (row order) of channel 1 raised by `codes`.
Image8 raised(int n, int codes) {
  Image8 img = gradient(20, 10, 3);
  for (int i = 0; i < n; ++i)
    img.pixels[std::size_t(i) * 3 + 1] = std::uint8_t(img.pixels[std::size_t(i) * 3 + 1] + codes);
  return img;
}

Image8 withBlackRow(const Image8& a) {
  Image8 img(a.width, a.height + 1, a.channels);
  std::copy(a.pixels.begin(), a.pixels.end(), img.pixels.begin());
  return img;
}

// Linear HDR values: a gradient up to about 6 (brighter than display white), alpha 1.
ImageF hdrGradient(int w, int h, int channels) {
  ImageF img(w, h, channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c) img.at(x, y, c) = c == 3 ? 1.0f : 0.01f + 0.25f * x + 0.1f * y + 0.3f * c;
  return img;
}

// Deterministic noise of amplitude `amount` on every `every`-th value.
ImageF noisy(ImageF img, float amount, int every) {
  std::uint32_t state = 12345;
  for (std::size_t i = 0; i < img.pixels.size(); i += std::size_t(every)) {
    state = state * 1664525u + 1013904223u;
    img.pixels[i] += amount * (float(state >> 8) / float(1u << 24) - 0.5f);
  }
  return img;
}

// A vertical edge: 0.1 left of `at`, 2.0 from it on.
ImageF edge(int at) {
  ImageF img(20, 10, 3);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 20; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = x < at ? 0.1f : 2.0f;
  return img;
}

ImageF with(ImageF img, int x, int y, int c, float value) {
  img.at(x, y, c) = value;
  return img;
}

std::vector<std::string> names(int channels) {
  switch (channels) {
    case 1:
      return {"Y"};
    case 3:
      return {"R", "G", "B"};
    default:
      return {"R", "G", "B", "A"};
  }
}

// Radiance RGBE, flat scanlines (no run-length encoding), as Greg Ward's reference code writes them.
void writeHdr(const fs::path& file, const ImageF& img) {
  std::string bytes = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(img.height) + " +X " +
                      std::to_string(img.width) + "\n";
  for (std::size_t i = 0; i < img.pixels.size(); i += 3) {
    const float v = std::max({img.pixels[i], img.pixels[i + 1], img.pixels[i + 2]});
    unsigned char rgbe[4] = {0, 0, 0, 0};
    if (v > 1e-32f) {
      int e = 0;
      const float m = std::frexp(v, &e) * 256.0f / v;
      for (int c = 0; c < 3; ++c) rgbe[c] = static_cast<unsigned char>(img.pixels[i + std::size_t(c)] * m);
      rgbe[3] = static_cast<unsigned char>(e + 128);
    }
    bytes.append(reinterpret_cast<const char*>(rgbe), 4);
  }
  std::ofstream(file, std::ios::binary) << bytes;
}

void writePfmImage(const fs::path& file, const ImageF& img) {
  std::vector<image::Color> pixels;
  for (std::size_t i = 0; i < img.pixels.size(); i += 3)
    pixels.emplace_back(img.pixels[i], img.pixels[i + 1], img.pixels[i + 2]);
  image::writePfm(file, img.width, img.height, pixels);
}

// 16-bit RGB PNG through libpng's simplified API (codes = value * 65535, as stored).
void writePng16(const fs::path& file, const std::vector<std::uint16_t>& rgb, int w, int h) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = png_uint_32(w);
  image.height = png_uint_32(h);
  image.format = PNG_FORMAT_LINEAR_RGB;
  ASSERT_TRUE(png_image_write_to_file(&image, file.c_str(), 0, rgb.data(), 0, nullptr)) << image.message;
}

const std::vector<std::string> kOptions = {
    "",                                              // idiff's defaults: any difference fails
    "--fail 0.02",                                   // only --fail: no pixel over it passes
    "--warn 0.001 --fail 0.05",                      // --warn below --fail
    "--fail 0.004 --warn 0.001 --failpercent 50",    // failures within the allowance: warnings decide
    "--fail 0.005 --failpercent 10 --hardfail 0.1",  // hard limit
    "--fail 0.007843137718737125",                   // 2/255 as a float: right at the threshold
    "--allowfailures 3",
    "--failpercent 100 --warnpercent 20 --hardwarn 0.5",
    "--fail 0.004 --failrelative 0.05",  // relative limits: large values need more
    "--fail 1 --warn 0.001 --warnrelative 0.1 --warnpercent 1",
};

const std::vector<std::string> kHdrOptions = {
    "",
    "--fail 0.02",
    "--fail 0.5 --warn 0.01",
    "--fail 0.01 --failpercent 20",
    "--failpercent 100 --hardfail 1",
    "--allowfailures 3",
    "--failpercent 100 --warnpercent 20 --hardwarn 0.5",
    "--fail 1e30 --hardfail 1e30",
    "--fail 0.001 --failrelative 0.02",
    "--fail 0.001 --failrelative 0.5 --warn 0.001 --warnrelative 0.01",
};

const std::vector<std::string> kPerceptualOptions = {
    "-p",
    "-p --failpercent 30",
    "-p --failpercent 60",
    "-p --failpercent 90 --fail 0.01",
    "-p --fail 2",
    "-p --allowfailures 5 --failpercent 50",
};

// idiff's spelling of an option set: "--fail 0.02 --failpercent 1" -> "-fail 0.02 -failpercent 1".
std::string oneDash(const std::string& options) {
  std::string out;
  std::istringstream words(options);
  for (std::string w; words >> w;) out.append(out.empty() ? "" : " ").append(w, w.starts_with("--") ? 1 : 0);
  return out;
}

struct FilePair {
  std::string name;
  fs::path a, b;
};

class IdiffConformance : public testing::ScratchDir {
 protected:
  void SetUp() override {
    testing::ScratchDir::SetUp();
    idiff_ = findProgram("idiff");
  }

  // Same exit codes for every pair and option set; same report text for same-size pairs.
  void compare(const std::vector<FilePair>& pairs, const std::vector<std::string>& options, bool same_report = true) {
    if (!idiff_) GTEST_SKIP() << "idiff (OpenImageIO's, Debian package openimageio-tools) is not on PATH";
    const fs::path log = dir() / "log.txt", idiff_log = dir() / "idiff.txt";
    std::ostringstream table;
    table << "idiff / wobble diff exit codes\n";
    for (const FilePair& p : pairs) {
      table << "  " << p.name << ":";
      for (const std::string& two_dashes : options) {
        const std::string files = " " + p.a.native() + " " + p.b.native(), o = oneDash(two_dashes);
        const int status = std::system((idiff_->string() + " " + o + files + " > " + idiff_log.string()).c_str());
        const int expected = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        int got = 0;
        for (const std::string& spelling : {o, two_dashes}) {
          got = testing::runWobble("diff " + spelling + files, log);
          EXPECT_EQ(got, expected) << p.name << " with [" << spelling << "]:\nwobble:\n"
                                   << testing::slurpFile(log) << "idiff:\n"
                                   << testing::slurpFile(idiff_log);
          if (same_report && expected != 4) {
            EXPECT_EQ(testing::slurpFile(log), testing::slurpFile(idiff_log)) << p.name << " with [" << spelling << "]";
          }
        }
        table << " " << expected << "/" << got;
      }
      table << "\n";
    }
    std::cout << table.str();
  }

  FilePair png(const std::string& name, const Image8& a, const Image8& b) {
    const FilePair p{name, dir() / (name + "_a.png"), dir() / (name + "_b.png")};
    image::writePng(p.a, a);
    image::writePng(p.b, b);
    return p;
  }
  FilePair exr(const std::string& name, const ImageF& a, const ImageF& b, bool half = false) {
    const FilePair p{name, dir() / (name + "_a.exr"), dir() / (name + "_b.exr")};
    image::writeExrImage(p.a, a, names(a.channels), half);
    image::writeExrImage(p.b, b, names(b.channels), half);
    return p;
  }

  std::optional<fs::path> idiff_;
};

TEST_F(IdiffConformance, SameSize) {
  const Image8 base = gradient(20, 10, 3);
  compare({png("equal", base, base), png("3px_2codes", base, raised(3, 2)), png("80px_5codes", base, raised(80, 5)),
           png("1px_60codes", base, raised(1, 60)), png("4px_2codes_swapped", raised(4, 2), base)},
          kOptions);
}

TEST_F(IdiffConformance, DifferentSizeOrChannels) {
  const Image8 base = gradient(20, 10, 3);
  compare({png("taller", base, gradient(20, 11, 3)), png("taller_by_black", base, withBlackRow(base)),
           png("shorter_by_black", withBlackRow(base), base), png("rgb_rgba", base, gradient(20, 10, 4)),
           png("black_grey_rgb", Image8(20, 10, 1), Image8(20, 10, 3)),
           png("black_rgb_rgba", Image8(20, 10, 3), Image8(20, 10, 4))},
          kOptions, false);
}

TEST_F(IdiffConformance, Png16Bit) {
  std::vector<std::uint16_t> a(20 * 10 * 3), b;
  for (std::size_t i = 0; i < a.size(); ++i) a[i] = std::uint16_t(1000 + 211 * i);
  b = a;
  for (int i = 0; i < 12; ++i) b[std::size_t(i) * 5] = std::uint16_t(b[std::size_t(i) * 5] + 40 + 90 * i);
  const FilePair equal{"png16_equal", dir() / "a16.png", dir() / "a16.png"};
  const FilePair changed{"png16_12px", dir() / "a16.png", dir() / "b16.png"};
  writePng16(equal.a, a, 20, 10);
  writePng16(changed.b, b, 20, 10);
  compare({equal, changed}, kOptions);
}

// Colour with partial alpha: idiff compares the colour premultiplied by alpha (OpenImageIO, on the 8-bit codes).
TEST_F(IdiffConformance, PngAlpha) {
  Image8 a = gradient(20, 10, 4), b = gradient(20, 10, 4);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 20; ++x) {
      a.at(x, y, 3) = std::uint8_t(12 * x + y);
      b.at(x, y, 3) = std::uint8_t(12 * x + y);
      b.at(x, y, 0) = std::uint8_t(a.at(x, y, 0) + (x % 3) * 2);  // hidden where alpha is low
    }
  // The same through libpng's simplified writer, which adds an sRGB chunk.
  const FilePair srgb{"rgba_srgb_chunk", dir() / "srgb_a.png", dir() / "srgb_b.png"};
  for (const auto& [file, img] : {std::pair{srgb.a, a}, std::pair{srgb.b, b}}) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = 20;
    image.height = 10;
    image.format = PNG_FORMAT_RGBA;
    ASSERT_TRUE(png_image_write_to_file(&image, file.c_str(), 0, img.pixels.data(), 0, nullptr)) << image.message;
  }
  compare({png("rgba_alpha", a, b), png("rgba_alpha_same", a, a), srgb}, kOptions);
}

TEST_F(IdiffConformance, ExrPairs) {
  const ImageF base = hdrGradient(20, 10, 3);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  compare({exr("exr_equal", base, base), exr("exr_equal_half", base, base, true),
           exr("exr_noise", base, noisy(base, 0.05f, 7)), exr("exr_noise_half", base, noisy(base, 0.05f, 3), true),
           exr("exr_edge_shifted", edge(10), edge(11)),
           exr("exr_nan_both", with(base, 3, 2, 1, nan), with(base, 3, 2, 1, nan)),
           exr("exr_nan_one", base, with(base, 3, 2, 1, nan)),
           exr("exr_nan_two", base, with(with(base, 3, 2, 1, nan), 5, 5, 0, nan)),
           exr("exr_inf_one", base, with(base, 4, 1, 2, inf)),
           exr("exr_inf_two", base, with(with(base, 4, 1, 2, inf), 9, 9, 0, inf)),
           exr("exr_inf_signs", with(base, 0, 0, 0, inf), with(base, 0, 0, 0, -inf)),
           exr("exr_nan_inf", with(base, 1, 1, 1, nan), with(base, 1, 1, 1, inf))},
          kHdrOptions);
  // Half against float: the same values, rounded to half in one file.
  const FilePair mixed{"exr_half_float", dir() / "h.exr", dir() / "f.exr"};
  image::writeExrImage(mixed.a, base, names(3), true);
  image::writeExrImage(mixed.b, base, names(3), false);
  compare({mixed}, kHdrOptions);
}

TEST_F(IdiffConformance, ExrDifferentSizeOrChannels) {
  const ImageF base = hdrGradient(20, 10, 3);
  compare({exr("exr_taller", base, hdrGradient(20, 11, 3)), exr("exr_wider", hdrGradient(21, 10, 3), base),
           exr("exr_rgb_rgba", base, hdrGradient(20, 10, 4)), exr("exr_rgba_rgb", hdrGradient(20, 10, 4), base),
           exr("exr_y_rgb", hdrGradient(20, 10, 1), base)},
          kHdrOptions, false);
}

TEST_F(IdiffConformance, HdrAndPfmPairs) {
  const ImageF base = hdrGradient(20, 10, 3);
  std::vector<FilePair> pairs;
  const auto add = [&](const std::string& name, const ImageF& a, const ImageF& b) {
    pairs.push_back({name + "_hdr", dir() / (name + "_a.hdr"), dir() / (name + "_b.hdr")});
    writeHdr(pairs.back().a, a);
    writeHdr(pairs.back().b, b);
    pairs.push_back({name + "_pfm", dir() / (name + "_a.pfm"), dir() / (name + "_b.pfm")});
    writePfmImage(pairs.back().a, a);
    writePfmImage(pairs.back().b, b);
  };
  add("equal", base, base);
  add("noise", base, noisy(base, 0.3f, 5));
  add("edge_shifted", edge(10), edge(11));
  compare(pairs, kHdrOptions);
}

// -p: colour differences swept across the perceptual threshold (each column's red a step further from the grey),
// a brightness difference, and noise.
TEST_F(IdiffConformance, Perceptual) {
  Image8 grey(20, 10, 3), reddish(20, 10, 3), light(20, 10, 3);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 20; ++x)
      for (int c = 0; c < 3; ++c) {
        grey.at(x, y, c) = 120;
        reddish.at(x, y, c) = std::uint8_t(c == 0 ? 120 + 3 * x : 120);
        light.at(x, y, c) = 200;
      }
  Image8 bw_noise = gradient(20, 10, 3);
  for (std::size_t i = 0; i < bw_noise.pixels.size(); i += 4)
    bw_noise.pixels[i] = std::uint8_t(bw_noise.pixels[i] ^ 0x30);
  compare({png("p_equal", grey, grey), png("p_red_sweep", grey, reddish), png("p_brighter", grey, light),
           png("p_noise", gradient(20, 10, 3), bw_noise), png("p_black_white", Image8(20, 10, 3), light)},
          kPerceptualOptions);
  const ImageF base = hdrGradient(20, 10, 3);
  compare({exr("p_exr_noise", base, noisy(base, 0.5f, 2))}, kPerceptualOptions);
  // Where -p decides: 2 pixels fail the numbers (within --failpercent) while a red sweep too small for --fail 0.3
  // crosses the perceptual threshold part of the way (idiff 2.4 counts 92 of 200): the same count, report and exit
  // codes on either side of it, and without -p.
  Image8 sweep(20, 10, 3), fine(20, 10, 3);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 20; ++x)
      for (int c = 0; c < 3; ++c) {
        const bool far = y == 0 && x < 2;
        sweep.at(x, y, c) = std::uint8_t(far ? (c == 1 ? 220 : 120) : c == 0 ? 120 + 3 * x : 120);
        fine.at(x, y, c) = std::uint8_t(far ? (c == 1 ? 220 : 120) : c == 2 ? 120 + x + 2 * y : 120);
      }
  compare({png("p_red_sweep_decides", grey, sweep), png("p_blue_sweep_decides", grey, fine)},
          {"-p --fail 0.3 --failpercent 10", "-p --fail 0.3 --failpercent 40", "-p --fail 0.3 --failpercent 50",
           "-p --fail 0.3 --failpercent 70", "--fail 0.3 --failpercent 10"});
}

// The difference image and the other options of idiff's spelling: -o writes it (-od only when the images differ),
// -abs and -scale, -a on single images, -q prints nothing; same exit codes as idiff, same files written.
TEST_F(IdiffConformance, OutputOptionsInIdiffSpelling) {
  if (!idiff_) GTEST_SKIP() << "idiff (OpenImageIO's, Debian package openimageio-tools) is not on PATH";
  const Image8 base = gradient(20, 10, 3);
  const std::vector<FilePair> pairs = {png("o_equal", base, base), png("o_80px", base, raised(80, 5))};
  const fs::path log = dir() / "log.txt", idiff_log = dir() / "idiff.txt";
  for (const FilePair& p : pairs)
    for (const char* o : {"-o {}", "-od -o {}", "-abs -scale 10 -o {}", "-a -fail 0.02 -o {}", "-q",
                          "-q -fail 0.02 -warn 0.01 -warnpercent 5", "-a -v"}) {
      std::string command = o;
      const std::string files = " " + p.a.native() + " " + p.b.native();
      const auto run = [&](const std::string& program, const fs::path& difference, const fs::path& to) {
        std::string c = command;
        if (const auto at = c.find("{}"); at != std::string::npos) c.replace(at, 2, difference.string());
        return program == "idiff" ? std::system((idiff_->string() + " " + c + files + " > " + to.string()).c_str())
                                  : testing::runWobble("diff " + c + files, to);
      };
      const fs::path theirs = dir() / (p.name + "_idiff_d.png"), ours = dir() / (p.name + "_wobble_d.png");
      fs::remove(theirs), fs::remove(ours);
      const int status = run("idiff", theirs, idiff_log);
      const int got = run("wobble", ours, log);
      EXPECT_EQ(got, WIFEXITED(status) ? WEXITSTATUS(status) : -1) << p.name << " with [" << o << "]";
      EXPECT_EQ(fs::exists(ours), fs::exists(theirs)) << p.name << " with [" << o << "]: the difference image";
      EXPECT_EQ(testing::slurpFile(log), testing::slurpFile(idiff_log)) << p.name << " with [" << o << "]";
      if (o == std::string("-abs -scale 10 -o {}") && p.name == "o_80px") {  // |A - B| x 10: 5 codes -> 50
        const ImageF d = image::readImageFile(ours).image;
        EXPECT_EQ(std::lround(d.at(0, 0, 1) * 255), 50);
        EXPECT_EQ(std::lround(d.at(0, 0, 0) * 255), 0);
      }
    }
}

// What wobble diff does not do, it refuses by name: -a on a file with more than one image.
TEST_F(IdiffConformance, AllSubimagesRefusesMultiPartExr) {
  const fs::path multi = dir() / "two_parts.exr", single = dir() / "one.exr", log = dir() / "log.txt";
  const ImageF base = hdrGradient(8, 4, 3);
  image::writeExrImage(single, base, names(3), false);
  {
    std::vector<Imf::Header> headers(2, Imf::Header(8, 4));
    for (int i = 0; i < 2; ++i) {
      headers[std::size_t(i)].setName("part" + std::to_string(i));
      headers[std::size_t(i)].setType(Imf::SCANLINEIMAGE);
      headers[std::size_t(i)].channels().insert("Y", Imf::Channel(Imf::FLOAT));
    }
    Imf::MultiPartOutputFile out(multi.c_str(), headers.data(), 2);
    std::vector<float> y(8 * 4, 0.5f);
    for (int i = 0; i < 2; ++i) {
      Imf::OutputPart part(out, i);
      Imf::FrameBuffer frame;
      frame.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y.data()), sizeof(float), sizeof(float) * 8));
      part.setFrameBuffer(frame);
      part.writePixels(4);
    }
  }
  EXPECT_EQ(image::subimageCount(multi), 2);
  EXPECT_EQ(image::subimageCount(single), 1);
  EXPECT_EQ(testing::runWobble("diff -a " + multi.string() + " " + multi.string(), log), 2);
  EXPECT_NE(testing::slurpFile(log).find("holds 2 subimages"), std::string::npos) << testing::slurpFile(log);
  EXPECT_EQ(testing::runWobble("diff " + multi.string() + " " + multi.string(), log), 0);  // without -a: part 0
  EXPECT_EQ(testing::runWobble("diff -a " + single.string() + " " + single.string(), log), 0);
}

}  // namespace
}  // namespace wobble
