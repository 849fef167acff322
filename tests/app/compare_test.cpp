// `wobble compare` end to end, through the wobble binary: each variant's folder is what a plain `wobble run` of it
// writes (run.json, OBJs); bad --vary input is exit 2 with nothing written; a variant that blows up is frozen on its
// last frame with a red label from the first frame it did not reach (checked on the decoded PNGs against its
// run.json), the video has every frame at the grid's size (ffprobe); a tile is the picture the plain run renders at
// that size, through the run's follow camera, with --quality preview and --frames.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>

#include "app/output/external_program.h"
#include "image/image_diff.h"
#include "image/png_io.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using testing::runWobble;
using testing::slurpFile;

nlohmann::json runJson(const fs::path& folder) {
  nlohmann::json j = nlohmann::json::parse(slurpFile(folder / "run.json"));
  j.erase("wall_time_seconds");  // the only field that may differ between two runs of the same thing
  return j;
}

// Pixels (x0..x1) x (y0..y1) of an RGB image.
image::Image8 crop(const image::Image8& image, int x0, int y0, int x1, int y1) {
  image::Image8 part(x1 - x0, y1 - y0, 3);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      for (int c = 0; c < 3; ++c) part.at(x - x0, y - y0, c) = image.at(x, y, c);
  return part;
}

// Pixels in the rectangle that are the labels' red (kBlewUpColor over the label's dark box).
int redPixels(const image::Image8& image, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) n += image.at(x, y, 0) > 180 && image.at(x, y, 1) < 100 && image.at(x, y, 2) < 100;
  return n;
}

class Compare : public testing::ScratchDir {
 protected:
  int wobble(const std::string& arguments) { return runWobble(arguments, dir() / "log.txt"); }
  std::string log() const { return slurpFile(dir() / "log.txt"); }
  fs::path out() const { return dir() / "out"; }

  // A small blue jelly dropped on a checked floor; the camera follows it (unless told otherwise). 6 frames.
  fs::path scene(const std::string& camera = "follow = \"jelly\"") {
    return write("small.toml", R"([simulation]
dt = 0.002
duration = 0.3
fps = 20

[bodies.jelly]
type = "jelly"
n = 3
size = 1.0
center = [0, 0.8, 0]
ks = 1000
kd = 5
color = [0.2, 0.5, 0.9]  # blue: only the labels are red

[colliders.floor]
type = "plane"
size = 10
texture = "checker"

[camera]
position = [1, 2, 4]
look_at = [0, 0.5, 0]
)" + camera + R"(

[render]
samples = 2
)");
  }
};

// Each variant's folder is a plain `wobble run` of it: the same run.json (but for wall times) and the same OBJs.
// With --render none there are no pictures, only compare.md, which lists every variant with its outcome.
TEST_F(Compare, EveryVariantIsThePlainRunOfIt) {
  const fs::path s = scene();
  ASSERT_EQ(wobble("compare " + s.string() + " --out " + out().string() +
                   " --vary integrator=midpoint,rk4 --vary jelly.ks=800,3000 --set jelly.kd=2 --render none --jobs 2"),
            0)
      << log();
  const char* folders[] = {"1_midpoint_800", "2_midpoint_3000", "3_rk4_800", "4_rk4_3000"};
  const char* integrators[] = {"midpoint", "midpoint", "rk4", "rk4"};
  const char* ks[] = {"800", "3000", "800", "3000"};
  const std::string md = slurpFile(out() / "compare.md");
  for (int i = 0; i < 4; ++i) {
    const fs::path plain = dir() / ("plain" + std::to_string(i));
    const std::string flags =
        "--integrator " + std::string(integrators[i]) + " --set jelly.kd=2 --set jelly.ks=" + ks[i] + " --render none";
    ASSERT_EQ(wobble("run " + s.string() + " " + flags + " --out " + plain.string()), 0) << log();
    const fs::path variant = out() / folders[i];
    ASSERT_TRUE(fs::exists(variant / "run.json")) << variant;
    EXPECT_EQ(runJson(variant), runJson(plain)) << folders[i];
    for (const char* obj : {"mesh/jelly_0001.obj", "mesh/jelly_0006.obj"})
      EXPECT_TRUE(slurpFile(variant / obj) == slurpFile(plain / obj)) << folders[i] << "/" << obj;
    EXPECT_NE(md.find(std::string("`") + folders[i] + "/`"), std::string::npos) << md;
    EXPECT_NE(md.find(flags + " --out " + variant.string()), std::string::npos) << "the plain run in\n" << md;
  }
  EXPECT_NE(md.find("| midpoint, dt = 2e-3, kd = 2, ks = 3000 | midpoint | 0.002 | 125 |"), std::string::npos) << md;
  EXPECT_NE(md.find("stable"), std::string::npos);
  EXPECT_FALSE(fs::exists(out() / "frames"));
  EXPECT_FALSE(fs::exists(out() / "compare.mp4"));
}

