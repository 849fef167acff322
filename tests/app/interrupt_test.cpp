// SIGINT/SIGTERM during `wobble run` and `wobble render`, two runs on one folder, and re-runs into an old folder:
// a signalled run stops after a complete frame with run.json saying "interrupted", ends ffmpeg and removes every
// temporary file, exiting 130 or 143; a signalled `wobble render` likewise stops after a complete frame, saying
// which, with no video; a second run on a held folder is refused (exit 2) naming the holder; a re-run replaces the
// earlier run's files, while `wobble render --frames` overwrites only its frames.
#include <signal.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <regex>

#include "app/output/external_program.h"
#include "image/png_io.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using testing::expectCompleteFiles;
using testing::runWobble;
using testing::slurpFile;
using testing::startWobble;
using testing::waitExit;
using testing::waitUntil;

class Interrupt : public testing::ScratchDir {
 protected:
  // 20 s at 20 fps: 400 frames, far more than a test waits for (the test signals it after its first frames).
  fs::path scene(double duration = 20) {
    return write("long.toml", R"([simulation]
dt = 0.002
duration = )" + std::to_string(duration) +
                                  R"(
fps = 20

[bodies.jelly]
type = "jelly"
n = 3
size = 1.0
center = [0, 0.6, 0]

[colliders.floor]
type = "plane"

[render]
samples = 1
)");
  }
  fs::path out() const { return dir() / "out"; }
  fs::path log() const { return dir() / "log.txt"; }
  std::string run(const fs::path& file, const std::string& extra = "") const {
    return "run " + file.string() + " --resolution 32x18 --out " + out().string() + " " + extra;
  }
  bool frameExists(int k) const {
    char name[32];
    std::snprintf(name, sizeof name, "frames/long_%04d.png", k);
    return fs::exists(out() / name);
  }
};

void expectInterruptedRun(const fs::path& out, const fs::path& clean_of_same_scene) {
  const auto j = nlohmann::json::parse(slurpFile(out / "run.json"));
  EXPECT_TRUE(j["interrupted"].get<bool>());
  const int written = j["frames"]["written"];
  EXPECT_GE(written, 2);
  for (int k = 1; k <= written; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "%04d", k);
    EXPECT_TRUE(fs::exists(out / "mesh" / ("jelly_" + std::string(name) + ".obj"))) << k;
    EXPECT_NO_THROW(image::readImage(out / "frames" / ("long_" + std::string(name) + ".png"))) << k;
  }
  char next[32];
  std::snprintf(next, sizeof next, "mesh/jelly_%04d.obj", written + 1);
  EXPECT_FALSE(fs::exists(out / next));
  EXPECT_FALSE(fs::exists(out / "long.mp4"));
  if (!clean_of_same_scene.empty()) expectCompleteFiles(out, clean_of_same_scene);
}

TEST_F(Interrupt, SigintAndSigtermStopAfterACompleteFrame) {
  const fs::path file = scene();
  // A clean run of the first `frames` frames into OUT, for the bytes the interrupted runs must hold.
  const auto cleanRun = [&](int frames, const fs::path& out) {
    const fs::path log = dir() / ("clean_" + std::to_string(frames) + ".txt");
    return runWobble("run " + file.string() + " --resolution 32x18 --frames 1:" + std::to_string(frames) + " --out " +
                         out.string(),
                     log) == 0
               ? ::testing::AssertionSuccess()
               : ::testing::AssertionFailure() << slurpFile(log);
  };
  const fs::path clean = dir() / "clean";
  ASSERT_TRUE(cleanRun(40, clean));
  for (const auto& [signal, status] : {std::pair{SIGINT, 130}, std::pair{SIGTERM, 143}}) {
    fs::remove_all(out());
    const pid_t child = startWobble(run(file), log());
    ASSERT_TRUE(waitUntil(child, [&] { return frameExists(2); })) << slurpFile(log());
    ::kill(child, signal);
    EXPECT_EQ(waitExit(child), status) << slurpFile(log());
    EXPECT_NE(slurpFile(log()).find("interrupted"), std::string::npos) << slurpFile(log());
    // Frames 1..k, byte for byte those of a clean run. The signal normally lands within the first 40 frames; on a
    // machine busy enough to delay this test past them, a clean run of the frames written is made to compare with.
    expectInterruptedRun(out(), "");
    const auto j = nlohmann::json::parse(slurpFile(out() / "run.json"));
    const int written = j["frames"]["written"].get<int>();
    fs::path reference = clean;
    if (written > 40) {
      reference = dir() / ("clean_" + std::to_string(written));
      ASSERT_TRUE(cleanRun(written, reference));
    }
    fs::remove(out() / "run.json");
    expectCompleteFiles(out(), reference);
    EXPECT_FALSE(fs::exists(out() / "mesh/.partial"));
  }
}

