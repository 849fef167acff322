// Sweeps in farm pieces (app/study/farm_pieces.h): `wobble study stability` and `wobble compare` split with --piece
// I/N into one folder and gathered with --gather give the bytes of a one-machine run (the stability CSV and Markdown;
// the comparison's frames, video, variant folders and numbers but for the times); a piece run again resumes; --piece
// out of range or against an earlier piece of another N or another sweep in the folder, and --gather before every
// piece is done, are exit 2 naming the flag and what is allowed.
#include <gtest/gtest.h>

#include <regex>
#include <sstream>

#include "app/output/external_program.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using testing::runWobble;
using testing::slurpFile;

class FarmPieces : public testing::ScratchDir {
 protected:
  int wobble(const std::string& arguments) { return runWobble(arguments, dir() / "log.txt"); }
  std::string log() const { return slurpFile(dir() / "log.txt"); }
  void expectRefused(const std::string& arguments, const std::vector<std::string>& parts) {
    EXPECT_EQ(wobble(arguments), 2) << arguments << ": " << log();
    for (const std::string& part : parts) EXPECT_NE(log().find(part), std::string::npos) << part << " in " << log();
  }
  fs::path scene() {
    return write("small.toml", R"([simulation]
dt = 0.002
duration = 0.25
fps = 20

[bodies.jelly]
type = "jelly"
n = 3
size = 1.0
center = [0, 0.8, 0]
ks = 1000
kd = 5
color = [0.2, 0.5, 0.9]

[colliders.floor]
type = "plane"
size = 10
texture = "checker"

[camera]
position = [1, 2, 4]
look_at = [0, 0.5, 0]
follow = "jelly"

[render]
samples = 2
)");
  }
};

// compare.md's table without its time columns (simulate, per step, per step vs cheapest, wall), and its other lines
// but the one naming how many runs shared the machine.
std::string withoutTimes(const std::string& markdown) {
  std::istringstream in(markdown);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (line.find("run(s) at a time") != std::string::npos) continue;
    if (!line.starts_with("|")) {
      out += line + "\n";
      continue;
    }
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, '|');)
      cells.push_back(std::regex_replace(cell, std::regex("^ +| +$"), ""));
    // "", 8 columns of numbers and outcomes, 4 of times, the folder
    for (std::size_t i = 0; i < cells.size(); ++i)
      if (i < 9 || i == 13) out += cells[i] + "|";
    out += "\n";
  }
  return out;
}

TEST_F(FarmPieces, StabilityStudyInPiecesIsTheOneMachineStudy) {
  const std::string study = "study stability " + scene().string() +
                            " --integrators explicit-euler,rk4 --ks-points 2 --dt-points 2 --ks-min 1e3 --ks-max 1e5 "
                            "--dt-min 1e-3 --dt-max 1e-2 --duration 0.05 --no-contact --jobs 1 --out ";
  const fs::path one = dir() / "one", split = dir() / "split";
  ASSERT_EQ(wobble(study + one.string()), 0) << log();
  // 2 integrators x (2 ks rows + 2 users' cases) = 8 rows: pieces of 3, 3 and 2.
  for (const char* piece : {"2/3", "1/3", "3/3"}) {
    ASSERT_EQ(wobble(study + split.string() + " --piece " + piece), 0) << log();
    EXPECT_NE(log().find("(0 kept from an earlier run)"), std::string::npos) << log();
    EXPECT_FALSE(fs::exists(split / "stability.csv"));
  }
  ASSERT_EQ(wobble(study + split.string() + " --piece 2/3"), 0) << log();  // again: resumes, runs nothing
  EXPECT_NE(log().find("rows 4 to 6 of 8 (3 kept from an earlier run)"), std::string::npos) << log();
  ASSERT_EQ(wobble(study + split.string() + " --gather"), 0) << log();
  EXPECT_EQ(slurpFile(split / "stability.csv"), slurpFile(one / "stability.csv"));
  EXPECT_EQ(slurpFile(split / "stability.md"), slurpFile(one / "stability.md"));
  for (const char* plot : {"stability-explicit-euler.png", "stability-rk4.png"})
    if (fs::exists(one / plot)) EXPECT_EQ(slurpFile(split / plot), slurpFile(one / plot)) << plot;

  // Bad pieces: out of range, against the folder's earlier pieces, gathering too early.
  expectRefused(study + split.string() + " --piece 4/3", {"--piece 4/3", "I must be 1 to 3"});
  expectRefused(study + split.string() + " --piece 0/3", {"--piece 0/3", "I must be 1 to 3"});
  expectRefused(study + split.string() + " --piece two", {"--piece 'two'", "expected I/N"});
  expectRefused(study + dir().string() + "/other --piece 1/9", {"--piece 1/9", "N must be 1 to 8"});
  expectRefused(study + split.string() + " --piece 1/2", {"--piece 1/2", "holds pieces of 3", "--piece I/3"});
  expectRefused(study + split.string() + " --piece 1/3 --strain-bound 0.4", {"--piece 1/3", "another stability"});
  const fs::path partial = dir() / "partial";
  ASSERT_EQ(wobble(study + partial.string() + " --piece 1/3"), 0) << log();
  expectRefused(study + partial.string() + " --gather", {"--gather", "piece(s) 2/3, 3/3"});
  expectRefused(study + (dir() / "none").string() + " --gather", {"--gather", "no piece"});
}

