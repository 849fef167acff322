// A full disk during `wobble run`: every write is checked, the run fails at the first error (exit 1) naming the file
// and "No space left on device", no temporary file stays, and every file with a final name is complete (the bytes
// of a clean run). Injected (WOBBLE_FAIL_WRITE_AFTER, io/atomic_file.h) at every kind of write: before any byte, after
// a short write() stored part of the file, and at close() once all of it is written; and for real on a small tmpfs
// where the test may mount one.
#include <sys/mount.h>

#include <cerrno>
#include <cstring>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/output/external_program.h"
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

  // `wobble run` with the N-th checked write (or close) failing as `how` says (atomic_file.h: "", ":short" or
  // ":close"): exit 1 naming the file and the reason, nothing half-written, no report.
  void expectCleanFailure(const fs::path& file, const fs::path& clean, int n, const std::string& how) {
    const fs::path out = dir() / ("fail" + std::to_string(n) + how), log = dir() / "log.txt";
    const std::string at = std::to_string(n) + how;
    EXPECT_EQ(runWobble(args(file, out), log, "WOBBLE_FAIL_WRITE_AFTER=" + at), 1) << at << ": " << slurpFile(log);
    const std::string message = slurpFile(log);
    EXPECT_NE(message.find("No space left on device"), std::string::npos) << at << ": " << message;
    EXPECT_NE(message.find(out.string() + "/"), std::string::npos) << at << ": names the file: " << message;
    expectCompleteFiles(out, clean);
    EXPECT_FALSE(fs::exists(out / "run.json")) << at;  // the run failed before its report
  }
};

// texture + 4 frames x (mtl, obj, png, exr) + run.json = 18 checked writes and closes; PNG/EXR are written on another
// thread.
TEST_F(FullDisk, InjectedWriteFailureAtEveryKindOfFile) {
  const fs::path file = scene(), clean = dir() / "clean", log = dir() / "log.txt";
  ASSERT_EQ(runWobble(args(file, clean), log), 0) << slurpFile(log);
  for (int n : {1, 2, 3, 4, 5, 9, 13, 17, 18}) expectCleanFailure(file, clean, n, "");
}

// The disk fills during a write(): part of the file is on disk (under its temporary name) when the error comes.
// And a close() that reports the error after every write() succeeded.
TEST_F(FullDisk, InjectedShortWriteAndFailingCloseAtEveryKindOfFile) {
  const fs::path file = scene(), clean = dir() / "clean", log = dir() / "log.txt";
  ASSERT_EQ(runWobble(args(file, clean), log), 0) << slurpFile(log);
  for (const std::string how : {":short", ":close"})
    for (int n : {1, 2, 3, 4, 5, 9, 13, 17, 18}) expectCleanFailure(file, clean, n, how);
}

// A real full file system: a small tmpfs (2 MB, or 64 MB with room for 40 files). Mounted by the test where it may
// (root outside a restricted container); elsewhere by the run's own shell in a user and mount namespace of its own
// (unshare(1): an unprivileged user may mount a tmpfs there where the kernel allows user namespaces), which copies the
// output out before the namespace and its tmpfs go. Skipped, saying why, only where neither is allowed.
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
  // `wobble arguments > log` in a new user and mount namespace on a tmpfs mounted with `options` at mount_, its output
  // folder `out` copied to `copy` afterwards. The exit status, or -1 (reason_ says why) when the namespace or the
  // mount is refused.
  int runInNamespace(const std::string& arguments, const fs::path& log, const fs::path& out, const fs::path& copy,
                     const std::string& options) {
    const fs::path mounted = dir() / "mounted", said = dir() / "unshare.txt";
    const std::string script = "mount -t tmpfs -o " + options + " tmpfs " + mount_.string() + " && touch " +
                               mounted.string() + " || exit 99; " + WOBBLE_BINARY + " " + arguments + " > " +
                               log.string() + " 2>&1; status=$?; cp -a " + out.string() + " " + copy.string() +
                               "; exit $status";
    const int status =
        std::system(("unshare --user --map-root-user --mount sh -c '" + script + "' 2> " + said.string()).c_str());
    if (!fs::exists(mounted)) {
      reason_ += "; unshare --user --mount: " + slurpFile(said);
      return -1;
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  fs::path mount_;
  bool mounted_ = false;
  std::string reason_;
};

// The disk budget (app/output/disk_budget.h) refuses a run estimated above the free space before it writes, so the disk
// here fills with files, not bytes: 64 MB but room for 40 files (ENOSPC all the same).
TEST_F(SmallTmpfs, RunFailsCleanlyWhenTheDiskFills) {
  // About 40 frames of an OBJ, MTL, PNG and EXR each: more than 40 files.
  const char* options = "size=64m,nr_inodes=40";
  const fs::path file = scene(8, 2.0), clean = dir() / "clean", log = dir() / "log.txt";
  const bool mounted = mount(options);
  const fs::path out = mount_ / "out";
  fs::path written = out;  // where the run's files are checked
  int status = -1;
  if (mounted) {
    ASSERT_EQ(runWobble(args(file, clean, "128x72"), log), 0) << slurpFile(log);
    status = runWobble(args(file, out, "128x72"), log);
  } else {
    if (!findProgram("unshare")) GTEST_SKIP() << "cannot mount a tmpfs here (" << reason_ << ") and no unshare";
    written = dir() / "copied";
    status = runInNamespace(args(file, out, "128x72"), log, out, written, options);
    if (status < 0) GTEST_SKIP() << "cannot mount a tmpfs here (" << reason_ << ")";
    ASSERT_EQ(runWobble(args(file, clean, "128x72"), log.string() + ".clean"), 0) << slurpFile(log.string() + ".clean");
  }
  EXPECT_EQ(status, 1) << slurpFile(log);
  const std::string message = slurpFile(log);
  EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
  EXPECT_NE(message.find(out.string() + "/"), std::string::npos) << message;
  EXPECT_FALSE(expectCompleteFiles(written, clean).empty());  // some frames made it, all of them whole
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
