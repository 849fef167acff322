// io/text_file.h and io/number_text.h: a file read back is the bytes written, a failed read names the file and the
// OS's reason; the number formatters print what the stream formatting they replaced printed (the oracle: std::ostream
// at its default precision and at 17 digits), and the shortest form reads back as the same double.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "io/number_text.h"
#include "io/text_file.h"
#include "tests/app/scratch_dir.h"

namespace wobble {
namespace {

class TextFile : public testing::ScratchDir {};

TEST_F(TextFile, ReadsBackTheBytesWritten) {
  std::string bytes = "a = 1\r\nb = \"x\"\n";
  bytes += '\0';
  for (int c = 0; c < 256; ++c) bytes += char(c);
  std::ofstream(dir() / "bytes.txt", std::ios::binary) << bytes;
  EXPECT_EQ(io::readTextFile(dir() / "bytes.txt"), bytes);
  io::writeTextFile(dir() / "written.txt", bytes);
  EXPECT_EQ(io::readTextFile(dir() / "written.txt"), bytes);
  std::ofstream(dir() / "empty.txt");
  EXPECT_EQ(io::readTextFile(dir() / "empty.txt"), "");
}

TEST_F(TextFile, AFailedReadNamesTheFileAndTheReason) {
  const auto messageFor = [](const std::filesystem::path& path) -> std::string {
    try {
      io::readTextFile(path);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error for " << path;
    return "";
  };
  EXPECT_EQ(messageFor(dir() / "absent.txt"),
            (dir() / "absent.txt").string() + ": cannot read: No such file or directory");
  EXPECT_EQ(messageFor(dir()), dir().string() + ": cannot read: Is a directory");
}

std::string streamed(double x, int precision) {
  std::ostringstream out;
  if (precision > 0) out.precision(precision);
  out << x;
  return out.str();
}

TEST(NumberText, FormatsAsTheStreamsItReplaced) {
  const double values[] = {0,
                           -0.0,
                           1,
                           -1,
                           0.1,
                           1.0 / 3,
                           2e-3,
                           1e-300,
                           6.02214076e23,
                           1e16,
                           123456,
                           1234567,
                           0.0012,
                           1e-5,
                           33.333333333333336,
                           -2.5e-6,
                           65536,
                           std::nextafter(1.0, 2.0),
                           std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()};
  for (const double x : values) {
    EXPECT_EQ(io::formatNumber(x), streamed(x, 0)) << x;
    EXPECT_EQ(io::formatNumber(x, io::kRoundTripDigits), streamed(x, 17)) << x;
    if (!std::isfinite(x)) continue;
    EXPECT_EQ(std::stod(io::formatNumber(x, io::kRoundTripDigits)), x);
    const std::string shortest = io::shortestNumber(x);
    EXPECT_EQ(std::stod(shortest), x) << shortest;
    EXPECT_LE(shortest.size(), io::formatNumber(x, io::kRoundTripDigits).size()) << x;
  }
  EXPECT_EQ(io::shortestNumber(0.0012), "0.0012");
  EXPECT_EQ(io::formatNumber(0.0012, io::kRoundTripDigits), "0.0011999999999999999");
}

}  // namespace
}  // namespace wobble
