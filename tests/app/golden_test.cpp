// Golden images: a small render (160 x 90, 4 samples per pixel) of an early frame of each shipped scene, through
// `wobble run` (simulating and rendering in one pass), compared with tests/golden/<scene>_NNNN.png.
// Tolerance (idiff semantics, render/image_diff.h): fail when more than 1% of the pixels differ by more than 0.02
// (of full scale) or any pixel by more than 0.25. Embree may differ in the last bits across CPUs; a real change in
// geometry, camera, lighting or materials moves far more than that.
// On failure the new image and a heatmap of the per-pixel error (x 10, magma) are written to golden_failures/ next to
// the test binary, and the message holds `wobble diff`'s report and table (app/commands/diff_command.h). To accept new
// images on purpose: WOBBLE_UPDATE_GOLDENS=1 ctest -R Golden (or run app_tests with it), then look at and commit
// tests/golden/.
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>

#include "app/commands/diff_command.h"
#include "app/commands/run_command.h"
#include "render/image/image_diff.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

struct GoldenCase {
  const char* scene;
  int frame;  // early, so each case simulates well under a few seconds
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
  o.render.resolution = "160x90";
  o.render.render = "png";
  const RunReport report = runScene(o);
  ASSERT_EQ(report.frames_rendered, 1);

  const std::string name = frameName(c.scene, c.frame);
  const fs::path image = dir() / "out/frames" / (name + ".png");
  const fs::path golden = testing::sourceDir() / "tests/golden" / (name + ".png");
  if (const char* update = std::getenv("WOBBLE_UPDATE_GOLDENS"); update && std::string(update) == "1") {
    fs::create_directories(golden.parent_path());
    fs::copy_file(image, golden, fs::copy_options::overwrite_existing);
    GTEST_SKIP() << "updated " << golden;
  }
  const fs::path failures = fs::path(WOBBLE_BINARY).parent_path() / "golden_failures";
  fs::create_directories(failures);
  const fs::path kept = failures / (name + ".new.png"), difference = failures / (name + ".heatmap.png");
  render::DiffOptions tolerance;
  tolerance.fail = 0.02f;
  tolerance.fail_percent = 1;
  tolerance.hard_fail = 0.25f;
  tolerance.warn = 0.02f;  // smaller differences pass silently
  tolerance.diff_scale = 10;
  std::ostringstream log;
  const DiffReport r = runDiff({.a = golden, .b = image, .heatmap = difference, .idiff = tolerance}, log);
  if (r.worst >= render::DiffCode::Fail) {
    fs::copy_file(image, kept, fs::copy_options::overwrite_existing);
    FAIL() << name << " differs from " << golden << ":\n"
           << log.str() << diffTable(r) << "\nnew image: " << kept << "\nheatmap (x10): " << difference
           << "\nIf the change is intended: WOBBLE_UPDATE_GOLDENS=1 ctest -R Golden, then commit tests/golden/.";
  }
  fs::remove(difference);
}

INSTANTIATE_TEST_SUITE_P(ShippedScenes, Golden,
                         ::testing::Values(GoldenCase{"jelly_slope", 25}, GoldenCase{"jelly_elevator", 46},
                                           GoldenCase{"cloth_sphere", 10}, GoldenCase{"cat_jelly", 31}),
                         [](const auto& info) { return std::string(info.param.scene); });

}  // namespace
}  // namespace wobble
