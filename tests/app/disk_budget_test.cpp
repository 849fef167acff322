// The disk budget (app/output/disk_budget.h): the per-file bounds hold for incompressible pictures; the estimate of a
// small run is not below the bytes it really wrote and, for meshes and point caches, at most 3 times them (pictures
// are bounded by their uncompressed size only); the free space is what df says; and runs that would flood the disk
// (fps = 1e6, a 16384 x 10 cloth at fps 65536) are refused at once with exit 2 and nothing written, by --max-disk so
// that the test does not depend on this machine's disk. `wobble render` is held to the same budget.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <random>

#include "app/commands/run_command.h"
#include "app/output/disk_budget.h"
#include "app/output/picture_key.h"
#include "image/exr_writer.h"
#include "image/file_size_bound.h"
#include "image/png_io.h"
#include "io/content_hash.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using testing::runWobble;
using testing::slurpFile;

class DiskBudget : public testing::ScratchDir {};

const std::map<std::string, std::string> kText = {{PictureKey::kSettingsName, io::hashOf("a")},
                                                  {PictureKey::kFrameName, io::hashOf("b")}};

TEST_F(DiskBudget, PictureBoundsHoldForNoise) {
  std::mt19937 random(7);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_real_distribution<float> value(0.0f, 4.0f);
  for (const auto& [w, h] : {std::pair{64, 48}, std::pair{333, 17}}) {
    image::Image8 image(w, h, 3);
    for (auto& p : image.pixels) p = static_cast<unsigned char>(byte(random));
    writePng(dir() / "noise.png", image, kText);
    const auto png = fs::file_size(dir() / "noise.png"), png_bound = image::pngSizeBound(w, h, 3, kText);
    EXPECT_LE(png, png_bound) << w << "x" << h;
    EXPECT_GE(double(png), 0.95 * double(png_bound)) << "noise does not compress: the bound is tight";

    image::Film film(w, h);
    std::vector<image::Color> denoised(film.color.size());
    for (std::size_t i = 0; i < film.color.size(); ++i) {
      film.color[i] = {value(random), value(random), value(random)};
      film.albedo[i] = {value(random), value(random), value(random)};
      film.normal[i] = {value(random), value(random), value(random)};
      film.depth[i] = value(random) * 1000;
      denoised[i] = {value(random), value(random), value(random)};
    }
    for (bool with_denoised : {false, true}) {
      image::writeExr(dir() / "noise.exr", film, with_denoised ? std::span(denoised) : std::span<image::Color>(),
                      kText);
      EXPECT_LE(fs::file_size(dir() / "noise.exr"), image::exrSizeBound(w, h, with_denoised, kText))
          << w << "x" << h << " denoised " << with_denoised;
    }
  }
}

// Bytes under out by what the estimate calls them.
std::map<std::string, std::uintmax_t> writtenBytes(const fs::path& out, const std::vector<std::string>& bases) {
  std::map<std::string, std::uintmax_t> bytes;
  for (const auto& entry : fs::recursive_directory_iterator(out)) {
    if (!entry.is_regular_file()) continue;
    const fs::path& p = entry.path();
    const std::string ext = p.extension().string(), stem = p.stem().string();
    const bool base = std::find(bases.begin(), bases.end(), stem) != bases.end();
    const std::string kind = ext == ".pc2" || (base && (ext == ".obj" || ext == ".mtl")) ? "PC2"
                             : ext == ".obj" || ext == ".mtl"                            ? "OBJ"
                             : p.parent_path().filename() == "frames"                    ? "PNG"
                             : ext == ".exr"                                             ? "EXR"
                                                                                         : "textures";
    bytes[kind] += entry.file_size();
  }
  return bytes;
}

TEST_F(DiskBudget, EstimateOfASmallRunBoundsWhatItWrote) {
  copyCatTexture();
  RunOptions o;
  o.scene = write("small.toml", R"([simulation]
dt = 0.002
duration = 0.3
fps = 20
[output]
pc2 = true
[bodies.jelly]
type = "jelly"
n = 4
size = 1.0
center = [0, 0.6, 0]
texture = "textures/cat.png"
[bodies.cloth]
type = "cloth"
nx = 7
ny = 5
size = [1.0, 0.7]
center = [0, 1.5, 0]
[colliders.floor]
type = "plane"
[render]
samples = 1
)");
  o.out = dir() / "out";
  o.render.render = "png,exr";
  o.render.resolution = "40x24";
  o.progress = false;
  const SceneFile scene = loadRunScene(o);
  const DiskEstimate e = estimateRunOutput(scene, 1, scene.frameCount());
  const RunReport r = runScene(o);
  ASSERT_EQ(r.frames_written, 6);
  const auto written = writtenBytes(dir() / "out", {"jelly", "cloth"});
  std::map<std::string, std::uint64_t> estimated;
  for (const DiskEstimate::Part& p : e.parts) estimated[p.what.substr(0, 3)] += p.bytes;
  for (const char* kind : {"OBJ", "PC2", "PNG", "EXR"}) {
    ASSERT_GT(written.count(kind), 0u) << kind;
    const double ratio = double(estimated[kind]) / double(written.at(kind));
    std::printf("%s: wrote %ju bytes, estimated %ju (%.2fx)\n", kind, written.at(kind), std::uintmax_t(estimated[kind]),
                ratio);
    EXPECT_GE(ratio, 1.0) << kind << ": never below what the run wrote";
    if (std::string(kind) == "OBJ" || std::string(kind) == "PC2") {
      EXPECT_LE(ratio, 3.0) << kind;
    }
  }
  EXPECT_GE(estimated["tex"], written.at("textures"));  // the texture copy and run.json
  std::uintmax_t total = 0;
  for (const auto& [kind, bytes] : written) total += bytes;
  EXPECT_GE(e.bytes(), total);
}

