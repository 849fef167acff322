// Golden images: a small render (160 x 90, render.samples = 4: adaptive where the scene sets render.noise_threshold,
// as jelly_slope's 0.3) of an early frame of each shipped scene, through `wobble run` (simulating and rendering in one
// pass), compared with tests/golden/<scene>_NNNN.png. The default scene is motion-blurred (camera.shutter = 0.5);
// jelly_slope_still_0025.png is it with the shutter at 0 (a shutter of 0 draws exactly what a renderer without motion
// blur drew).
// Tolerance (goldenVerdict below): fail when more than 1% of the pixels differ by more than 0.02 (of full scale) or any
// pixel by more than 0.25 (idiff semantics, image/image_diff.h), when the mean error over all values exceeds 0.004,
// or when the mean pixel error (largest over the channels) over any 8 x 8 window exceeds 0.05. idiff's rule alone
// lets a 12 x 12 patch darkened by 60 of 255 through (exactly 1% of 160 x 90, and 0.235 < 0.25) and a uniform shift
// of 0.019 (under 0.02 everywhere): the mean catches a shift, the window a local defect (GoldenTolerance checks both).
// Embree may differ in the last bits across CPUs (scattered edge pixels: a few per window, a small mean); a real
// change in geometry, camera, lighting or materials moves far more than that. (Measured when written: two renders the
// goldens' pixels, two a pixel or so off by 1 of 255, mean error under 1e-6, worst window under 0.001.)
// On failure the new image and a heatmap of the per-pixel error (x 10, magma) are written to golden_failures/ next to
// the test binary, and the message holds the verdict, `wobble diff`'s report and table (app/commands/diff_command.h).
// To accept new images on purpose: WOBBLE_UPDATE_GOLDENS=1 ctest -R Golden (or run app_tests with it), then look at and
// commit tests/golden/.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "app/commands/diff_command.h"
#include "app/commands/run_command.h"
#include "image/image_diff.h"
#include "image/png_io.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

constexpr double kMeanBound = 0.004;   // mean absolute error over all values
constexpr int kWindow = 8;             // pixels a side of the local windows
constexpr double kWindowBound = 0.05;  // mean pixel error over any window

image::DiffOptions idiffTolerance() {
  image::DiffOptions tolerance;
  tolerance.fail = 0.02f;
  tolerance.fail_percent = 1;
  tolerance.hard_fail = 0.25f;
  tolerance.warn = 0.02f;  // smaller differences pass silently
  tolerance.diff_scale = 10;
  return tolerance;
}

// The largest mean, over every kWindow x kWindow window, of the pixels' errors (largest absolute difference over the
// channels), and the window's top-left corner. Same-shaped images (the idiff rule has failed them otherwise).
double worstWindow(const image::ImageF& a, const image::ImageF& b, int& wx, int& wy) {
  const int w = a.width, h = a.height;
  // Summed-area table of the pixel errors, (w + 1) x (h + 1) with a zero first row and column.
  std::vector<double> sum(std::size_t(w + 1) * (h + 1), 0.0);
  const auto at = [&](int x, int y) -> double& { return sum[std::size_t(y) * (w + 1) + x]; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float e = 0;
      for (int c = 0; c < a.channels; ++c) e = std::max(e, std::fabs(a.at(x, y, c) - b.at(x, y, c)));
      at(x + 1, y + 1) = e + at(x, y + 1) + at(x + 1, y) - at(x, y);
    }
  double worst = 0;
  wx = wy = 0;
  for (int y = 0; y + kWindow <= h; ++y)
    for (int x = 0; x + kWindow <= w; ++x) {
      const double mean =
          (at(x + kWindow, y + kWindow) - at(x, y + kWindow) - at(x + kWindow, y) + at(x, y)) / (kWindow * kWindow);
      if (mean > worst) worst = mean, wx = x, wy = y;
    }
  return worst;
}

struct Verdict {
  bool pass = true;
  std::string message;
};

