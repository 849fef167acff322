// A full disk during `wobble run`: every write is checked, the run fails at the first error (exit 1) naming the file
// and "No space left on device", no temporary file stays, and every file with a final name is complete (the bytes
// of a clean run). Injected (WOBBLE_FAIL_WRITE_AFTER, io/atomic_file.h) at every kind of write, and for real on
// a small tmpfs where the test may mount one.
#include <sys/mount.h>

#include <cerrno>
#include <cstring>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using testing::expectCompleteFiles;
using testing::runWobble;
using testing::slurpFile;

class FullDisk : public testing::ScratchDir {
 protected:
  // A textured jelly (texture copy, OBJ, MTL), rendered (PNG, EXR), with run.json: every writer of a run.
  fs::path scene(int n = 3, double duration = 0.2) {
    copyCatTexture();
    return write("small.toml", R"([simulation]
dt = 0.002
duration = )" + std::to_string(duration) +
                                   R"(
fps = 20

[bodies.jelly]
type = "jelly"
n = )" + std::to_string(n) + R"(
size = 1.0
center = [0, 0.6, 0]
texture = "textures/cat.png"

[colliders.floor]
type = "plane"

[render]
samples = 1
)");
  }
  std::string args(const fs::path& file, const fs::path& out, const std::string& size = "32x18") {
    return "run " + file.string() + " --render png,exr --resolution " + size + " --out " + out.string();
  }
};

TEST_F(FullDisk, InjectedWriteFailureAtEveryKindOfFile) {
  const fs::path file = scene(), clean = dir() / "clean", log = dir() / "log.txt";
  ASSERT_EQ(runWobble(args(file, clean), log), 0) << slurpFile(log);
  // texture + 4 frames x (mtl, obj, png, exr) + run.json = 18 checked writes; PNG/EXR are written on another thread.
  for (int n : {1, 2, 3, 4, 5, 9, 13, 17, 18}) {
    const fs::path out = dir() / ("fail" + std::to_string(n));
    EXPECT_EQ(runWobble(args(file, out), log, "WOBBLE_FAIL_WRITE_AFTER=" + std::to_string(n)), 1)
        << n << ": " << slurpFile(log);
    const std::string message = slurpFile(log);
    EXPECT_NE(message.find("No space left on device"), std::string::npos) << n << ": " << message;
    EXPECT_NE(message.find(out.string() + "/"), std::string::npos) << n << ": names the file: " << message;
    expectCompleteFiles(out, clean);
    EXPECT_FALSE(fs::exists(out / "run.json")) << n;  // the run failed before its report
  }
}

// A real full file system: a 2 MB tmpfs, when the test may mount one (root outside a restricted container).
class SmallTmpfs : public FullDisk {
 protected:
  void TearDown() override {
    if (mounted_) ::umount2(mount_.c_str(), MNT_DETACH);
    FullDisk::TearDown();
  }
  bool mount(const char* options = "size=2m") {
    mount_ = dir() / "tmpfs";
    fs::create_directories(mount_);
    mounted_ = ::mount("tmpfs", mount_.c_str(), "tmpfs", 0, options) == 0;
    if (!mounted_) reason_ = std::strerror(errno);
    return mounted_;
  }
  fs::path mount_;
  bool mounted_ = false;
  std::string reason_;
};

// The disk budget (app/view/disk_budget.h) refuses a run estimated above the free space before it writes, so the disk
// here fills with files, not bytes: 64 MB but room for 40 files (ENOSPC all the same).
TEST_F(SmallTmpfs, RunFailsCleanlyWhenTheDiskFills) {
  if (!mount("size=64m,nr_inodes=40"))
    GTEST_SKIP() << "cannot mount a tmpfs here (" << reason_ << "): needs root outside a container";
  // About 40 frames of an OBJ, MTL, PNG and EXR each: more than 40 files.
  const fs::path file = scene(8, 2.0), clean = dir() / "clean", log = dir() / "log.txt";
  ASSERT_EQ(runWobble(args(file, clean, "128x72"), log), 0) << slurpFile(log);
  const fs::path out = mount_ / "out";
  EXPECT_EQ(runWobble(args(file, out, "128x72"), log), 1) << slurpFile(log);
  const std::string message = slurpFile(log);
  EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
  EXPECT_NE(message.find(out.string() + "/"), std::string::npos) << message;
  EXPECT_FALSE(expectCompleteFiles(out, clean).empty());  // some frames made it, all of them whole
}

// A run estimated above the free space of a real 2 MB file system (about 40 frames of 60 KB OBJs and 20 KB PNGs)
// is refused before it writes anything: exit 2, the mount left empty, the message giving both sizes.
TEST_F(SmallTmpfs, RunAboveTheFreeSpaceIsRefusedAtOnce) {
  if (!mount()) GTEST_SKIP() << "cannot mount a tmpfs here (" << reason_ << "): needs root outside a container";
  const fs::path file = scene(8, 2.0), log = dir() / "log.txt";
  EXPECT_EQ(runWobble(args(file, mount_ / "out", "128x72"), log), 2) << slurpFile(log);
  const std::string message = slurpFile(log);
  EXPECT_NE(message.find("above the 2.0 MB free"), std::string::npos) << message;
  EXPECT_NE(message.find("fewer frames"), std::string::npos) << message;
  EXPECT_TRUE(fs::is_empty(mount_));
}

}  // namespace
}  // namespace wobble
