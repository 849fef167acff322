// `wobble study render` on a shipped frame (small): the denoised image's error against the reference is lower than the
// noisy one's, Sobol's error falls faster with spp than independent samples', the reference is cached and reused, and
// the outputs (CSV, Markdown, images, the exported frame) are written; bad options are bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include "app/scene/input_error.h"
#include "app/study/study_render_report.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

class RenderStudy : public testing::ScratchDir {
 protected:
  RenderStudyOptions options() const {
    RenderStudyOptions o;
    o.scene = testing::sourceDir() / "scenes/cat_jelly.toml";  // the textured jelly on the wooden slope
    o.frame = 31;
    o.resolution = "96x54";
    o.reference_spp = 512;
    o.max_spp = 16;
    o.variants = {"independent", "sobol", "sobol+denoise"};
    o.out = dir() / "study";
    o.progress = false;
    return o;
  }
};

const RenderPoint& point(const RenderStudyResult& r, const std::string& variant, int spp) {
  const auto it = std::find_if(r.points.begin(), r.points.end(),
                               [&](const RenderPoint& p) { return p.variant == variant && p.spp == spp; });
  if (it == r.points.end())
    throw std::runtime_error("no study point " + variant + " at " + std::to_string(spp) + " spp");
  return *it;
}

double slope(const RenderStudyResult& r, const std::string& variant) {
  for (const RenderVariantFit& f : r.fits)
    if (f.variant == variant) return f.slope;
  ADD_FAILURE() << "no fit for " << variant;
  return 0;
}

TEST_F(RenderStudy, DenoisingAndSobolLowerTheErrorOnAShippedFrame) {
  const RenderStudyResult r = runRenderStudy(options());
  ASSERT_EQ(r.points.size(), 15u);  // 3 variants x 1, 2, 4, 8, 16 spp
  EXPECT_LT(r.reference_rmse, 0.004);
  for (int spp : {1, 2, 4}) {
    const RenderPoint &noisy = point(r, "sobol", spp), &denoised = point(r, "sobol+denoise", spp);
    EXPECT_LT(denoised.rmse, 0.8 * noisy.rmse) << spp << " spp";
    EXPECT_LT(denoised.relmse, noisy.relmse) << spp << " spp";
    EXPECT_EQ(noisy.mean_spp, spp);
  }
  // Independent samples converge as spp^-1/2; Owen-scrambled Sobol points faster.
  EXPECT_NEAR(slope(r, "independent"), -0.5, 0.1);
  EXPECT_LT(slope(r, "sobol"), slope(r, "independent") - 0.08);
  EXPECT_LT(point(r, "sobol", 16).rmse, point(r, "independent", 16).rmse);

  const fs::path out = dir() / "study";
  writeRenderStudyOutputs(r, out, "no-such-gnuplot");
  for (const char* file : {"render.csv", "render.md", "reference.png", "images/sobol-denoise_4.png", "frame/scene.obj",
                           "frame/scene.json"})
    EXPECT_TRUE(fs::exists(out / file)) << file;
  EXPECT_TRUE(fs::exists(r.reference_file));
  std::ifstream csv(out / "render.csv");
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 16);

  // A second study of the same frame reads the reference from the cache: the same errors, no reference render.
  RenderStudyOptions again = options();
  again.variants = {"sobol"};
  again.max_spp = 1;
  const RenderStudyResult cached = runRenderStudy(again);
  EXPECT_TRUE(cached.reference_cached);
  EXPECT_EQ(cached.points.front().rmse, point(r, "sobol", 1).rmse);
}

TEST_F(RenderStudy, BadOptionsAreBadInput) {
  const auto fails = [&](auto change) {
    RenderStudyOptions o = options();
    change(o);
    EXPECT_THROW(runRenderStudy(o), InputError);
    EXPECT_FALSE(fs::exists(dir() / "study"));
  };
  fails([](RenderStudyOptions& o) { o.variants = {"sobol", "magic"}; });
  fails([](RenderStudyOptions& o) { o.reference_spp = 3; });
  fails([](RenderStudyOptions& o) { o.max_spp = 0; });
  fails([](RenderStudyOptions& o) { o.thresholds = {0.1, -1}; });
  fails([](RenderStudyOptions& o) { o.frame = 100000; });
  fails([](RenderStudyOptions& o) { o.resolution = "96"; });
}

}  // namespace
}  // namespace wobble
