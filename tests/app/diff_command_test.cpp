// `wobble diff` on folders (app/commands/diff_command.h): pairs by name, missing and extra files as failures, the
// worst status, heatmaps for the failing pairs only, and a JUnit report that python3's XML parser reads with one test
// case per image and the failing ones marked; FLIP through the command line; bad input: clear messages naming the
// file, idiff's exit status 4 for a file error, 2 for bad flags, nothing half-written.
#include <gtest/gtest.h>

#include <fstream>

#include "image/image_file.h"
#include "image/png_io.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using image::Image8;
using image::ImageF;

Image8 picture(int shift) {
  Image8 img(24, 16, 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = std::uint8_t(x < 12 + shift ? 30 + 5 * y : 200 - 40 * c);
  return img;
}

ImageF linear(float gain) {
  ImageF img(16, 8, 3);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = gain * (0.1f + 0.05f * float(i % 23));
  return img;
}

class DiffFolders : public testing::ScratchDir {
 protected:
  void SetUp() override {
    testing::ScratchDir::SetUp();
    fs::create_directories(golden() / "sub");
    fs::create_directories(fresh() / "sub");
    image::writePng(golden() / "same.png", picture(0));
    image::writePng(fresh() / "same.png", picture(0));
    image::writePng(golden() / "sub/edge.png", picture(0));
    image::writePng(fresh() / "sub/edge.png", picture(2));  // an edge moved by two pixels: fails
    image::writeExrImage(golden() / "frame.exr", linear(1), {"R", "G", "B"}, true);
    image::writeExrImage(fresh() / "frame.exr", linear(1), {"R", "G", "B"}, true);
    image::writePng(golden() / "gone.png", picture(0));  // missing from the new renders
    image::writePng(fresh() / "stray.png", picture(0));  // extra
    std::ofstream(golden() / ".hidden") << "skipped";
  }
  fs::path golden() const { return dir() / "golden"; }
  fs::path fresh() const { return dir() / "new"; }
  fs::path log() const { return dir() / "log.txt"; }
};

TEST_F(DiffFolders, PairsByNameWorstStatusHeatmapsAndJunit) {
  const fs::path heat = dir() / "heat", junit = dir() / "report.xml";
  const int status = testing::runWobble("diff " + golden().string() + " " + fresh().string() + " --out " +
                                            heat.string() + " --junit " + junit.string(),
                                        log());
  const std::string out = testing::slurpFile(log());
  EXPECT_EQ(status, 2) << out;
  for (const char* line : {"PASS  same.png", "FAILURE  sub/edge.png", "PASS  frame.exr", "FAILURE  gone.png: missing",
                           "FAILURE  stray.png: extra", "| image | result | details |",
                           "5 pairs: 2 pass, 0 warning, 3 failure, 0 file error"})
    EXPECT_NE(out.find(line), std::string::npos) << line << " in\n" << out;
  EXPECT_EQ(out.find(".hidden"), std::string::npos);
  // A heatmap for the failing comparison only: magma, dark where nothing changed, bright at the moved edge.
  EXPECT_TRUE(fs::exists(heat / "sub/edge.png.heatmap.png"));
  EXPECT_FALSE(fs::exists(heat / "same.png.heatmap.png"));
  EXPECT_FALSE(fs::exists(heat / "frame.exr.heatmap.png"));
  const Image8 map = image::readImage(heat / "sub/edge.png.heatmap.png");
  EXPECT_EQ(map.at(2, 2, 0), 0);     // magma's first entry: no error
  EXPECT_GT(map.at(12, 5, 0), 200);  // the moved edge
  // The JUnit report, read by python3's XML parser: one test case per image, the failing ones with <failure>.
  const fs::path summary = dir() / "junit.txt";
  const std::string python =
      "import sys, xml.etree.ElementTree as E\n"
      "root = E.parse(sys.argv[1]).getroot()\n"
      "cases = root.findall('./testsuite/testcase')\n"
      "print(root.tag, root.get('tests'), root.get('failures'), root.get('errors'))\n"
      "for c in sorted(cases, key=lambda c: c.get('name')):\n"
      "    print(c.get('name'), 'failure' if c.find('failure') is not None else 'error' if c.find('error') is not "
      "None else 'pass')\n";
  std::ofstream(dir() / "read.py") << python;
  ASSERT_EQ(std::system(
                ("python3 " + (dir() / "read.py").string() + " " + junit.string() + " > " + summary.string()).c_str()),
            0)
      << testing::slurpFile(junit);
  EXPECT_EQ(testing::slurpFile(summary),
            "testsuites 5 3 0\nframe.exr pass\ngone.png failure\nsame.png pass\nstray.png failure\nsub/edge.png "
            "failure\n")
      << testing::slurpFile(junit);
}

TEST_F(DiffFolders, FileErrorsAreTheWorstStatus) {
  std::ofstream(fresh() / "frame.exr") << "truncated";
  const fs::path junit = dir() / "report.xml";
  EXPECT_EQ(testing::runWobble("diff " + golden().string() + " " + fresh().string() + " --junit " + junit.string(),
                               log()),
            4);
  const std::string out = testing::slurpFile(log());
  EXPECT_NE(out.find("FILE ERROR  frame.exr: " + (fresh() / "frame.exr").string()), std::string::npos) << out;
  EXPECT_NE(testing::slurpFile(junit).find("<error type=\"FILE ERROR\""), std::string::npos);
}

TEST_F(DiffFolders, AnImageAgainstAFolderTakesItsNamesake) {
  EXPECT_EQ(testing::runWobble("diff " + (golden() / "sub/edge.png").string() + " " + (fresh() / "sub").string(),
                               log()),
            2);
  EXPECT_NE(testing::slurpFile(log()).find((fresh() / "sub/edge.png").string()), std::string::npos);
  EXPECT_EQ(testing::runWobble("diff " + (golden() / "same.png").string() + " " + fresh().string(), log()), 0);
}

TEST_F(DiffFolders, NothingInCommonIsAFileError) {
  fs::create_directories(dir() / "empty");
  const fs::path junit = dir() / "report.xml";
  EXPECT_EQ(testing::runWobble("diff " + golden().string() + " " + (dir() / "empty").string(), log()), 4);
  const std::string out = testing::slurpFile(log());
  EXPECT_NE(out.find("no file in common"), std::string::npos) << out;
  EXPECT_NE(out.find(golden().string()), std::string::npos) << out;
}

TEST_F(DiffFolders, FlipThresholdsAndHeatmap) {
  const std::string files = " " + (golden() / "sub/edge.png").string() + " " + (fresh() / "sub/edge.png").string();
  const fs::path heat = dir() / "flip.png";
  EXPECT_EQ(testing::runWobble("diff --metric flip" + files + " --out " + heat.string(), log()), 2);
  const std::string out = testing::slurpFile(log());
  for (const char* line : {"LDR-FLIP", "Mean: ", "Weighted median: ", "p95: ", "mean ", "FAILURE"})
    EXPECT_NE(out.find(line), std::string::npos) << line << " in\n" << out;
  EXPECT_EQ(image::readImage(heat).width, 24);
  EXPECT_EQ(testing::runWobble("diff --metric flip" + files + " --fail mean=0.9,p99=1", log()), 0);
  EXPECT_EQ(testing::runWobble("diff --metric flip" + files + " --fail 0.9 --warn max=0.01", log()), 1);
  const std::string same = " " + (golden() / "frame.exr").string() + " " + (fresh() / "frame.exr").string();
  EXPECT_EQ(testing::runWobble("diff --metric flip" + same, log()), 0);
  EXPECT_NE(testing::slurpFile(log()).find("HDR-FLIP"), std::string::npos);
}

TEST_F(DiffFolders, BadInputNamesTheFileAndWritesNothing) {
  std::ofstream(dir() / "text.png") << "not an image";
  const fs::path out = dir() / "d.png", junit = dir() / "r.xml";
  const std::string good = (golden() / "same.png").string();
  EXPECT_EQ(testing::runWobble("diff " + good + " " + (dir() / "text.png").string() + " --out " + out.string(), log()),
            4);
  EXPECT_NE(testing::slurpFile(log()).find("text.png: not an image"), std::string::npos) << testing::slurpFile(log());
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(testing::runWobble("diff " + good + " " + good + " --layer albedo", log()), 4);
  EXPECT_NE(testing::slurpFile(log()).find("has no layers"), std::string::npos);
  const std::string exr = (golden() / "frame.exr").string();
  EXPECT_EQ(testing::runWobble("diff " + exr + " " + exr + " --channels R,Q", log()), 4);
  EXPECT_NE(testing::slurpFile(log()).find("no channel 'Q'"), std::string::npos) << testing::slurpFile(log());
  EXPECT_EQ(testing::runWobble("diff --metric flip " + good + " " + good + " --fail mean=x --junit " + junit.string(),
                               log()),
            2);
  EXPECT_NE(testing::slurpFile(log()).find("--fail 'mean=x'"), std::string::npos) << testing::slurpFile(log());
  EXPECT_FALSE(fs::exists(junit));
  EXPECT_EQ(testing::runWobble("diff " + good + " " + good + " --fail lots", log()), 2);
}

}  // namespace
}  // namespace wobble