TEST_F(DiskBudget, FreeSpaceIsWhatDfSaysAtTheNearestExistingFolder) {
  std::FILE* df = ::popen(("df --output=avail -B1 " + dir().string() + " | tail -1").c_str(), "r");
  ASSERT_NE(df, nullptr);
  unsigned long long avail = 0;
  ASSERT_EQ(std::fscanf(df, "%llu", &avail), 1);
  ::pclose(df);
  const double slack = 256.0 * 1024 * 1024;  // other programs write meanwhile
  EXPECT_NEAR(double(freeDiskSpace(dir())), double(avail), slack);
  EXPECT_NEAR(double(freeDiskSpace(dir() / "not/yet/there")), double(avail), slack);
  EXPECT_FALSE(fs::exists(dir() / "not"));
}

// A 20-line scene at fps = 1e6: 50,000 frames of OBJ and PNG. Refused at once; the same scene at 100 fps runs.
TEST_F(DiskBudget, MillionFramesPerSecondIsRefusedBeforeWritingAnything) {
  const auto scene = [&](const std::string& fps) {
    return write("fast.toml", R"(# a small jelly, filmed at a million frames per second
[simulation]
integrator = "symplectic-euler"
dt = 0.001
duration = 0.05
fps = )" + fps + R"(

[bodies.jelly]
type = "jelly"
n = 4
size = 1.0
center = [0, 1.0, 0]

[colliders.floor]
type = "plane"

[render]
samples = 1
)");
  };
  const fs::path out = dir() / "out", log = dir() / "log.txt";
  const std::string flags = " --resolution 64x36 --max-disk 100MB --out " + out.string();
  EXPECT_EQ(runWobble("run " + scene("1e6").string() + flags, log), 2) << slurpFile(log);
  const std::string message = slurpFile(log);
  for (const char* says :
       {"50000 frames", "OBJ + MTL", "100.0 MB", "fewer frames", "output.obj=false", "--render none"})
    EXPECT_NE(message.find(says), std::string::npos) << says << " in: " << message;
  EXPECT_FALSE(fs::exists(out)) << "nothing written";
  EXPECT_EQ(runWobble("run " + scene("100").string() + flags, log), 0) << slurpFile(log);
  EXPECT_TRUE(fs::exists(out / "mesh/jelly_0005.obj"));
}

// A 16384 x 10 cloth at fps 65536 for a second: terabytes of OBJ text. Refused at once, nothing written.
TEST_F(DiskBudget, LongClothAtHighFrameRateIsRefusedBeforeWritingAnything) {
  const fs::path file = write("long.toml", R"([simulation]
dt = 0.001
duration = 1.0
fps = 65536
[bodies.cloth]
type = "cloth"
nx = 16384
ny = 10
size = [100.0, 0.05]
center = [0, 1, 0]
)");
  const fs::path out = dir() / "out", log = dir() / "log.txt";
  EXPECT_EQ(runWobble("run " + file.string() + " --render none --max-disk 1GB --out " + out.string(), log), 2)
      << slurpFile(log);
  const std::string message = slurpFile(log);
  EXPECT_NE(message.find("65536 frames"), std::string::npos) << message;
  EXPECT_NE(message.find("TB"), std::string::npos) << message;
  EXPECT_EQ(message.find("--render none"), std::string::npos) << "nothing rendered: no such hint: " << message;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(DiskBudget, RenderOfASequenceIsHeldToTheBudget) {
  const fs::path file = write("small.toml", R"([simulation]
duration = 0.2
fps = 20
[bodies.jelly]
type = "jelly"
n = 3
size = 1.0
center = [0, 1.0, 0]
[render]
samples = 1
)");
  const fs::path out = dir() / "out", log = dir() / "log.txt";
  ASSERT_EQ(runWobble("run " + file.string() + " --render none --out " + out.string(), log), 0) << slurpFile(log);
  const std::string render =
      "render " + (out / "mesh").string() + " --scene " + file.string() + " --resolution 640x360";
  // 4 PNGs of 640x360 are at most 4 x 691 KB uncompressed: above 1 MB, refused; below 10 MB, rendered.
  EXPECT_EQ(runWobble(render + " --max-disk 1MB", log), 2) << slurpFile(log);
  EXPECT_NE(slurpFile(log).find("--frames A:B"), std::string::npos) << slurpFile(log);
  EXPECT_FALSE(fs::exists(out / "frames"));
  EXPECT_EQ(runWobble(render + " --max-disk 10MB", log), 0) << slurpFile(log);
  EXPECT_TRUE(fs::exists(out / "frames/small_0004.png"));
}

}  // namespace
}  // namespace wobble
