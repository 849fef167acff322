// Rendering in pieces (docs/farm-rendering.md), through the wobble binary: `wobble frames` splits a
// range; GNU parallel renders the pieces into one folder at once, and they are the bytes of one render; `wobble
// video` joins them into the video one render makes, and refuses missing frames (listed), frames of two sizes or two
// settings; --skip-existing renders exactly the frames whose files lack the key this frame would get (checked by the
// report's counts and by the files' inodes: a rendered frame is a new file, renamed into place).
#include <signal.h>
#include <sys/stat.h>

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/commands/frames_command.h"
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

class SplitRender : public testing::ScratchDir {
 protected:
  // 8 frames of a small jelly falling onto a floor; a fixed camera, or one that follows the jelly.
  fs::path scene(bool follow = false) {
    return write("split.toml", std::string(R"([simulation]
dt = 0.002
duration = 0.4
fps = 20

[bodies.jelly]
type = "jelly"
n = 3
size = 1.0
center = [0, 1.2, 0]

[colliders.floor]
type = "plane"
texture = "checker"

[camera]
position = [1.5, 1.5, 4]
look_at = [0, 0.6, 0]
)") + (follow ? "follow = \"jelly\"\n" : "") +
                                   R"(
[render]
samples = 1
)");
  }
  fs::path out() const { return dir() / "out"; }
  fs::path log() const { return dir() / "log.txt"; }
  int wobble(const std::string& arguments, const std::string& env = "") { return runWobble(arguments, log(), env); }
  // Renders the run of scene s whole and in three pieces at once (extra: more flags for both); the same bytes.
  void piecesAreOneRender(const fs::path& s, const std::string& extra);
  std::string said() const { return slurpFile(log()); }
  static fs::path frame(const fs::path& out, int k) {
    return out / "frames" / ("split_000" + std::to_string(k) + ".png");
  }
  // The simulation alone, as the first job of a split render does.
  void simulate(const fs::path& s) {
    ASSERT_EQ(wobble("run " + s.string() + " --render none --out " + out().string()), 0) << said();
  }
  std::string render(const fs::path& s, const std::string& extra) const {
    return "render " + (out() / "mesh").string() + " --scene " + s.string() + " --resolution 32x18 " + extra;
  }
  // "rendered R frame(s)" and "skipped S frame(s)" of a `wobble render` report.
  std::pair<int, int> counts() const {
    const std::string text = said();
    std::smatch r, s;
    EXPECT_TRUE(std::regex_search(text, r, std::regex("rendered ([0-9]+) frame"))) << text;
    const bool skipped = std::regex_search(text, s, std::regex("skipped ([0-9]+) frame"));
    return {r.empty() ? -1 : std::stoi(r[1]), skipped ? std::stoi(s[1]) : 0};
  }
  static ino_t inode(const fs::path& p) {
    struct stat st {};
    return ::stat(p.c_str(), &st) == 0 ? st.st_ino : 0;
  }
  std::vector<ino_t> inodes() const {
    std::vector<ino_t> all;
    for (int k = 1; k <= 8; ++k) all.push_back(inode(frame(out(), k)));
    return all;
  }
  // The frames (1-based) whose file is another one than before.
  std::vector<int> replaced(const std::vector<ino_t>& before) const {
    std::vector<int> frames;
    const std::vector<ino_t> now = inodes();
    for (int k = 1; k <= 8; ++k)
      if (now[k - 1] != before[k - 1]) frames.push_back(k);
    return frames;
  }
  // A shell command's standard output.
  std::string output(const std::string& command) {
    const fs::path file = dir() / "output.txt";
    EXPECT_EQ(std::system((command + " > " + file.string() + " 2>&1").c_str()), 0) << command;
    return slurpFile(file);
  }
  int videoFrames(const fs::path& mp4) {
    return std::stoi(
        output("ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames "
               "-of default=nw=1:nk=1 " +
               mp4.string()));
  }
  // Frame n (0-based) of a video, decoded.
  image::Image8 decoded(const fs::path& mp4, int n) {
    const fs::path png = dir() / (mp4.stem().string() + "_decoded" + std::to_string(n) + ".png");
    output("ffmpeg -nostdin -loglevel error -y -i " + mp4.string() + " -vf 'select=eq(n\\," + std::to_string(n) +
           ")' -frames:v 1 " + png.string());
    return image::readImage(png);
  }
};