// Whether image matches golden: idiff's rule (result: its report), the mean bound and the window bound.
Verdict goldenVerdict(const image::ImageF& golden, const image::ImageF& image, const image::DiffResult& idiff) {
  Verdict v;
  std::ostringstream m;
  m << idiff.message;
  if (idiff.code >= image::DiffCode::Fail) v.pass = false;
  if (idiff.mean_error > kMeanBound) {
    v.pass = false;
    m << "\n  mean error " << idiff.mean_error << " is over " << kMeanBound;
  }
  if (golden.sameShape(image)) {
    int x = 0, y = 0;
    const double window = worstWindow(golden, image, x, y);
    m << "\n  worst " << kWindow << " x " << kWindow << " window: mean pixel error " << window << " at (" << x << ", "
      << y << ")";
    if (window > kWindowBound) {
      v.pass = false;
      m << ", over " << kWindowBound;
    }
  }
  v.message = m.str();
  return v;
}

Verdict goldenVerdict(const image::ImageF& golden, const image::ImageF& image) {
  return goldenVerdict(golden, image, image::diffImages(golden, image, idiffTolerance()));
}

// 8-bit codes as the comparison reads them (image_diff.h: times 1/255).
image::ImageF unitFloat(const image::Image8& image) {
  image::ImageF out(image.width, image.height, image.channels);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) out.pixels[i] = float(image.pixels[i]) * (1.0f / 255.0f);
  return out;
}

struct GoldenCase {
  const char* scene;
  int frame;                 // early, so each case simulates well under a few seconds
  const char* set = "";      // a key laid over the scene, if any
  const char* variant = "";  // the golden's name after the scene's, for a case with a key set
};

class Golden : public testing::ScratchDir, public ::testing::WithParamInterface<GoldenCase> {};

std::string frameName(const std::string& scene, int frame) {
  char number[16];
  std::snprintf(number, sizeof number, "_%04d", frame);
  return scene + number;
}

TEST_P(Golden, SmallRenderMatches) {
  const GoldenCase c = GetParam();
  RunOptions o;
  o.scene = testing::sourceDir() / "scenes" / (std::string(c.scene) + ".toml");
  o.out = dir() / "out";
  o.frames = std::to_string(c.frame);
  // Simulate only up to the frame: (frame + 0.5) / fps seconds hold `frame` frames (the scenes run at 30 fps).
  o.sets = {"simulation.duration=" + std::to_string((c.frame + 0.5) / 30.0), "render.video=false", "render.samples=4"};
  if (*c.set) o.sets.push_back(c.set);
  o.render.resolution = "160x90";
  o.render.render = "png";
  const RunReport report = runScene(o);
  ASSERT_EQ(report.frames_rendered, 1);

  const std::string name = frameName(std::string(c.scene) + c.variant, c.frame);
  const fs::path image = dir() / "out/frames" / (frameName(c.scene, c.frame) + ".png");
  const fs::path golden = testing::sourceDir() / "tests/golden" / (name + ".png");
  if (const char* update = std::getenv("WOBBLE_UPDATE_GOLDENS"); update && std::string(update) == "1") {
    fs::create_directories(golden.parent_path());
    fs::copy_file(image, golden, fs::copy_options::overwrite_existing);
    GTEST_SKIP() << "updated " << golden;
  }
  const fs::path failures = fs::path(WOBBLE_BINARY).parent_path() / "golden_failures";
  fs::create_directories(failures);
  const fs::path kept = failures / (name + ".new.png"), difference = failures / (name + ".heatmap.png");
  const image::DiffResult r = image::diffFiles(golden, image, idiffTolerance());
  ASSERT_NE(r.code, image::DiffCode::FileError) << r.message;
  const Verdict v = goldenVerdict(unitFloat(image::readImage(golden)), unitFloat(image::readImage(image)), r);
  if (!v.pass) {
    fs::copy_file(image, kept, fs::copy_options::overwrite_existing);
    std::ostringstream log;
    const DiffReport report = runDiff({.a = golden, .b = image, .heatmap = difference, .idiff = idiffTolerance()}, log);
    FAIL() << name << " differs from " << golden << ":\n"
           << v.message << "\n"
           << log.str() << diffTable(report) << "\nnew image: " << kept << "\nheatmap (x10): " << difference
           << "\nIf the change is intended: WOBBLE_UPDATE_GOLDENS=1 ctest -R Golden, then commit tests/golden/.";
  }
  fs::remove(difference);
}