// `wobble render` of a run's 400 OBJ frames, signalled after its second frame: exit 130 (SIGINT) or 143 (SIGTERM),
// "interrupted: stopped after frame K", frames 1..K written whole (the bytes of a clean render of them) and no
// further one, no temporary file and no video (when ffmpeg is there to make one).
TEST_F(Interrupt, RenderStopsAfterACompleteFrame) {
  const fs::path file = scene();
  ASSERT_EQ(runWobble(run(file, "--render none"), log()), 0) << slurpFile(log());
  const bool video = findProgram("ffmpeg").has_value();
  const std::string render = "render " + (out() / "mesh").string() + " --scene " + file.string() +
                             " --resolution 32x18" + (video ? " --video" : "");
  // A clean render of the first `frames` frames of a copy of the run, for the bytes the interrupted ones must hold.
  const fs::path clean = dir() / "clean";
  fs::create_directories(clean);
  fs::copy(out() / "mesh", clean / "mesh", fs::copy_options::recursive);
  fs::copy(out() / "scene", clean / "scene", fs::copy_options::recursive);  // the scene the run carried
  const auto cleanRender = [&](int frames) {
    const fs::path clean_log = dir() / "clean.txt";
    return runWobble("render " + (clean / "mesh").string() + " --scene " + file.string() +
                         " --resolution 32x18 --frames 1:" + std::to_string(frames),
                     clean_log) == 0
               ? ::testing::AssertionSuccess()
               : ::testing::AssertionFailure() << slurpFile(clean_log);
  };
  ASSERT_TRUE(cleanRender(40));
  int cleaned = 40;
  for (const auto& [signal, status] : {std::pair{SIGINT, 130}, std::pair{SIGTERM, 143}}) {
    fs::remove_all(out() / "frames");
    const pid_t child = startWobble(render, log());
    ASSERT_TRUE(waitUntil(child, [&] { return frameExists(2); })) << slurpFile(log());
    ::kill(child, signal);
    EXPECT_EQ(waitExit(child), status) << slurpFile(log());
    const std::string said = slurpFile(log());
    std::smatch m;
    ASSERT_TRUE(std::regex_search(said, m, std::regex("interrupted: stopped after frame ([0-9]+)"))) << said;
    const int last = std::stoi(m[1]);
    EXPECT_GE(last, 2) << said;
    EXPECT_LT(last, 400) << said;
    for (int k = 1; k <= last; ++k) EXPECT_TRUE(frameExists(k)) << k;
    EXPECT_FALSE(frameExists(last + 1)) << said;
    EXPECT_FALSE(fs::exists(out() / "long.mp4"));
    // As in the run's test: a machine busy enough to let more than 40 frames through gets a longer clean render.
    if (last > cleaned) {
      ASSERT_TRUE(cleanRender(last));
      cleaned = last;
    }
    expectCompleteFiles(out(), clean);
  }
}