double meanDifference(const image::Image8& a, const image::Image8& b) {
  EXPECT_TRUE(a.sameShape(b));
  double sum = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) sum += std::abs(int(a.pixels[i]) - int(b.pixels[i]));
  return sum / double(a.pixels.size());
}

TEST(FrameChunks, ContiguousEvenPiecesCoverTheRange) {
  EXPECT_EQ(frameChunks(1, 10, 4), (std::vector<std::pair<int, int>>{{1, 3}, {4, 6}, {7, 8}, {9, 10}}));
  for (int first : {1, 7})
    for (int count = 1; count <= 30; ++count)
      for (int chunks = 1; chunks <= count; ++chunks) {
        const auto pieces = frameChunks(first, first + count - 1, chunks);
        ASSERT_EQ(int(pieces.size()), chunks);
        int next = first, smallest = count, largest = 0;
        for (const auto& [a, b] : pieces) {
          EXPECT_EQ(a, next);
          smallest = std::min(smallest, b - a + 1), largest = std::max(largest, b - a + 1);
          next = b + 1;
        }
        EXPECT_EQ(next, first + count);
        EXPECT_LE(largest - smallest, 1);
      }
}

TEST_F(SplitRender, FramesPrintsThePiecesOfASceneOrARun) {
  const fs::path s = scene();
  EXPECT_EQ(wobble("frames " + s.string() + " --chunks 3"), 0) << said();
  EXPECT_EQ(said(), "1:3\n4:6\n7:8\n");
  EXPECT_EQ(wobble("frames " + s.string() + " --chunks 3 --chunk 2"), 0) << said();
  EXPECT_EQ(said(), "4:6\n");
  EXPECT_EQ(wobble("frames " + s.string() + " --chunks 2 --set simulation.duration=1"), 0) << said();
  EXPECT_EQ(said(), "1:10\n11:20\n");
  // A run's folder: the frames it wrote.
  ASSERT_EQ(wobble("run " + s.string() + " --render none --frames 3:8 --out " + out().string()), 0) << said();
  EXPECT_EQ(wobble("frames " + out().string() + " --chunks 4"), 0) << said();
  EXPECT_EQ(said(), "3:4\n5:6\n7:7\n8:8\n");
  EXPECT_EQ(wobble("frames " + out().string() + " --chunks 2 --frames 5:8"), 0) << said();
  EXPECT_EQ(said(), "5:6\n7:8\n");
  for (const std::string& bad : {s.string() + " --chunks 9", s.string() + " --chunks 0",
                                 s.string() + " --chunks 2 --chunk 3", out().string() + " --chunks 2 --frames 1:4",
                                 (dir() / "nothing").string() + " --chunks 2", dir().string() + " --chunks 2"}) {
    EXPECT_EQ(wobble("frames " + bad), 2) << bad << "\n" << said();
  }
  EXPECT_EQ(wobble("frames " + s.string() + " --chunks 9"), 2);
  EXPECT_NE(said().find("must be 1 to 8"), std::string::npos) << said();
}