// Bad --vary input: exit 2, the message naming the flag, and nothing written, also when only a later variant is bad.
TEST_F(Compare, BadVaryIsBadInputAndWritesNothing) {
  const fs::path s = scene();
  const std::pair<std::string, std::string> cases[] = {
      {"--vary jelly.nope=1,2", "nope"},                     // unknown key: the reader's message
      {"--vary jelly.ks=soft,1e4", "--vary jelly.ks=soft"},  // wrong type
      {"--vary dt=fast,1e-3", "dt 'fast' is not a number"},
      {"--vary dt=1e-3,-1", "--vary dt=-1"},  // out of range: the reader's check
      {"--vary integrator=", "an empty list of values"},
      {"--vary integrator=rk4,nope", "--vary integrator=nope (variant 2 of 2)"},
      {"--vary integrator=rk4,midpoint --integrator rk4", "also set by --integrator"},
      {"--vary jelly.ks=1,2 --vary jelly.kd=1,2 --vary dt=1e-3,2e-3", "at most two"},
      {"--render none", "--vary is required"},
      {"--vary integrator=rk4,midpoint --set jelly.nope=1", "unknown key 'bodies.jelly.nope'"},  // a shared flag
  };
  for (const auto& [flags, message] : cases) {
    EXPECT_EQ(wobble("compare " + s.string() + " --out " + out().string() + " " + flags), 2) << flags << "\n" << log();
    EXPECT_NE(log().find(message), std::string::npos) << flags << ": expected '" << message << "' in\n" << log();
    EXPECT_FALSE(fs::exists(out())) << flags;
  }
}

// explicit Euler blows up on a stiff jelly where RK4 does not. Its tile keeps its last frame (the same pixels below
// the label) with a red label from the first frame it did not reach, as its run.json says; RK4's tile never turns
// red. The video has every frame, at the grid's size.
TEST_F(Compare, BlownUpVariantIsFrozenAndLabelledFromTheRightFrame) {
  const fs::path s = scene("");  // a fixed camera
  ASSERT_EQ(wobble("compare " + s.string() + " --out " + out().string() +
                   " --vary integrator=rk4,explicit-euler --set jelly.ks=3e4 --set jelly.kd=0 --dt 4e-3"
                   " --resolution 256x144"),
            0)
      << log();
  const nlohmann::json euler = nlohmann::json::parse(slurpFile(out() / "2_explicit-euler/run.json"));
  ASSERT_TRUE(euler["blew_up"].get<bool>()) << euler.dump(2);
  ASSERT_FALSE(nlohmann::json::parse(slurpFile(out() / "1_rk4/run.json"))["blew_up"].get<bool>());
  const int last = euler["frames"]["written"].get<int>();  // its last good frame
  ASSERT_GE(last, 2) << "the scene should blow up after a few frames";
  ASSERT_LT(last, 6);

  const int tile_w = 128, tile_h = 72;  // 1 x 2 tiles of 16:9 in 256 x 144
  const auto frame = [&](int k) {
    return image::readImage(out() / ("frames/compare_000" + std::to_string(k) + ".png"));
  };
  const image::Image8 good = frame(last);
  ASSERT_EQ(good.width, 2 * tile_w);
  ASSERT_EQ(good.height, tile_h);
  const image::Image8 frozen = crop(good, tile_w, tile_h / 2, 2 * tile_w, tile_h);  // below the label
  EXPECT_NE(crop(frame(last - 1), tile_w, tile_h / 2, 2 * tile_w, tile_h).pixels, frozen.pixels) << "it moved before";
  for (int k = 1; k <= 6; ++k) {
    const image::Image8 image = frame(k);
    const int red = redPixels(image, tile_w, 0, 2 * tile_w, tile_h / 2);
    if (k <= last) {
      EXPECT_EQ(red, 0) << "frame " << k << ": not blown up yet";
    } else {
      EXPECT_GT(red, 20) << "frame " << k << ": the red label";
      EXPECT_EQ(crop(image, tile_w, tile_h / 2, 2 * tile_w, tile_h).pixels, frozen.pixels) << "frame " << k;
    }
    EXPECT_EQ(redPixels(image, 0, 0, tile_w, tile_h), 0) << "frame " << k << ": rk4 holds";
  }
  const std::string md = slurpFile(out() / "compare.md");
  EXPECT_NE(md.find("blew-up | t = "), std::string::npos) << md;
  EXPECT_NE(md.find("step " + std::to_string(euler["blow_up"]["step"].get<long>())), std::string::npos) << md;

  if (!findProgram("ffprobe")) GTEST_SKIP() << "ffprobe is not installed";
  const fs::path probe = dir() / "probe.txt";
  const std::string command =
      "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
      "stream=width,height,nb_read_frames -of default=nw=1 " +
      (out() / "compare.mp4").string() + " > " + probe.string();
  ASSERT_EQ(std::system(command.c_str()), 0);
  const std::string info = slurpFile(probe);
  for (const char* expected : {"width=256", "height=72", "nb_read_frames=6"})
    EXPECT_NE(info.find(expected), std::string::npos) << expected << " in\n" << info;
}

