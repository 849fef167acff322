// Image comparison: idiff 2.4's result codes on made-up images, and the difference image. (The real idiff beside
// wobble diff: tests/app/idiff_conformance_test.cpp.)
#include "image/image_diff.h"

#include <fstream>

#include <gtest/gtest.h>

#include "image/png_io.h"
#include "tests/temp_dir.h"

namespace wobble::image {
namespace {

ImageF gradient(int w = 10, int h = 10, int c = 3) {
  ImageF img(w, h, c);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k) img.at(x, y, k) = (x + 2 * y + 3 * k) / 40.0f;
  return img;
}

// Changes channel 1 of the first `n` pixels (in row order) by `delta`.
ImageF perturbed(int n, float delta) {
  ImageF img = gradient();
  for (int i = 0; i < n; ++i) img.pixels[std::size_t(i) * 3 + 1] += delta;
  return img;
}

DiffOptions thresholds(float fail, float fail_percent, float warn) {
  DiffOptions o;
  o.fail = fail;
  o.fail_percent = fail_percent;
  o.warn = warn;
  return o;
}

TEST(ImageDiff, IdenticalImagesPass) {
  const DiffResult r = diffImages(gradient(), gradient());
  EXPECT_EQ(r.code, DiffCode::Pass);
  EXPECT_EQ(r.exitCode(), 0);
  EXPECT_EQ(r.max_error, 0);
  EXPECT_EQ(r.fail_pixels, 0);
  EXPECT_NE(r.message.find("PASS"), std::string::npos);
}

TEST(ImageDiff, DifferencesWithinToleranceStillPass) {
  const DiffResult r = diffImages(gradient(), perturbed(3, 0.005f), thresholds(0.01f, 0, 0.01f));
  EXPECT_EQ(r.exitCode(), 0);
  EXPECT_NEAR(r.max_error, 0.005, 1e-6);
  EXPECT_EQ(r.max_channel, 1);
  EXPECT_EQ(r.warn_pixels, 0);
}

TEST(ImageDiff, NoFailingPixelPassesWhateverTheWarnings) {
  // idiff's first rule: at most allow_failures (0) pixels over `fail` passes, even over the warn threshold and
  // over hard_fail and hard_warn.
  DiffOptions o = thresholds(0.1f, 0, 0.004f);
  o.hard_fail = o.hard_warn = 0.001f;
  const DiffResult r = diffImages(gradient(), perturbed(3, 0.005f), o);
  EXPECT_EQ(r.exitCode(), 0);
  EXPECT_EQ(r.warn_pixels, 3);
  EXPECT_EQ(r.fail_pixels, 0);
  o.allow_failures = 3;  // and this many failing pixels pass too, by any amount
  o.fail = 0.001f;
  EXPECT_EQ(diffImages(gradient(), perturbed(3, 0.5f), o).exitCode(), 0);
  EXPECT_EQ(diffImages(gradient(), perturbed(4, 0.5f), o).exitCode(), 2);
}

TEST(ImageDiff, WarningsCountOnceSomePixelsFailWithinTheAllowance) {
  // 3 % of the pixels over `fail`, 5 % allowed: the warnings decide.
  const DiffResult r = diffImages(gradient(), perturbed(3, 0.005f), thresholds(0.004f, 5, 0.004f));
  EXPECT_EQ(r.code, DiffCode::Warning);
  EXPECT_EQ(r.exitCode(), 1);
  EXPECT_EQ(r.warn_pixels, 3);
  EXPECT_EQ(r.fail_pixels, 3);
  // Allowing 5 % warnings (3 of 100 pixels) passes.
  DiffOptions o = thresholds(0.004f, 5, 0.004f);
  o.warn_percent = 5;
  EXPECT_EQ(diffImages(gradient(), perturbed(3, 0.005f), o).exitCode(), 0);
}

TEST(ImageDiff, TooManyFailingPixelsFail) {
  // 3 % of the pixels fail: more than the 1 % allowed.
  const DiffResult r = diffImages(gradient(), perturbed(3, -0.05f), thresholds(0.01f, 1, 0.01f));
  EXPECT_EQ(r.code, DiffCode::Fail);
  EXPECT_EQ(r.exitCode(), 2);
  EXPECT_EQ(r.fail_pixels, 3);
  EXPECT_NE(r.message.find("FAILURE"), std::string::npos);
  // 5 % allowed: the failing pixels are tolerated, but they are over the warn threshold too.
  EXPECT_EQ(diffImages(gradient(), perturbed(3, -0.05f), thresholds(0.01f, 5, 0.01f)).exitCode(), 1);
}

TEST(ImageDiff, OnePixelOverTheHardLimitFails) {
  DiffOptions o = thresholds(0.1f, 50, 0.1f);
  o.warn_percent = 50;
  EXPECT_EQ(diffImages(gradient(), perturbed(1, 0.5f), o).exitCode(), 0);  // 1 % failing is allowed...
  o.hard_fail = 0.3f;
  const DiffResult r = diffImages(gradient(), perturbed(1, 0.5f), o);  // ...unless one pixel is too far off
  EXPECT_EQ(r.exitCode(), 2);
  EXPECT_EQ(r.max_x, 0);
  EXPECT_EQ(r.max_y, 0);
}

// idiff -p: pixels failing Yee's perceptual test count against --failpercent as the numeric failures do (idiff 2.4's
// rule), so the allowance decides; without -p they count for nothing. Here 3 pixels fail the numeric test (0.5 off
// against 0.3) and a further block of 30 is 0.2 off: under the numeric limit, but plainly visible.
TEST(ImageDiff, PerceptualFailuresCountAgainstTheFailPercent) {
  ImageF b = gradient();
  for (int i = 0; i < 33; ++i) b.pixels[std::size_t(i) * 3 + 1] += i < 3 ? 0.5f : 0.2f;
  DiffOptions o = thresholds(0.3f, 10, 0.3f);
  o.warn_percent = 100;
  const DiffResult numeric = diffImages(gradient(), b, o);
  EXPECT_EQ(numeric.fail_pixels, 3);
  EXPECT_EQ(numeric.perceptual_failures, 0);  // not counted without -p
  EXPECT_EQ(numeric.code, DiffCode::Pass);    // 3 of 100 failing, 10 allowed
  o.perceptual = true;
  const DiffResult perceptual = diffImages(gradient(), b, o);
  EXPECT_GT(perceptual.perceptual_failures, 10);
  EXPECT_LE(perceptual.perceptual_failures, 60);
  EXPECT_EQ(perceptual.code, DiffCode::Fail);  // more perceptual failures than the 10 allowed
  EXPECT_NE(perceptual.message.find("failed the perceptual test"), std::string::npos);
  o.fail_percent = 60;  // the same failures within the allowance: no failure
  EXPECT_EQ(diffImages(gradient(), b, o).code, DiffCode::Pass);
}

TEST(ImageDiff, DifferentSizesAreComparedOverBothWithBlackWhereMissing) {
  EXPECT_EQ(diffImages(gradient(10, 10), gradient(10, 9)).exitCode(), 2);
  EXPECT_EQ(diffImages(gradient(10, 10, 3), gradient(10, 10, 4)).exitCode(), 2);  // the alpha against 0
  ImageF padded(10, 11, 4);  // the gradient, a black row below, a black alpha channel: nothing differs
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x)
      for (int c = 0; c < 3; ++c) padded.at(x, y, c) = gradient().at(x, y, c);
  const DiffResult same = diffImages(gradient(), padded);
  EXPECT_EQ(same.exitCode(), 0);
  EXPECT_EQ(same.max_error, 0);
  EXPECT_NE(same.message.find("differ in size"), std::string::npos) << same.message;
  // Percentages are of the first image's pixels: 10 failing pixels (the taller image's last row) are 10 % of
  // 10 x 10 (over 9.5 %: fail) but 9.1 % of 10 x 11 (within it: the warnings decide).
  const DiffOptions o = thresholds(1e-6f, 9.5f, 1e-6f);
  EXPECT_EQ(diffImages(gradient(10, 10), gradient(10, 11), o).exitCode(), 2);
  EXPECT_EQ(diffImages(gradient(10, 11), gradient(10, 10), o).exitCode(), 1);
  ImageF difference;
  diffImages(gradient(10, 10), gradient(10, 11), {}, &difference);
  EXPECT_TRUE(difference.width == 10 && difference.height == 11 && difference.channels == 3);
  EXPECT_NEAR(difference.at(3, 10, 0), gradient(10, 11).at(3, 10, 0), 1e-6);
}