// The pieces of a split render, rendered at the same time into one folder, are the bytes of one render. Needs neither
// GNU parallel nor ffmpeg: `wobble frames` cuts the range, the pieces are three wobble processes started at once,
// each asked for a video it must leave to `wobble video` (a piece makes none).
// With motion blur (a follow camera too), a piece blends its first frame's poses from the OBJ of the frame before it,
// as one render does: the same bytes again, and not the still pictures.
void SplitRender::piecesAreOneRender(const fs::path& s, const std::string& extra) {
  simulate(s);
  const fs::path whole = dir() / "whole";
  ASSERT_EQ(wobble(render(s, "--out " + whole.string() + extra)), 0) << said();
  ASSERT_EQ(wobble("frames " + out().string() + " --chunks 3"), 0) << said();
  std::istringstream ranges(said());
  std::vector<pid_t> pieces;
  std::vector<fs::path> logs;
  for (std::string range; std::getline(ranges, range);) {
    logs.push_back(dir() / ("piece" + std::to_string(pieces.size()) + ".txt"));
    pieces.push_back(
        testing::startWobble(render(s, "--frames " + range + " --set render.video=true" + extra), logs.back()));
  }
  ASSERT_EQ(pieces.size(), 3u);
  for (std::size_t i = 0; i < pieces.size(); ++i) EXPECT_EQ(testing::waitExit(pieces[i]), 0) << slurpFile(logs[i]);
  EXPECT_FALSE(fs::exists(out() / "split.mp4"));
  for (int k = 1; k <= 8; ++k) {
    ASSERT_TRUE(fs::exists(frame(out(), k))) << "frame " << k;
    EXPECT_TRUE(slurpFile(frame(out(), k)) == slurpFile(frame(whole, k))) << "frame " << k << " differs";
  }
}

TEST_F(SplitRender, PiecesRenderedAtOnceAreOneRendersBytes) { piecesAreOneRender(scene(), ""); }

// The farm's recipe: a run that only simulated (--render none) is rendered from its folder alone, with no --scene or
// --render, to the PNGs the scene file renders: the same settings' hash, so the scene file's render keeps them all.
TEST_F(SplitRender, AFolderThatOnlySimulatedRendersItsPngs) {
  const fs::path s = scene();
  simulate(s);
  ASSERT_EQ(wobble("render " + out().string() + " --resolution 32x18 --frames 1:3"), 0) << said();
  EXPECT_EQ(counts(), std::make_pair(3, 0));
  EXPECT_TRUE(fs::exists(frame(out(), 3)));
  ASSERT_EQ(wobble(render(s, "--frames 1:3 --skip-existing")), 0) << said();
  EXPECT_EQ(counts(), std::make_pair(0, 3));
}

TEST_F(SplitRender, BlurredPiecesAreOneRendersBytes) {
  const fs::path s = scene(true);
  piecesAreOneRender(s, " --set camera.shutter=0.5");
  const fs::path still = dir() / "still";
  ASSERT_EQ(wobble(render(s, "--frames 4 --out " + still.string())), 0) << said();
  EXPECT_FALSE(slurpFile(frame(still, 4)) == slurpFile(frame(out(), 4))) << "motion blur changed nothing";
}

