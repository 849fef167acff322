// The flags' typed settings (app/scene/scene_flags.h) reach the scene as the same keys given as --set text would:
// the TOML parse of their KEY=VALUE record is the independent path. A bad value is named by its flag.
#include <gtest/gtest.h>

#include <algorithm>

#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "app/scene/scene_flags.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

const std::string kScene = R"([simulation]
duration = 0.5

[bodies.jelly]
type = "jelly"
n = 3

[colliders.floor]
type = "plane"
)";

class SceneFlagsTest : public testing::ScratchDir {
 protected:
  std::string errorFor(const std::vector<std::string>& sets, const SceneFlags& flags) {
    try {
      loadScene(write("flags.toml", kScene), sets, flags);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error";
    return "";
  }
};

void expectAll(const std::string& message, std::initializer_list<const char*> parts) {
  for (const char* part : parts)
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' missing in: " << message;
}

TEST_F(SceneFlagsTest, FlagsReadAsTheirKeysWould) {
  SceneFlags flags;
  flags.set("simulation.integrator", "--integrator", std::string("midpoint"));
  flags.set("simulation.dt", "--dt", 0.0025);
  flags.set("output.pc2", "--pc2", true);
  flags.add(renderFlagSettings(
      {.render = "png,exr", .quality = "preview", .samples_per_pixel = 8, .denoise = "off", .resolution = "64x36"}));
  const std::vector<std::string> record = flags.record();
  EXPECT_EQ(record, (std::vector<std::string>{"simulation.integrator=\"midpoint\"",
                                              "simulation.dt=0.0025000000000000001", "output.pc2=true",
                                              "render.png=true", "render.exr=true", "render.quality=\"preview\"",
                                              "render.samples=8", "render.noise_threshold=\"auto\"",
                                              "render.denoise=false", "camera.resolution=[64,36]"}));

  const fs::path file = write("flags.toml", kScene);
  const SceneFile typed = loadScene(file, {"jelly.ks=2800"}, flags);
  std::vector<std::string> sets = {"jelly.ks=2800"};
  sets.insert(sets.end(), record.begin(), record.end());
  const SceneFile text = loadScene(file, sets);
  EXPECT_EQ(typed.text, text.text);
  EXPECT_EQ(typed.picture_text, text.picture_text);
  EXPECT_EQ(typed.integrator, "midpoint");
  EXPECT_EQ(typed.dt, 0.0025);
  EXPECT_TRUE(typed.write_pc2);
  const RenderOptionsConfig& o = typed.render.options;
  EXPECT_TRUE(o.png && o.exr);
  EXPECT_EQ(o.samples_per_pixel, 8);
  EXPECT_EQ(o.min_samples, 1);            // the preview preset's, below --spp
  EXPECT_EQ(o.noise_threshold, 1.0 / 8);  // "auto", set by --spp: Cycles' max(0.001, 1 / N)
  EXPECT_FALSE(o.denoise);
  EXPECT_EQ(typed.render.camera.resolution, (std::array<int, 2>{32, 18}));  // --resolution, halved by the preset
}

// A scene without [render] renders nothing, but a flag that sets a render key asks for frames (as --set would).
TEST_F(SceneFlagsTest, ARenderFlagAsksForFrames) {
  const fs::path file = write("flags.toml", kScene);
  EXPECT_FALSE(loadScene(file).render.options.png);
  EXPECT_TRUE(loadScene(file, {}, renderFlagSettings({.samples_per_pixel = 2})).render.options.png);
  EXPECT_FALSE(loadScene(file, {}, renderFlagSettings({.render = "none"})).render.options.png);
}

// --spp N gives a converging still: the noise threshold follows the budget (Cycles' automatic threshold,
// max(0.001, 1 / N)) instead of the scene's, which was chosen for the scene's own budget (jelly_slope: 0.3 at 2).
// The scene's threshold stands without --spp, and --set render.samples keeps it (the way to choose both).
TEST_F(SceneFlagsTest, SppBringsAThresholdThatFollowsTheBudget) {
  const fs::path file = write("flags.toml", kScene + "\n[render]\nsamples = 2\nnoise_threshold = 0.3\n");
  EXPECT_EQ(loadScene(file).render.options.noise_threshold, 0.3);
  for (const int spp : {4, 64, 1024, 4096}) {
    const RenderOptionsConfig o = loadScene(file, {}, renderFlagSettings({.samples_per_pixel = spp})).render.options;
    EXPECT_EQ(o.samples_per_pixel, spp);
    EXPECT_EQ(o.noise_threshold, std::max(0.001, 1.0 / spp)) << spp;
  }
  const RenderOptionsConfig set = loadScene(file, {"render.samples=64", "render.noise_threshold=0.05"}).render.options;
  EXPECT_EQ(set.noise_threshold, 0.05);
  EXPECT_EQ(loadScene(file, {"render.samples=64", "render.noise_threshold=\"auto\""}).render.options.noise_threshold,
            1.0 / 64);
  // With --spp, a threshold given by --set wins, and the record (run.json) leaves --spp's out, so read back as
  // --set texts the settings are the same.
  const SceneFlags spp = renderFlagSettings({.samples_per_pixel = 64});
  EXPECT_EQ(loadScene(file, {"render.noise_threshold=0.05"}, spp).render.options.noise_threshold, 0.05);
  EXPECT_EQ(spp.yieldingTo({"render.noise_threshold = 0"}).record(), std::vector<std::string>{"render.samples=64"});
  expectAll(errorFor({"render.noise_threshold=\"low\""}, {}),
            {"(--set): render.noise_threshold = \"low\"", "a number in [0, 1] or \"auto\""});
}

TEST_F(SceneFlagsTest, ErrorsNameTheFlag) {
  SceneFlags dt;
  dt.set("simulation.dt", "--dt", 1e-300);
  expectAll(errorFor({}, dt), {"flags.toml (--dt): simulation.dt = 1e-300", "steps per frame"});
  SceneFlags integrator;
  integrator.set("simulation.integrator", "--integrator", std::string("rk5"));
  expectAll(errorFor({}, integrator), {"(--integrator): simulation.integrator = \"rk5\"", "must be one of"});
  // A key set by --set is still named so when a flag sets another.
  SceneFlags midpoint;
  midpoint.set("simulation.integrator", "--integrator", std::string("midpoint"));
  expectAll(errorFor({"jelly.ks=-1"}, midpoint), {"(--set): bodies.jelly.ks = -1", ">= 0"});
  expectAll(errorFor({"render=1"}, renderFlagSettings({.samples_per_pixel = 4})),
            {"--spp (render.samples=4)", "'render' is a value"});
  try {
    renderFlagSettings({.resolution = "64x"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    expectAll(e.what(), {"--resolution 64x", "WxH"});
  }
}

}  // namespace
}  // namespace wobble