// One variant's tile is the picture its plain run renders at that size (below the label): the follow camera has
// seen the frames before --frames too, and --quality preview halves the picture as it does a run's.
TEST_F(Compare, TileIsThePlainRunsPicture) {
  const fs::path s = scene();
  const std::string common = " --resolution 256x144 --quality preview --frames 3:5";
  ASSERT_EQ(wobble("compare " + s.string() + " --out " + out().string() + " --vary jelly.kd=2" + common), 0) << log();
  ASSERT_EQ(wobble("run " + s.string() + " --out " + (dir() / "plain").string() + " --set jelly.kd=2" + common), 0)
      << log();
  EXPECT_FALSE(fs::exists(out() / "frames/compare_0002.png"));
  image::DiffOptions tolerance;  // the tiles are drawn from the OBJ files' float text: only rounding may differ
  tolerance.fail = 2.5f / 255;
  tolerance.fail_percent = 0.5f;
  for (int k = 3; k <= 5; ++k) {
    const image::Image8 tile = image::readImage(out() / ("frames/compare_000" + std::to_string(k) + ".png"));
    const image::Image8 run = image::readImage(dir() / ("plain/frames/small_000" + std::to_string(k) + ".png"));
    ASSERT_EQ(tile.width, 128);
    ASSERT_EQ(tile.height, 72);
    ASSERT_TRUE(tile.sameShape(run));
    const image::DiffResult r = image::diffImages(image::toFloat(crop(tile, 0, 36, 128, 72)),
                                                  image::toFloat(crop(run, 0, 36, 128, 72)), tolerance);
    EXPECT_LE(r.exitCode(), 1) << "frame " << k << ": " << r.message;
    EXPECT_NE(crop(tile, 0, 0, 128, 30).pixels, crop(run, 0, 0, 128, 30).pixels) << "frame " << k << ": the label";
  }
}

// With camera.shutter the tiles are motion-blurred as `wobble render` blurs an OBJ sequence (the poses blended from
// the frame before, the follow camera moving over the shutter): each tile is that render of the variant's OBJs (up
// to rounding: the tiles' camera follows the simulated states, a render's the OBJ text), and differs from the
// unblurred tile where the jelly moves. Frame 1 has no frame before it and is still.
TEST_F(Compare, TilesHonourTheShutter) {
  const fs::path s = scene();
  const std::string common = " --resolution 256x144 --quality preview --frames 1:4";
  ASSERT_EQ(wobble("compare " + s.string() + " --out " + out().string() + " --vary jelly.kd=2" + common +
                   " --set camera.shutter=0.5"),
            0)
      << log();
  const fs::path still = dir() / "still";
  ASSERT_EQ(wobble("compare " + s.string() + " --out " + still.string() + " --vary jelly.kd=2" + common), 0) << log();
  fs::path variant;
  for (const auto& entry : fs::directory_iterator(out()))
    if (fs::exists(entry.path() / "mesh")) variant = entry.path();
  ASSERT_FALSE(variant.empty());
  ASSERT_EQ(wobble("render " + (variant / "mesh").string() + " --scene " + s.string() + " --out " +
                   (dir() / "again").string() +
                   " --set jelly.kd=2 --set camera.shutter=0.5 --resolution 128x72 --frames 1:4"),
            0)
      << log();
  image::DiffOptions tolerance;
  tolerance.fail = 2.5f / 255;
  tolerance.fail_percent = 0.5f;
  for (int k = 1; k <= 4; ++k) {
    const std::string n = "000" + std::to_string(k) + ".png";
    const image::Image8 tile = image::readImage(out() / ("frames/compare_" + n));
    const image::Image8 rendered = image::readImage(dir() / ("again/frames/small_" + n));
    const image::Image8 unblurred = image::readImage(still / ("frames/compare_" + n));
    ASSERT_EQ(tile.width, 128);
    ASSERT_TRUE(tile.sameShape(rendered));
    const image::DiffResult r = image::diffImages(image::toFloat(crop(tile, 0, 36, 128, 72)),
                                                  image::toFloat(crop(rendered, 0, 36, 128, 72)), tolerance);
    EXPECT_LE(r.exitCode(), 1) << "frame " << k << ": " << r.message;
    if (k == 1) EXPECT_EQ(tile.pixels, unblurred.pixels) << "frame 1 is still";
    else EXPECT_NE(crop(tile, 0, 36, 128, 72).pixels, crop(unblurred, 0, 36, 128, 72).pixels) << "frame " << k;
  }
}

}  // namespace
}  // namespace wobble