// The recipe of docs/farm-rendering.md: simulate once, render the pieces with GNU parallel (all at once, into one
// folder), join them.
TEST_F(SplitRender, ParallelPiecesAreOneRenderAndItsVideo) {
  if (!findProgram("parallel")) GTEST_SKIP() << "GNU parallel is not installed (./setup.sh installs it)";
  if (!findProgram("ffmpeg") || !findProgram("ffprobe")) GTEST_SKIP() << "ffmpeg is not installed";
  const fs::path s = scene();
  simulate(s);
  const fs::path whole = dir() / "whole";
  ASSERT_EQ(wobble(render(s, "--out " + whole.string() + " --video")), 0) << said();
  // (The scene asks for a video: a piece makes none of its own.)
  const std::string pieces = std::string(WOBBLE_BINARY) + " frames " + out().string() + " --chunks 3 | parallel " +
                             "--will-cite -j 3 " + WOBBLE_BINARY + " " +
                             render(s, "--frames {} --set render.video=true");
  ASSERT_EQ(std::system((pieces + " > " + log().string() + " 2>&1").c_str()), 0) << pieces << "\n" << said();
  EXPECT_EQ(std::regex_search(said(), std::regex("rendered [0-9]+ frame")), true) << said();
  EXPECT_FALSE(fs::exists(out() / "split.mp4"));
  for (int k = 1; k <= 8; ++k)
    EXPECT_TRUE(slurpFile(frame(out(), k)) == slurpFile(frame(whole, k))) << "frame " << k << " differs";

  ASSERT_EQ(wobble("video " + out().string()), 0) << said();
  EXPECT_NE(said().find("8 frame(s) 1..8"), std::string::npos) << said();
  const fs::path joined = out() / "split.mp4", one = whole / "split.mp4";
  EXPECT_EQ(videoFrames(joined), 8);
  EXPECT_EQ(videoFrames(one), 8);
  for (int n : {0, 7}) {
    const image::Image8 a = decoded(joined, n), b = decoded(one, n);
    EXPECT_EQ(a.pixels, b.pixels) << "decoded frame " << n;
    // And it is that frame: closer to its own PNG than to the other end's (the jelly has fallen in between; at
    // 32 x 18, H.264's 4:2:0 colour leaves about 5 levels of mean difference to its own, twice that to the other).
    const image::Image8 own = image::readImage(frame(out(), n + 1)), other = image::readImage(frame(out(), 8 - n));
    EXPECT_LT(meanDifference(a, own), meanDifference(a, other)) << "decoded frame " << n;
  }
}

// `wobble video` of a run's own frames is the video the run streamed while rendering, whatever the CPUs.
TEST_F(SplitRender, VideoOfARunsFramesIsItsVideo) {
  if (!findProgram("ffmpeg") || !findProgram("ffprobe")) GTEST_SKIP() << "ffmpeg is not installed";
  const fs::path s = scene();
  ASSERT_EQ(wobble("run " + s.string() + " --resolution 32x18 --video --out " + out().string()), 0) << said();
  fs::rename(out() / "split.mp4", dir() / "streamed.mp4");
  ASSERT_EQ(wobble("video " + out().string()), 0) << said();
  const auto md5 = [&](const fs::path& mp4) {
    const std::string text = output("ffmpeg -nostdin -loglevel error -i " + mp4.string() + " -f framemd5 -");
    return text.substr(text.find("\n0,"));
  };
  EXPECT_EQ(md5(out() / "split.mp4"), md5(dir() / "streamed.mp4"));
  EXPECT_EQ(videoFrames(out() / "split.mp4"), 8);
  // The same bytes on one CPU (the encoder's threads are fixed, not taken from the machine).
  fs::rename(out() / "split.mp4", dir() / "all_cpus.mp4");
  ASSERT_EQ(wobble("video " + out().string(), "taskset -c 0"), 0) << said();
  EXPECT_TRUE(slurpFile(out() / "split.mp4") == slurpFile(dir() / "all_cpus.mp4"));
}

// Pieces share the folder (a shared lock): another piece starts while one renders, a run or `wobble video` waits.
TEST_F(SplitRender, PiecesShareTheFolderWhileRunAndVideoWait) {
  const fs::path s = scene();
  ASSERT_EQ(wobble("run " + s.string() + " --render none --set simulation.duration=20 --out " + out().string()), 0)
      << said();  // 400 frames: far more than the first piece renders before the test stops it
  const fs::path first_log = dir() / "first.txt";
  const pid_t first = testing::startWobble(render(s, "--frames 1:399 --set simulation.duration=20"), first_log);
  ASSERT_TRUE(testing::waitUntil(first, [&] { return fs::exists(frame(out(), 1)); })) << slurpFile(first_log);
  EXPECT_EQ(wobble(render(s, "--frames 400 --set simulation.duration=20")), 0) << said();
  EXPECT_TRUE(fs::exists(out() / "frames" / "split_0400.png"));
  EXPECT_EQ(wobble("video " + out().string()), 2) << said();
  EXPECT_NE(said().find("another wobble (pid " + std::to_string(first) + ")"), std::string::npos) << said();
  EXPECT_EQ(wobble("run " + s.string() + " --render none --out " + out().string()), 2) << said();
  ::kill(first, SIGTERM);
  EXPECT_EQ(testing::waitExit(first), 143) << slurpFile(first_log);
}

