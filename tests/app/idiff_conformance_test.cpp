// `wobble diff` against the real OpenImageIO idiff (Debian 12's openimageio-tools, idiff 2.4): the same image pairs
// with the same options must give the same exit code. Pairs made here: equal, a few pixels off by a little, many off,
// one far off, right at a threshold, and pairs of different size or channel count (which idiff compares over both,
// the missing values as black). Options: the defaults, only --fail, --warn below --fail, percentages, hard limits,
// --allowfailures. Skipped, saying why, where idiff is not installed. Prints the table of exit codes it compared.
#include <gtest/gtest.h>

#include <functional>
#include <iostream>
#include <map>

#include "app/output/external_program.h"
#include "render/image/png_io.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using render::Image8;

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

const std::vector<std::string> kOptions = {
    "",                                              // idiff's defaults: any difference fails
    "--fail 0.02",                                   // only --fail: no pixel over it passes
    "--warn 0.001 --fail 0.05",                      // --warn below --fail
    "--fail 0.004 --warn 0.001 --failpercent 50",    // failures within the allowance: warnings decide
    "--fail 0.005 --failpercent 10 --hardfail 0.1",  // hard limit
    "--fail 0.007843137718737125",                   // 2/255 as a float: right at the threshold
    "--allowfailures 3",
    "--failpercent 100 --warnpercent 20 --hardwarn 0.5",
};

class IdiffConformance : public testing::ScratchDir {
 protected:
  void compare(const std::map<std::string, std::pair<Image8, Image8>>& pairs) {
    const auto idiff = findProgram("idiff");
    if (!idiff) GTEST_SKIP() << "idiff (OpenImageIO's, Debian package openimageio-tools) is not on PATH";
    const fs::path log = dir() / "log.txt";
    std::ostringstream table;
    table << "idiff / wobble diff exit codes\n";
    for (const auto& [name, images] : pairs) {
      const fs::path a = dir() / (name + "_a.png"), b = dir() / (name + "_b.png");
      render::writePng(a, images.first);
      render::writePng(b, images.second);
      table << "  " << name << ":";
      for (const std::string& options : kOptions) {
        const std::string files = std::string(" ") + a.string() + " " + b.string();
        const int status =
            std::system((idiff->string() + " -q " + options + files + " > " + log.string() + " 2>&1").c_str());
        const int expected = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        const int got = testing::runWobble("diff " + options + files, log);
        EXPECT_EQ(got, expected) << name << " with [" << options << "]: " << testing::slurpFile(log);
        table << " " << expected << "/" << got;
      }
      table << "\n";
    }
    std::cout << table.str();
  }
};

TEST_F(IdiffConformance, SameSize) {
  const Image8 base = gradient(20, 10, 3);
  compare({{"equal", {base, base}},
           {"3px_2codes", {base, raised(3, 2)}},
           {"80px_5codes", {base, raised(80, 5)}},
           {"1px_60codes", {base, raised(1, 60)}},
           {"4px_2codes_swapped", {raised(4, 2), base}}});
}

TEST_F(IdiffConformance, DifferentSizeOrChannels) {
  const Image8 base = gradient(20, 10, 3);
  compare({{"taller", {base, gradient(20, 11, 3)}},
           {"taller_by_black", {base, withBlackRow(base)}},
           {"shorter_by_black", {withBlackRow(base), base}},
           {"rgb_rgba", {base, gradient(20, 10, 4)}},
           {"black_grey_rgb", {Image8(20, 10, 1), Image8(20, 10, 3)}},
           {"black_rgb_rgba", {Image8(20, 10, 3), Image8(20, 10, 4)}}});
}

}  // namespace
}  // namespace wobble