TEST_F(FarmPieces, CompareInPiecesIsTheOneMachineComparison) {
  const std::string compare = "compare " + scene().string() +
                              " --vary integrator=explicit-euler,midpoint,rk4 --resolution 96x54 --quality preview "
                              "--jobs 1 --out ";
  const fs::path one = dir() / "one", split = dir() / "split";
  ASSERT_EQ(wobble(compare + one.string()), 0) << log();
  ASSERT_EQ(wobble(compare + split.string() + " --piece 2/2"), 0) << log();
  EXPECT_NE(log().find("variants 3 to 3 of 3"), std::string::npos) << log();
  ASSERT_EQ(wobble(compare + split.string() + " --piece 1/2"), 0) << log();
  EXPECT_FALSE(fs::exists(split / "compare.md"));
  EXPECT_FALSE(fs::exists(split / "frames"));
  ASSERT_EQ(wobble(compare + split.string() + " --piece 1/2"), 0) << log();  // resumes: nothing to run
  EXPECT_NE(log().find("(2 kept from an earlier run)"), std::string::npos) << log();
  ASSERT_EQ(wobble(compare + split.string() + " --gather"), 0) << log();

  int frames = 0;
  for (const auto& e : fs::directory_iterator(one / "frames")) {
    ++frames;
    EXPECT_TRUE(slurpFile(e.path()) == slurpFile(split / "frames" / e.path().filename())) << e.path().filename();
  }
  EXPECT_EQ(frames, 5);
  if (fs::exists(one / "compare.mp4")) EXPECT_TRUE(slurpFile(one / "compare.mp4") == slurpFile(split / "compare.mp4"));
  for (const char* variant : {"1_explicit-euler", "2_midpoint", "3_rk4"})
    for (int k = 1; k <= 5; ++k) {
      const fs::path obj = fs::path(variant) / "mesh" / ("jelly_000" + std::to_string(k) + ".obj");
      EXPECT_TRUE(slurpFile(one / obj) == slurpFile(split / obj)) << obj;
    }
  const std::string gathered =
      std::regex_replace(slurpFile(split / "compare.md"), std::regex(split.string()), one.string());
  EXPECT_EQ(withoutTimes(gathered), withoutTimes(slurpFile(one / "compare.md")));

  expectRefused(compare + split.string() + " --piece 3/2", {"--piece 3/2", "I must be 1 to 2"});
  expectRefused(compare + split.string() + " --piece 1/4", {"--piece 1/4", "N must be 1 to 3"});
  expectRefused(compare + split.string() + " --piece 1/3", {"--piece 1/3", "holds pieces of 2"});
}

}  // namespace
}  // namespace wobble