TEST_F(SplitRender, VideoRefusesMissingOrMixedFrames) {
  const fs::path s = scene();
  simulate(s);
  ASSERT_EQ(wobble(render(s, "--frames 1:8")), 0) << said();
  fs::remove(frame(out(), 2));
  fs::remove(frame(out(), 5));
  fs::remove(frame(out(), 6));
  EXPECT_EQ(wobble("video " + out().string()), 2) << said();
  EXPECT_NE(said().find("3 of 8 frame(s)"), std::string::npos) << said();
  EXPECT_NE(said().find("--frames: 2 5:6;"), std::string::npos) << said();
  EXPECT_FALSE(fs::exists(out() / "split.mp4"));
  EXPECT_EQ(wobble("video " + out().string() + " --frames 3:4"), 0) << said();  // a range that is all there

  // The missing ones rendered with another sample count: two settings, refused unless asked.
  ASSERT_EQ(wobble(render(s, "--frames 2 --spp 2")), 0) << said();
  ASSERT_EQ(wobble(render(s, "--frames 5:6 --spp 2")), 0) << said();
  fs::remove(out() / "split.mp4");
  EXPECT_EQ(wobble("video " + out().string()), 2) << said();
  EXPECT_NE(said().find("different settings"), std::string::npos) << said();
  EXPECT_NE(said().find("frames 1 3:4 7:8: settings"), std::string::npos) << said();
  EXPECT_NE(said().find("frames 2 5:6: settings"), std::string::npos) << said();
  EXPECT_FALSE(fs::exists(out() / "split.mp4"));
  if (findProgram("ffmpeg")) {
    EXPECT_EQ(wobble("video " + out().string() + " --allow-mixed"), 0) << said();
    EXPECT_TRUE(fs::exists(out() / "split.mp4"));
  }

  // Another size; a folder without run.json needs --scene; no ffmpeg is exit 1.
  ASSERT_EQ(wobble("render " + (out() / "mesh").string() + " --scene " + s.string() + " --frames 8 --resolution 16x8"),
            0)
      << said();
  EXPECT_EQ(wobble("video " + out().string() + " --allow-mixed"), 2) << said();
  EXPECT_NE(said().find("differ in size"), std::string::npos) << said();
  EXPECT_NE(said().find("frames 8: 16 x 8"), std::string::npos) << said();
  fs::remove(out() / "run.json");
  EXPECT_EQ(wobble("video " + out().string() + " --frames 1:7 --allow-mixed"), 2) << said();
  EXPECT_NE(said().find("--scene"), std::string::npos) << said();
  EXPECT_EQ(wobble("video " + out().string() + " --frames 1:7 --allow-mixed --scene " + s.string(),
                   "PATH=" + (dir() / "nothing").string()),
            1)
      << said();
  EXPECT_NE(said().find("ffmpeg not found"), std::string::npos) << said();
}

