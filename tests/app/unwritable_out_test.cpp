// An --out that cannot be written is refused at once with the operating system's reason (exit 1), before the disk
// budget is estimated (so never as "above the ... free" with advice to write fewer frames), and nothing is written:
// a folder without write permission (run as an unprivileged user where the test runs as root), a file in the way of
// OUT or of one of its parents, a read-only file system (a tmpfs mounted read-only: by the test as root, else in a user
// and mount namespace of its own; skipped, saying why, where neither is allowed).
#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <gtest/gtest.h>

#include "app/output/external_program.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using testing::runWobble;
using testing::slurpFile;

class UnwritableOut : public testing::ScratchDir {
 protected:
  void TearDown() override {
    if (mounted_) ::umount2(mount_.c_str(), MNT_DETACH);
    testing::ScratchDir::TearDown();
  }
  fs::path scene() {
    return write("small.toml",
                 "[simulation]\ndt = 0.002\nduration = 0.1\nfps = 20\n[bodies.jelly]\ntype = \"jelly\"\nn = 3\n"
                 "[colliders.floor]\ntype = \"plane\"\n[camera]\nresolution = [32, 18]\n[render]\nsamples = 1\n");
  }
  // Exit 1, the reason and OUT named, nothing about the disk budget.
  static void expectRefused(int status, const fs::path& log, const fs::path& out, const std::string& reason) {
    const std::string message = slurpFile(log);
    EXPECT_EQ(status, 1) << message;
    EXPECT_NE(message.find(reason), std::string::npos) << message;
    EXPECT_NE(message.find(out.string() + ": cannot write there"), std::string::npos) << message;
    EXPECT_EQ(message.find("free"), std::string::npos) << "the disk budget spoke: " << message;
  }
  fs::path mount_;
  bool mounted_ = false;
};

TEST_F(UnwritableOut, FolderWithoutWritePermission) {
  const fs::path file = scene(), locked = dir() / "locked", out = locked / "out", log = dir() / "log.txt";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                              fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  // Root writes anywhere: the run is made as the unprivileged user nobody.
  std::string as = "";
  if (::geteuid() == 0) {
    if (!findProgram("setpriv")) GTEST_SKIP() << "running as root, and no setpriv to run wobble as another user";
    as = "setpriv --reuid=65534 --regid=65534 --clear-groups ";
  }
  const int status = std::system(
      (as + WOBBLE_BINARY + " run " + file.string() + " --out " + out.string() + " > " + log.string() + " 2>&1")
          .c_str());
  expectRefused(WIFEXITED(status) ? WEXITSTATUS(status) : -1, log, out, "Permission denied");
  EXPECT_NE(slurpFile(log).find("(" + locked.string() + ")"), std::string::npos) << "names the folder asked";
  EXPECT_FALSE(fs::exists(out));
  fs::permissions(locked, fs::perms::owner_all);
}

TEST_F(UnwritableOut, FileInTheWay) {
  const fs::path file = scene(), log = dir() / "log.txt", in_the_way = write("taken", "a file\n");
  expectRefused(runWobble("run " + file.string() + " --out " + in_the_way.string(), log), log, in_the_way,
                "Not a directory");
  const fs::path below = in_the_way / "out";
  expectRefused(runWobble("run " + file.string() + " --out " + below.string(), log), log, below, "Not a directory");
  EXPECT_NE(slurpFile(log).find("a file is in the way"), std::string::npos) << slurpFile(log);
  EXPECT_EQ(slurpFile(in_the_way), "a file\n");
  // `wobble render` too: a run's sequence re-rendered into a file.
  const fs::path run = dir() / "run";
  ASSERT_EQ(runWobble("run " + file.string() + " --render none --out " + run.string(), log), 0) << slurpFile(log);
  expectRefused(runWobble("render " + run.string() + " --render png --out " + in_the_way.string(), log), log,
                in_the_way, "Not a directory");
}

TEST_F(UnwritableOut, ReadOnlyFileSystem) {
  const fs::path file = scene(), log = dir() / "log.txt";
  mount_ = dir() / "ro";
  fs::create_directories(mount_);
  const fs::path out = mount_ / "out";
  mounted_ = ::mount("tmpfs", mount_.c_str(), "tmpfs", MS_RDONLY, "size=64k") == 0;
  if (mounted_) {
    expectRefused(runWobble("run " + file.string() + " --out " + out.string(), log), log, out, "Read-only file system");
    EXPECT_TRUE(fs::is_empty(mount_));
    return;
  }
  const std::string why = std::strerror(errno);
  if (!findProgram("unshare")) GTEST_SKIP() << "cannot mount a tmpfs here (" << why << ") and no unshare";
  const fs::path mounted = dir() / "mounted", said = dir() / "unshare.txt", listing = dir() / "listing.txt";
  const std::string script = "mount -t tmpfs -o ro,size=64k tmpfs " + mount_.string() + " && touch " +
                             mounted.string() + " || exit 99; " + WOBBLE_BINARY + " run " + file.string() + " --out " +
                             out.string() + " > " + log.string() + " 2>&1; status=$?; ls -A " + mount_.string() +
                             " > " + listing.string() + "; exit $status";
  const int status =
      std::system(("unshare --user --map-root-user --mount sh -c '" + script + "' 2> " + said.string()).c_str());
  if (!fs::exists(mounted))
    GTEST_SKIP() << "cannot mount a read-only tmpfs here (" << why << "; unshare: " << slurpFile(said) << ")";
  expectRefused(WIFEXITED(status) ? WEXITSTATUS(status) : -1, log, out, "Read-only file system");
  EXPECT_EQ(slurpFile(listing), "");
}

}  // namespace
}  // namespace wobble