// The comparison rejects the two defects idiff's rule alone lets through, in every golden: a 12 x 12 patch darkened by
// 60 of 255 (placed, nearest the centre, where every value is at least 60, so the patch differs by exactly that) and
// a uniform shift of 0.019; and it accepts the golden itself. (The true renders: Golden.SmallRenderMatches.)
TEST(GoldenTolerance, RejectsADarkenedPatchAndAUniformShift) {
  for (const char* name :
       {"jelly_slope_0025", "jelly_slope_still_0025", "jelly_elevator_0046", "cloth_sphere_0010", "cat_jelly_0031"}) {
    const image::ImageF golden =
        unitFloat(image::readImage(testing::sourceDir() / "tests/golden" / (std::string(name) + ".png")));
    EXPECT_TRUE(goldenVerdict(golden, golden).pass) << name;

    constexpr int kPatch = 12;
    const float dark = 60.0f / 255;
    int px = -1, py = -1;
    double best = 1e30;
    for (int y = 0; y + kPatch <= golden.height; ++y)
      for (int x = 0; x + kPatch <= golden.width; ++x) {
        float lowest = 1;
        for (int j = 0; j < kPatch; ++j)
          for (int i = 0; i < kPatch; ++i)
            for (int c = 0; c < golden.channels; ++c) lowest = std::min(lowest, golden.at(x + i, y + j, c));
        const double d = std::hypot(x + kPatch / 2 - golden.width / 2, y + kPatch / 2 - golden.height / 2);
        if (lowest >= dark && d < best) best = d, px = x, py = y;
      }
    ASSERT_GE(px, 0) << name << ": no 12 x 12 patch of values >= 60";
    image::ImageF patched = golden;
    for (int j = 0; j < kPatch; ++j)
      for (int i = 0; i < kPatch; ++i)
        for (int c = 0; c < golden.channels; ++c) patched.at(px + i, py + j, c) -= dark;
    const image::DiffResult patch_idiff = image::diffImages(golden, patched, idiffTolerance());
    EXPECT_LT(patch_idiff.code, image::DiffCode::Fail) << name << ": idiff's rule alone passes it\n"
                                                       << patch_idiff.message;
    EXPECT_FALSE(goldenVerdict(golden, patched, patch_idiff).pass)
        << name << ": darkened patch at " << px << ", " << py;

    image::ImageF shifted = golden;
    for (float& value : shifted.pixels) value += 0.019f;
    const image::DiffResult shift_idiff = image::diffImages(golden, shifted, idiffTolerance());
    EXPECT_LT(shift_idiff.code, image::DiffCode::Fail) << name << ": idiff's rule alone passes it\n"
                                                       << shift_idiff.message;
    EXPECT_FALSE(goldenVerdict(golden, shifted, shift_idiff).pass) << name << ": shifted by 0.019";
  }
}

INSTANTIATE_TEST_SUITE_P(ShippedScenes, Golden,
                         ::testing::Values(GoldenCase{"jelly_slope", 25},
                                           GoldenCase{"jelly_slope", 25, "camera.shutter=0", "_still"},
                                           GoldenCase{"jelly_elevator", 46}, GoldenCase{"cloth_sphere", 10},
                                           GoldenCase{"cat_jelly", 31}),
                         [](const auto& info) { return std::string(info.param.scene) + info.param.variant; });

}  // namespace
}  // namespace wobble