TEST(ImageDiff, FilesMissingFilesAndTheDifferenceImage) {
  test::TempDir dir;
  writePng(dir / "a.png", toImage8(gradient()));
  ImageF changed = gradient();
  changed.at(4, 2, 0) += 20 / 255.0f;
  writePng(dir / "b.png", toImage8(changed));
  writePng(dir / "small.png", toImage8(gradient(4, 4)));

  EXPECT_EQ(diffFiles(dir / "a.png", dir / "a.png").exitCode(), 0);
  DiffOptions o;
  o.diff_scale = 4;
  const DiffResult r = diffFiles(dir / "a.png", dir / "b.png", o, dir / "diff.png");
  EXPECT_EQ(r.exitCode(), 2);
  EXPECT_EQ(r.fail_pixels, 1);
  EXPECT_NEAR(r.max_error, 20 / 255.0, 1e-6);
  const Image8 diff = readImage(dir / "diff.png");
  ASSERT_EQ(diff.width, 10);
  EXPECT_EQ(diff.at(4, 2, 0), 80);  // 20 codes of difference, scaled by 4
  EXPECT_EQ(diff.at(4, 2, 1), 0);
  EXPECT_EQ(diff.at(3, 2, 0), 0);

  EXPECT_EQ(diffFiles(dir / "a.png", dir / "small.png").exitCode(), 2);
  const DiffResult missing = diffFiles(dir / "a.png", dir / "golden.png");
  EXPECT_EQ(missing.exitCode(), 4);
  EXPECT_NE(missing.message.find("golden.png"), std::string::npos) << missing.message;
  std::ofstream(dir / "junk.png") << "not an image";
  EXPECT_EQ(diffFiles(dir / "junk.png", dir / "a.png").exitCode(), 4);
}

}  // namespace
}  // namespace wobble::image