// A stand-in ffmpeg that starts writing its output and then hangs: wobble must end it and remove the partial file.
TEST_F(Interrupt, SigtermEndsFfmpegAndRemovesItsPartialFile) {
  const fs::path bin = dir() / "bin", started = dir() / "ffmpeg_pid";
  fs::create_directories(bin);
  write("bin/ffmpeg", "#!/bin/sh\nfor last; do :; done\necho partial > \"$last\"\necho $$ > " + started.string() +
                          ".new\nmv " + started.string() + ".new " + started.string() + "\nexec sleep 600\n");
  fs::permissions(bin / "ffmpeg", fs::perms::owner_all);
  const pid_t child = startWobble(run(scene(0.2), "--video"), log(), "PATH=" + bin.string() + ":/usr/bin:/bin");
  ASSERT_TRUE(waitUntil(child, [&] { return fs::exists(started); })) << slurpFile(log());
  const pid_t ffmpeg = std::stoi(slurpFile(started));
  ::kill(child, SIGTERM);
  EXPECT_EQ(waitExit(child), 143) << slurpFile(log());
  const bool ffmpeg_left = ::kill(ffmpeg, 0) == 0;
  if (ffmpeg_left) ::kill(ffmpeg, SIGKILL);
  EXPECT_FALSE(ffmpeg_left) << "ffmpeg still running";
  for (const auto& entry : fs::recursive_directory_iterator(out()))
    EXPECT_TRUE(entry.path().filename() == ".wobble.lock" || entry.path().filename().string()[0] != '.')
        << "left: " << entry.path();
  EXPECT_FALSE(fs::exists(out() / "long.mp4"));
  EXPECT_TRUE(nlohmann::json::parse(slurpFile(out() / "run.json"))["interrupted"].get<bool>());
}

TEST_F(Interrupt, SecondRunOnAHeldFolderIsRefused) {
  const fs::path file = scene();
  const pid_t first = startWobble(run(file), log());
  ASSERT_TRUE(waitUntil(first, [&] { return frameExists(1); })) << slurpFile(log());
  const fs::path second_log = dir() / "second.txt";
  EXPECT_EQ(runWobble(run(file, "--render none"), second_log), 2);
  const std::string message = slurpFile(second_log);
  EXPECT_NE(message.find(out().string()), std::string::npos) << message;
  EXPECT_NE(message.find("pid " + std::to_string(first)), std::string::npos) << message;
  EXPECT_NE(message.find(".wobble.lock"), std::string::npos) << message;
  // An interrupted run keeps at least two frames (expectInterruptedRun): on a busy machine the first run may not
  // have finished its second yet.
  ASSERT_TRUE(waitUntil(first, [&] { return frameExists(2); })) << slurpFile(log());
  ::kill(first, SIGTERM);
  EXPECT_EQ(waitExit(first), 143) << slurpFile(log());
  // The first run's files are untouched by the refused one, and its lock died with it: a new run may go ahead.
  expectInterruptedRun(out(), "");
  EXPECT_EQ(runWobble(run(scene(0.2), "--render none"), second_log), 0) << slurpFile(second_log);
}

TEST_F(Interrupt, RerunReplacesAnEarlierRunButRenderKeepsOtherFrames) {
  const fs::path file = scene(1.0);  // 20 frames
  ASSERT_EQ(runWobble(run(file), log()), 0) << slurpFile(log());
  ASSERT_TRUE(frameExists(20));
  // `wobble render --frames` re-renders frames 3 and 4 into the same folder: the other 18 stay (split rendering).
  ASSERT_EQ(runWobble("render " + (out() / "mesh").string() + " --scene " + file.string() +
                          " --frames 3:4 --resolution 32x18",
                      log()),
            0)
      << slurpFile(log());
  for (int k = 1; k <= 20; ++k) EXPECT_TRUE(frameExists(k)) << k;

  ASSERT_EQ(runWobble(run(file, "--frames 1:5"), log()), 0) << slurpFile(log());
  EXPECT_NE(slurpFile(log()).find("removed"), std::string::npos) << slurpFile(log());
  for (int k = 1; k <= 20; ++k) {
    char obj[32];
    std::snprintf(obj, sizeof obj, "mesh/jelly_%04d.obj", k);
    EXPECT_EQ(frameExists(k), k <= 5) << k;
    EXPECT_EQ(fs::exists(out() / obj), k <= 5) << k;
  }
  const auto j = nlohmann::json::parse(slurpFile(out() / "run.json"));
  EXPECT_EQ(j["frames"]["last"].get<int>(), 5);
  EXPECT_FALSE(j["interrupted"].get<bool>());
}

}  // namespace
}  // namespace wobble
