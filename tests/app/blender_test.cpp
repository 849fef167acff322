// Blender 3.4+ (Debian's `blender`) with a run's output: the OBJ sequence imports (tests/blender/import_check.py);
// the base OBJ plus the PC2 through a Mesh Cache modifier set up by hand, as docs/blender.md says, gives the OBJ
// frames' vertices at the first, middle and last frame; `wobble blend` builds a .blend that Blender reopens with the
// bodies, their modifiers and materials, the colliders (the moving ones keyframed), the follow camera's keyframes and
// the frame range, and plays the same vertices (tests/blender/mesh_cache_check.py). Skipped, saying why, where Blender
// is not installed. Without Blender, `wobble blend` says so and fails; without point caches, it names the file.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "app/output/external_program.h"
#include "image/color_difference.h"
#include "image/image_file.h"
#include "image/png_io.h"
#include "render/environment.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"
#include "tests/app/small_scene.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using testing::runWobble;
using testing::slurpFile;

class Blender : public testing::ScratchDir {
 protected:
  // A textured jelly followed by the camera, a cloth, a floor, a moving sphere and an elevator: 12 frames.
  fs::path scene() {
    copyCatTexture();
    return write("blendable.toml", testing::smallSceneText({.duration = "0.6",
                                                            .center = "[0, 2.6, 0]",
                                                            .jelly = "color = [1.0, 0.9, 0.8]\n",
                                                            .floor = "texture = \"wood\"\n",
                                                            .rest = R"(
[bodies.sheet]
type = "cloth"
nx = 5
ny = 5
size = [1.5, 1.5]
center = [3, 1.2, 0]
color = [0.2, 0.5, 0.9]

[colliders.ball]
type = "sphere"
center = [6, 0.3, 0]   # away from the cloth: the cloth stays a cloth
radius = 0.5
velocity = [0, 0.5, 0]

[colliders.lift]
type = "elevator"
start = [-3, 0, 0]
size = 2

[camera]
follow = "jelly"
position = [2, 4, 8]
look_at = [0, 2, 0]
)"}));
  }
  int blender(const std::string& arguments, const fs::path& log) {
    const std::string command = blender_->string() + " -b " + arguments + " > " + log.string() + " 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  void SetUp() override {
    ScratchDir::SetUp();
    blender_ = findProgram("blender");
  }
  std::string script(const char* name) const { return (testing::sourceDir() / "tests/blender" / name).string(); }
  std::optional<fs::path> blender_;
};

TEST_F(Blender, ObjSequenceImports) {
  if (!blender_)
    GTEST_SKIP() << "blender is not on PATH (./setup.sh tests installs it; plain setup.sh leaves it out: it is large)";
  const fs::path out = dir() / "out", log = dir() / "log.txt";
  ASSERT_EQ(runWobble("run " + (testing::sourceDir() / "scenes/cat_jelly.toml").string() +
                          " --frames 1:4 --set simulation.duration=0.2 --render none --out " + out.string(),
                      log),
            0)
      << slurpFile(log);
  EXPECT_EQ(blender("--factory-startup --python-exit-code 1 --python " + script("import_check.py") + " -- " +
                        (out / "mesh").string(),
                    log),
            0)
      << slurpFile(log);
}

TEST_F(Blender, PointCacheByHandPlaysTheObjFrames) {
  if (!blender_)
    GTEST_SKIP() << "blender is not on PATH (./setup.sh tests installs it; plain setup.sh leaves it out: it is large)";
  const fs::path out = dir() / "out", log = dir() / "log.txt";
  ASSERT_EQ(runWobble("run " + scene().string() + " --frames 3:12 --render none --pc2 --out " + out.string(), log), 0)
      << slurpFile(log);
  for (const char* body : {"jelly", "sheet"})
    EXPECT_EQ(blender("--factory-startup --python-exit-code 1 --python " + script("mesh_cache_check.py") +
                          " -- by-hand " + out.string() + " " + body,
                      log),
              0)
        << slurpFile(log);
}

// A mesh jelly's point cache holds the model's own vertices (scenes/models/jelly_mould.obj, in the file's order), and
// the Mesh Cache modifier plays it at the OBJ frames' positions.
TEST_F(Blender, MeshJellyPointCachePlaysTheObjFrames) {
  if (!blender_)
    GTEST_SKIP() << "blender is not on PATH (./setup.sh tests installs it; plain setup.sh leaves it out: it is large)";
  const fs::path out = dir() / "out", log = dir() / "log.txt";
  ASSERT_EQ(runWobble("run " + (testing::sourceDir() / "scenes/jelly_mould.toml").string() +
                          " --frames 1:9 --set simulation.duration=0.3 --set jelly.cells=4 --render none --pc2 --out " +
                          out.string(),
                      log),
            0)
      << slurpFile(log);
  EXPECT_EQ(blender("--factory-startup --python-exit-code 1 --python " + script("mesh_cache_check.py") +
                        " -- by-hand " + out.string() + " jelly",
                    log),
            0)
      << slurpFile(log);
}

TEST_F(Blender, BlendFileReopensAndPlays) {
  if (!blender_)
    GTEST_SKIP() << "blender is not on PATH (./setup.sh tests installs it; plain setup.sh leaves it out: it is large)";
  const fs::path out = dir() / "out", log = dir() / "log.txt";
  ASSERT_EQ(runWobble("run " + scene().string() + " --render none --pc2 --out " + out.string(), log), 0)
      << slurpFile(log);
  // A relative OUT, as from the project root (`wobble blend out/<scene>`): Blender saves only to absolute paths.
  ASSERT_EQ(runWobble("blend out", log, "cd " + dir().string() + " &&"), 0) << slurpFile(log);
  EXPECT_NE(slurpFile(log).find("camera following, 12 keyframes"), std::string::npos) << slurpFile(log);
  ASSERT_TRUE(fs::is_regular_file(out / "blendable.blend"));
  for (const auto& entry : fs::directory_iterator(out))  // no manifest, script, log or partial .blend left
    if (entry.path().filename().string()[0] == '.') {
      EXPECT_EQ(entry.path().filename(), ".wobble.lock");
    }
  // Moved as a whole, the folder still plays: the .blend's paths are relative to it.
  const fs::path moved = dir() / "moved";
  fs::rename(out, moved);
  const nlohmann::json expected = {{"bodies",
                                    {{{"name", "jelly"}, {"color", {1.0, 0.9, 0.8}}, {"textured", true}},
                                     {{"name", "sheet"}, {"color", {0.2, 0.5, 0.9}}, {"textured", false}}}},
                                   {"colliders", {"floor", "ball", "lift"}},
                                   {"moving", {"ball", "lift"}},
                                   {"camera_follows", true}};
  std::ofstream(dir() / "expected.json") << expected.dump();
  EXPECT_EQ(blender((moved / "blendable.blend").string() + " --python-exit-code 1 --python " +
                        script("mesh_cache_check.py") + " -- blend " + moved.string() + " " +
                        (dir() / "expected.json").string(),
                    log),
            0)
      << slurpFile(log);
}

// Gelatine, the thin lens, the shutter and the environment map in Cycles (issue 29): tests/blender/gelatine_check.py
// reads the .blend's nodes and camera against the scene's keys; tests/blender/environment_check.py finds the map in
// the world at its strength and rotation, and renders Cycles' view along several directions: each is the radiance
// wobble's renderer sees there (EnvironmentMap::eval of the same file), so the orientation, rotation and strength
// agree.
TEST_F(Blender, GelatineLensShutterAndEnvironmentMapOntoCycles) {
  if (!blender_)
    GTEST_SKIP() << "blender is not on PATH (./setup.sh tests installs it; plain setup.sh leaves it out: it is large)";
  copyCatTexture();
  // 16 x 8 texels, each its own colour, as float RGB.
  image::ImageF map(16, 8, 3);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      map.at(x, y, 0) = 0.1f + float(x);
      map.at(x, y, 1) = 0.2f + float(y);
      map.at(x, y, 2) = 0.5f;
    }
  image::writeExrImage(dir() / "sky.exr", map, {"R", "G", "B"}, false);
  const fs::path scene = write("gel.toml", testing::smallSceneText({.duration = "0.3",
                                                                    .center = "[0, 1.6, 0]",
                                                                    .jelly = R"(material = "gelatine"
ior = 1.35
roughness = 0.1
absorption_color = [0.9, 0.5, 0.6]
absorption_depth = 0.5
scatter = 2.0
scatter_albedo = [0.9, 0.8, 0.7]
print = 0.4
)",
                                                                    .rest = R"(
[camera]
follow = "jelly"
position = [2, 3, 6]
look_at = [0, 1.5, 0]
aperture = 0.1
focus = "jelly"
shutter = 0.4

[render]
environment = "sky.exr"
environment_rotation = 60
environment_strength = 2
)"}));
  const fs::path out = dir() / "out", log = dir() / "log.txt";
  ASSERT_EQ(runWobble("run " + scene.string() + " --render none --pc2 --out " + out.string(), log), 0)
      << slurpFile(log);
  ASSERT_EQ(runWobble("blend " + out.string(), log), 0) << slurpFile(log);
  const nlohmann::json expected = {{"name", "jelly"},
                                   {"ior", 1.35},
                                   {"roughness", 0.1},
                                   {"absorption_color", {0.9, 0.5, 0.6}},
                                   {"absorption_depth", 0.5},
                                   {"scatter", 2.0},
                                   {"scatter_albedo", {0.9, 0.8, 0.7}},
                                   {"print", 0.4},
                                   {"aperture", 0.1},
                                   // The followed jelly's distance along the view at frame 1, which the follow
                                   // camera keeps: (c - p) . (l - p) / |l - p| = 42.1 / 6.5 for its centre c, the eye
                                   // p and the look_at point l above.
                                   {"focus", 42.1 / 6.5},
                                   {"shutter", 0.4},
                                   {"frames", 6}};
  std::ofstream(dir() / "expected.json") << expected.dump();
  EXPECT_EQ(blender((out / "gel.blend").string() + " --python-exit-code 1 --python " + script("gelatine_check.py") +
                        " -- " + (dir() / "expected.json").string(),
                    log),
            0)
      << slurpFile(log);
  const render::EnvironmentMap wobble = render::EnvironmentMap::load(dir() / "sky.exr", 60, 2);
  nlohmann::json probes = nlohmann::json::array();
  // Texel centres of the map, turned by the rotation: away from texel edges, where a renderer's rounding decides.
  for (const auto& [x, y] : {std::pair{8, 2}, {1, 4}, {12, 1}, {5, 6}, {15, 3}}) {
    // The texel's centre in the map: azimuth atan2(z, x) = 2 pi u - pi, polar angle pi v from +Y; turned by the
    // rotation (right-handed about +Y), its azimuth falls by 60 degrees.
    const double phi = 2 * M_PI * (x + 0.5) / 16 - M_PI - 60 * M_PI / 180, theta = M_PI * (y + 0.5) / 8;
    const Eigen::Vector3f d(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                            float(std::sin(theta) * std::sin(phi)));
    const image::Color c = wobble.eval(d);
    EXPECT_FLOAT_EQ(c.x(), 2 * map.at(x, y, 0));
    EXPECT_FLOAT_EQ(c.y(), 2 * map.at(x, y, 1));
    probes.push_back({{"direction", {d.x(), d.y(), d.z()}}, {"radiance", {c.x(), c.y(), c.z()}}});
  }
  const nlohmann::json environment = {{"file", (dir() / "sky.exr").string()},
                                      {"rotation", 60},
                                      {"strength", 2},
                                      {"probes", probes}};
  std::ofstream(dir() / "environment.json") << environment.dump();
  EXPECT_EQ(blender((out / "gel.blend").string() + " --python-exit-code 1 --python " + script("environment_check.py") +
                        " -- " + (dir() / "environment.json").string(),
                    log),
            0)
      << slurpFile(log);
}

// Shadow caustics in Cycles (issue 51): where wobble carries the sun's light through gelatine (render.caustics =
// "photons", the default), the .blend turns on Cycles' manifold next-event estimation for it: the gelatine body casts
// shadow caustics, the other body and the colliders receive them, the sun lights them; with caustics off, no flag is
// set (tests/blender/caustics_check.py reads them back in Blender).
TEST_F(Blender, GelatineCastsShadowCausticsInCycles) {
  if (!blender_)
    GTEST_SKIP() << "blender is not on PATH (./setup.sh tests installs it; plain setup.sh leaves it out: it is large)";
  copyCatTexture();
  const fs::path scene =
      write("caustic.toml",
            testing::smallSceneText(
                {.duration = "0.1", .center = "[0, 1.6, 0]", .jelly = "material = \"gelatine\"\n", .rest = R"(
[bodies.sheet]
type = "cloth"
nx = 4
ny = 4
size = [1.0, 1.0]
center = [3, 1.0, 0]

[colliders.ball]
type = "sphere"
center = [-3, 0.5, 0]
radius = 0.5
)"}));
  const fs::path log = dir() / "log.txt";
  for (const bool on : {true, false}) {
    const fs::path out = dir() / (on ? "on" : "off");
    ASSERT_EQ(runWobble("run " + scene.string() + " --render none --pc2 --out " + out.string() +
                            (on ? "" : " --set render.caustics=off"),
                        log),
              0)
        << slurpFile(log);
    ASSERT_EQ(runWobble("blend " + out.string(), log), 0) << slurpFile(log);
    const nlohmann::json expected = {{"casters", on ? nlohmann::json{"jelly"} : nlohmann::json::array()},
                                     {"receivers",
                                      on ? nlohmann::json{"sheet", "floor", "ball"} : nlohmann::json::array()},
                                     {"lights", on ? nlohmann::json{"sun"} : nlohmann::json::array()}};
    std::ofstream(dir() / "expected.json") << expected.dump();
    EXPECT_EQ(blender((out / "caustic.blend").string() + " --python-exit-code 1 --python " +
                          script("caustics_check.py") + " -- " + (dir() / "expected.json").string(),
                      log),
              0)
        << (on ? "caustics on: " : "caustics off: ") << slurpFile(log);
  }
}

// Cycles renders the .blend as wobble renders the scene (issue 51): a small frame of a textured, coated jelly on a
// wooden slope turned about two axes (its square's orientation and its planks show), a checked ball, wobble's sky,
// sun and tone curve, at 128 x 72. wobble renders it with 64 samples a pixel (no adaptive stop, no denoiser) and
// Cycles from the .blend with 64 (no adaptive stop, seed 1); the mean CIE76 difference of the two PNGs must be at
// most 2.5, the issue's bound for converged pictures. Measured with Blender 3.4.1: 1.44 (mostly both renderers' noise
// at 64 samples); without the tone curve (Blender's default Filmic view) 5.65, with the compositor off (the Standard
// view of the radiance) 4.0, the floor's UVs turned by 90 degrees 3.1, a flat blue sky for wobble's 5.7.
TEST_F(Blender, CyclesRendersTheBlendAsWobbleRendersTheScene) {
  if (!blender_)
    GTEST_SKIP() << "blender is not on PATH (./setup.sh tests installs it; plain setup.sh leaves it out: it is large)";
  copyCatTexture();
  const fs::path scene = write("lookalike.toml", testing::smallSceneText({.duration = "0.1",
                                                                          .center = "[0, 1.3, 0]",
                                                                          .jelly = "color = [1.0, 0.9, 0.8]\n",
                                                                          .floor_name = "slope",
                                                                          .floor = R"(normal = [0.25, 1.0, 0.15]
size = 12
texture = "wood"
texture_scale = 3
)",
                                                                          .rest = R"(
[colliders.ball]
type = "sphere"
center = [-1.8, 0.8, -0.5]
radius = 0.6
texture = "checker"

[camera]
position = [3, 3.5, 6]
look_at = [0, 0.8, 0]
resolution = [128, 72]
)"}));
  const fs::path out = dir() / "out", log = dir() / "log.txt";
  ASSERT_EQ(runWobble("run " + scene.string() + " --pc2 --spp 64 --denoise off --set render.noise_threshold=0 --out " +
                          out.string(),
                      log),
            0)
      << slurpFile(log);
  ASSERT_EQ(runWobble("blend " + out.string(), log), 0) << slurpFile(log);
  EXPECT_TRUE(fs::is_regular_file(out / "blender/slope.png"));  // the wood, baked beside the .blend
  EXPECT_TRUE(fs::is_regular_file(out / "blender/ball.png"));
  const std::string settings =
      "import bpy; s = bpy.context.scene; s.cycles.samples = 64; s.cycles.use_adaptive_sampling = False; "
      "s.cycles.seed = 1; s.cycles.use_animated_seed = False; s.render.threads_mode = 'FIXED'; s.render.threads = 2";
  ASSERT_EQ(blender((out / "lookalike.blend").string() + " --python-expr \"" + settings + "\" -o " +
                        (dir() / "cycles_####").string() + " -F PNG -f 2",
                    log),
            0)
      << slurpFile(log);
  const image::Image8 wobble = image::readImage(out / "frames/lookalike_0002.png");
  const image::Image8 cycles = image::readImage(dir() / "cycles_0002.png");
  const image::ColorDifference d = image::cie76(wobble, cycles);
  std::printf("wobble against Cycles: mean CIE76 %.2f (95th percentile %.2f)\n", d.mean, d.p95);
  EXPECT_LE(d.mean, 2.5);
}

// A file the .blend needs that cannot be written (a baked texture, an environment map's copy: here a file stands where
// OUT/blender/ should be) is an I/O error, exit 1, naming the file; no .blend is left, half-written or not. Written,
// the file is referenced by its path relative to the .blend, and --pack puts it inside.
TEST_F(Blender, UnwritableFilesForTheBlendAreAnIoErrorAndLeaveNoBlend) {
  if (!blender_)
    GTEST_SKIP() << "blender is not on PATH (./setup.sh tests installs it; plain setup.sh leaves it out: it is large)";
  image::ImageF map(8, 4, 3);
  image::writeExrImage(dir() / "sky.exr", map, {"R", "G", "B"}, false);
  const std::string head = R"([simulation]
dt = 0.002
duration = 0.1
fps = 20

[bodies.jelly]
type = "jelly"
n = 3
)";
  for (const auto& [name, tail, file] :
       {std::tuple{"wood", "[colliders.floor]\ntype = \"plane\"\ntexture = \"wood\"\n", "floor.png"},
        std::tuple{"environment",
                   "[colliders.floor]\ntype = \"plane\"\ntexture = \"none\"\n\n[render]\nenvironment = \"sky.exr\"\n",
                   "sky.exr"}}) {
    const fs::path scene = write(std::string(name) + ".toml", head + "\n" + tail);
    const fs::path out = dir() / name, log = dir() / "log.txt";
    ASSERT_EQ(runWobble("run " + scene.string() + " --pc2 --render none --out " + out.string(), log), 0)
        << slurpFile(log);
    std::ofstream(out / "blender") << "in the way\n";
    EXPECT_EQ(runWobble("blend " + out.string(), log), 1) << slurpFile(log);
    EXPECT_NE(slurpFile(log).find((out / "blender" / file).string() + ": cannot write"), std::string::npos)
        << slurpFile(log);
    for (const auto& entry : fs::directory_iterator(out)) EXPECT_NE(entry.path().extension(), ".blend") << entry.path();
    for (const auto& entry : fs::directory_iterator(out)) {  // nothing half-written under a hidden name either
      if (entry.path().filename().string()[0] == '.') {
        EXPECT_EQ(entry.path().filename(), ".wobble.lock");
      }
    }
    fs::remove(out / "blender");  // writable again: the same command builds the .blend
    EXPECT_EQ(runWobble("blend " + out.string(), log), 0) << slurpFile(log);
    EXPECT_TRUE(fs::is_regular_file(out / "blender" / file));
    EXPECT_TRUE(fs::is_regular_file(out / (std::string(name) + ".blend")));
    // --pack: the image (the baked wood, the map's copy) is inside the .blend, under its relative path.
    EXPECT_EQ(runWobble("blend --pack " + out.string(), log), 0) << slurpFile(log);
    EXPECT_EQ(blender((out / (std::string(name) + ".blend")).string() +
                          " --python-exit-code 1 --python-expr \"import bpy; i = [x for x in bpy.data.images if "
                          "x.filepath == '//blender/" +
                          file +
                          "']; assert len(i) == 1 and i[0].packed_file, "
                          "[(x.filepath, x.packed_file) for x in bpy.data.images]\"",
                      log),
              0)
        << slurpFile(log);
  }
}

TEST_F(Blender, BlendNeedsBlenderAndThePointCaches) {
  const fs::path out = dir() / "out", log = dir() / "log.txt";
  ASSERT_EQ(runWobble("run " + scene().string() + " --frames 1:2 --render none --out " + out.string(), log), 0)
      << slurpFile(log);
  EXPECT_EQ(runWobble("blend " + out.string(), log), 2);  // no --pc2: names the missing cache and the fix
  EXPECT_NE(slurpFile(log).find((out / "mesh/jelly.pc2").string() + ": not found"), std::string::npos)
      << slurpFile(log);
  EXPECT_NE(slurpFile(log).find("--pc2"), std::string::npos) << slurpFile(log);
  EXPECT_EQ(runWobble("blend " + (dir() / "nowhere").string(), log), 2);
  EXPECT_NE(slurpFile(log).find("no run.json"), std::string::npos) << slurpFile(log);

  ASSERT_EQ(runWobble("run " + scene().string() + " --frames 1:2 --render none --pc2 --out " + out.string(), log), 0);
  EXPECT_EQ(runWobble("blend " + out.string(), log, "PATH=/nonexistent"), 1);
  EXPECT_NE(slurpFile(log).find("blender not found on PATH"), std::string::npos) << slurpFile(log);
  EXPECT_FALSE(fs::exists(out / "blendable.blend"));
}

}  // namespace
}  // namespace wobble