TEST_F(SplitRender, SkipExistingRendersExactlyTheFramesWithOtherSettings) {
  const fs::path s = scene(true);  // a follow camera: a frame's view depends on the frames before it
  simulate(s);
  ASSERT_EQ(wobble(render(s, "")), 0) << said();
  const std::string first = slurpFile(frame(out(), 2));
  // All there, same settings: nothing rendered, whatever the thread count (one CPU here) or the output folder.
  std::vector<ino_t> before = inodes();
  ASSERT_EQ(wobble(render(s, "--skip-existing"), "taskset -c 0"), 0) << said();
  EXPECT_EQ(counts(), std::pair(0, 8));
  EXPECT_TRUE(replaced(before).empty());
  fs::create_directories(dir() / "elsewhere");
  fs::copy(out() / "frames", dir() / "elsewhere" / "frames", fs::copy_options::recursive);
  ASSERT_EQ(wobble(render(s, "--skip-existing --out " + (dir() / "elsewhere").string())), 0) << said();
  EXPECT_EQ(counts(), std::pair(0, 8));

  // Frame 2 gone, frame 3 without a key (another program's PNG), frame 6's mesh moved: 2, 3, 6 and, through the
  // follow camera, 7 and 8 render again; the others stay the same files.
  fs::remove(frame(out(), 2));
  image::writePng(frame(out(), 3), image::readImage(frame(out(), 3)));
  const fs::path obj = out() / "mesh" / "jelly_0006.obj";
  std::string mesh = slurpFile(obj);
  const std::size_t v = mesh.find("\nv ") + 1;
  mesh.replace(v, mesh.find('\n', v) - v, "v 0.5 3 0.5");  // the first vertex, moved by metres
  std::ofstream(obj) << mesh;
  before = inodes();
  ASSERT_EQ(wobble(render(s, "--skip-existing")), 0) << said();
  EXPECT_EQ(counts(), std::pair(5, 3));
  EXPECT_EQ(replaced(before), (std::vector<int>{2, 3, 6, 7, 8}));
  EXPECT_TRUE(slurpFile(frame(out(), 2)) == first);  // the same bytes as the first time

  // Another setting: all again. The video is not a setting of the pictures: all kept, and the video made of them.
  before = inodes();
  ASSERT_EQ(wobble(render(s, "--skip-existing --spp 2")), 0) << said();
  EXPECT_EQ(counts(), std::pair(8, 0));
  EXPECT_EQ(replaced(before).size(), 8u);
  before = inodes();
  ASSERT_EQ(wobble(render(s, "--skip-existing --spp 2 --video")), 0) << said();
  EXPECT_EQ(counts(), std::pair(0, 8));
  EXPECT_TRUE(replaced(before).empty());
  if (findProgram("ffprobe")) {
    EXPECT_EQ(videoFrames(out() / "split.mp4"), 8);
  }
  // EXR too: the PNGs are there, the EXRs not yet: all rendered; then all there.
  ASSERT_EQ(wobble(render(s, "--skip-existing --spp 2 --render png,exr")), 0) << said();
  EXPECT_EQ(counts(), std::pair(8, 0));
  ASSERT_EQ(wobble(render(s, "--skip-existing --spp 2 --render png,exr")), 0) << said();
  EXPECT_EQ(counts(), std::pair(0, 8));
}

// A `wobble run` resumed with --skip-existing simulates again but renders only the frames it has not.
TEST_F(SplitRender, RunWithSkipExistingKeepsItsFrames) {
  const fs::path s = scene(true);
  const std::string run = "run " + s.string() + " --resolution 32x18 --out " + out().string();
  ASSERT_EQ(wobble(run), 0) << said();
  fs::remove(frame(out(), 4));
  std::vector<ino_t> before = inodes();
  ASSERT_EQ(wobble(run + " --skip-existing"), 0) << said();
  EXPECT_EQ(nlohmann::json::parse(slurpFile(out() / "run.json"))["frames_skipped"], 7);
  EXPECT_EQ(replaced(before), std::vector<int>{4});
  // A new range leaves no frame of the old one; without --skip-existing the run starts over.
  ASSERT_EQ(wobble(run + " --skip-existing --frames 1:6"), 0) << said();
  EXPECT_EQ(nlohmann::json::parse(slurpFile(out() / "run.json"))["frames_skipped"], 6);
  EXPECT_FALSE(fs::exists(frame(out(), 7)));
  ASSERT_EQ(wobble(run + " --frames 1:6"), 0) << said();
  const auto j = nlohmann::json::parse(slurpFile(out() / "run.json"));
  EXPECT_EQ(j["frames_rendered"], 6);  // (not the inodes: the files were removed first, their numbers reused)
  EXPECT_EQ(j["frames_skipped"], 0);
}

}  // namespace
}  // namespace wobble
