// Sweeps in farm pieces (app/study/farm_pieces.h): every `wobble study` kind (stability, accuracy, render) and
// `wobble compare` split with --piece I/N into one folder and gathered with --gather give the bytes of a one-machine
// run (the stability CSV and Markdown; the accuracy and render studies' tables but for their times, the render
// study's images; the comparison's frames, video, variant folders and numbers but for the times); a piece run again
// resumes; --piece out of range or against an earlier piece of another N or another sweep in the folder, --gather
// before every piece is done, and a kept result altered since, are exit 2 naming the flag (or file) and what is
// allowed.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>

#include "app/output/external_program.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"
#include "tests/app/small_scene.h"

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
  // The command run on one machine into one(), then into split() piece by piece in `order` (none finds an earlier
  // run, none writes the report), `again` run a second time (it resumes, saying `kept`), then gathered.
  void runInPieces(const std::string& command, const std::vector<std::string>& order, const std::string& report,
                   const std::string& again, const std::string& kept) {
    ASSERT_EQ(wobble(command + one().string()), 0) << log();
    for (const std::string& piece : order) {
      ASSERT_EQ(wobble(command + split().string() + " --piece " + piece), 0) << log();
      EXPECT_NE(log().find("(0 kept from an earlier run)"), std::string::npos) << log();
      EXPECT_FALSE(fs::exists(split() / report));
    }
    ASSERT_EQ(wobble(command + split().string() + " --piece " + again), 0) << log();
    EXPECT_NE(log().find(kept), std::string::npos) << log();
    ASSERT_EQ(wobble(command + split().string() + " --gather"), 0) << log();
  }
  fs::path one() const { return dir() / "one"; }
  fs::path split() const { return dir() / "split"; }

  // The small scene's jelly, dropped on a checked floor, the camera following it: 5 frames.
  fs::path scene() {
    copyCatTexture();
    return write("small.toml", testing::smallSceneText({.duration = "0.25",
                                                        .center = "[0, 0.8, 0]",
                                                        .jelly = "ks = 1000\nkd = 5\n",
                                                        .floor = "size = 10\ntexture = \"checker\"\n",
                                                        .rest = testing::kFollowCamera}));
  }
};

// A table's text (a CSV, or Markdown's | rows) without the columns whose header cell `drop` names (the times, which
// are each run's where it ran); other lines as they are.
std::string withoutColumns(const std::string& text, char separator, const std::vector<std::string>& drop) {
  std::istringstream in(text);
  std::vector<bool> keep;
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (separator == '|' && !line.starts_with("|")) {
      out += line + "\n";
      continue;
    }
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, separator);)
      cells.push_back(std::regex_replace(cell, std::regex("^ +| +$"), ""));
    if (keep.empty())
      for (const std::string& cell : cells) keep.push_back(std::find(drop.begin(), drop.end(), cell) == drop.end());
    for (std::size_t i = 0; i < cells.size(); ++i)
      if (i >= keep.size() || keep[i]) out += cells[i] + separator;
    out += "\n";
  }
  return out;
}

// compare.md without its time columns, and its other lines but the one naming how many runs shared the machine.
std::string withoutTimes(const std::string& markdown) {
  return withoutColumns(std::regex_replace(markdown, std::regex(".*run\\(s\\) at a time.*\n"), ""), '|',
                        {"simulate (s)", "per step (us)", "per step vs cheapest", "wall (s)"});
}

TEST_F(FarmPieces, StabilityStudyInPiecesIsTheOneMachineStudy) {
  const std::string study = "study stability " + scene().string() +
                            " --integrators explicit-euler,rk4 --ks-points 2 --dt-points 2 --ks-min 1e3 --ks-max 1e5 "
                            "--dt-min 1e-3 --dt-max 1e-2 --duration 0.05 --no-contact --jobs 1 --out ";
  // 2 integrators x (2 ks rows + 2 users' cases) = 8 rows: pieces of 3, 3 and 2.
  runInPieces(study, {"2/3", "1/3", "3/3"}, "stability.csv", "2/3", "rows 4 to 6 of 8 (3 kept from an earlier run)");
  EXPECT_EQ(slurpFile(split() / "stability.csv"), slurpFile(one() / "stability.csv"));
  EXPECT_EQ(slurpFile(split() / "stability.md"), slurpFile(one() / "stability.md"));
  for (const char* plot : {"stability-explicit-euler.png", "stability-rk4.png"})
    if (fs::exists(one() / plot)) {
      EXPECT_EQ(slurpFile(split() / plot), slurpFile(one() / plot)) << plot;
    }

  // Bad pieces: out of range, against the folder's earlier pieces, gathering too early.
  expectRefused(study + split().string() + " --piece 4/3", {"--piece 4/3", "I must be 1 to 3"});
  expectRefused(study + split().string() + " --piece 0/3", {"--piece 0/3", "I must be 1 to 3"});
  expectRefused(study + split().string() + " --piece two", {"--piece 'two'", "expected I/N"});
  expectRefused(study + dir().string() + "/other --piece 1/9", {"--piece 1/9", "N must be 1 to 8"});
  expectRefused(study + split().string() + " --piece 1/2", {"--piece 1/2", "holds pieces of 3", "--piece I/3"});
  expectRefused(study + split().string() + " --piece 1/3 --strain-bound 0.4", {"--piece 1/3", "another stability"});
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
  if (fs::exists(one / "compare.mp4")) {
    EXPECT_TRUE(slurpFile(one / "compare.mp4") == slurpFile(split / "compare.mp4"));
  }
  for (const char* variant : {"1_explicit-euler", "2_midpoint", "3_rk4"})
    for (int k = 1; k <= 5; ++k) {
      const fs::path obj = fs::path(variant) / "mesh" / ("jelly_000" + std::to_string(k) + ".obj");
      EXPECT_TRUE(slurpFile(one / obj) == slurpFile(split / obj)) << obj;
    }
  const std::string gathered =
      std::regex_replace(slurpFile(split / "compare.md"), std::regex(split.string()), one.string());
  EXPECT_EQ(withoutTimes(gathered), withoutTimes(slurpFile(one / "compare.md")));
  EXPECT_NE(gathered.find("gathered from 2 pieces run apart"), std::string::npos) << gathered;
  EXPECT_EQ(gathered.find("written); 1 run(s) at a time"), std::string::npos) << gathered;

  expectRefused(compare + split.string() + " --piece 3/2", {"--piece 3/2", "I must be 1 to 2"});
  expectRefused(compare + split.string() + " --piece 1/4", {"--piece 1/4", "N must be 1 to 3"});
  expectRefused(compare + split.string() + " --piece 1/3", {"--piece 1/3", "holds pieces of 2"});
}

TEST_F(FarmPieces, AccuracyStudyInPiecesIsTheOneMachineStudy) {
  const std::string study = "study accuracy " + scene().string() +
                            " --integrators explicit-euler,rk4 --duration 0.1 --kmin 4 --kmax 6 --samples 4 "
                            "--repeats 0 --out ";
  // The reference, its twin and 2 integrators x 3 steps = 8 runs: pieces of 3, 3 and 2; the reference's own piece
  // last, so the others ran without it.
  runInPieces(study, {"3/3", "2/3", "1/3"}, "accuracy.csv", "1/3", "runs 1 to 3 of 8 (3 kept from an earlier run)");
  const std::vector<std::string> times = {"seconds"};
  const std::string gathered = slurpFile(split() / "accuracy.csv");
  EXPECT_EQ(withoutColumns(gathered, ',', times), withoutColumns(slurpFile(one() / "accuracy.csv"), ',', times));
  EXPECT_NE(gathered.find("rk4,0.0015625"), std::string::npos) << gathered;  // every point is there
  const auto fits = [](const std::string& md) {
    return md.substr(md.find("## Fitted"), md.find("## Fastest") - md.find("## Fitted"));
  };
  EXPECT_EQ(fits(slurpFile(split() / "accuracy.md")), fits(slurpFile(one() / "accuracy.md")));

  expectRefused(study + split().string() + " --piece 1/9", {"--piece 1/9", "N must be 1 to 8"});
  expectRefused(study + split().string() + " --piece 1/2", {"--piece 1/2", "holds pieces of 3", "--piece I/3"});
  expectRefused(study + split().string() + " --piece 1/3 --reference rk45", {"--piece 1/3", "another accuracy"});
  // A kept trajectory altered since its piece wrote it: the gathering names it.
  std::ofstream(split() / "pieces/accuracy/item-0005.bin", std::ios::binary | std::ios::app) << "x";
  expectRefused(study + split().string() + " --gather", {"--gather", "piece(s) 2/3"});
  const fs::path altered = split() / "pieces/accuracy/item-0004.bin";
  std::string bytes = slurpFile(altered);
  bytes[8] ^= 1;
  std::ofstream(altered, std::ios::binary) << bytes;
  ASSERT_EQ(wobble(study + split().string() + " --piece 2/3"), 0) << log();  // runs item 5 again, keeps item 4's size
  expectRefused(study + split().string() + " --gather", {"item-0004.bin", "altered"});
}

TEST_F(FarmPieces, RenderStudyInPiecesIsTheOneMachineStudy) {
  const std::string study = "study render " + scene().string() +
                            " --frame 3 --resolution 48x27 --reference-spp 16 --max-spp 4 --variants "
                            "sobol,sobol+denoise,adaptive --thresholds 0.1 --out ";
  // The reference's two halves, 2 variants x 3 sample counts and one threshold: 9 renders in pieces of 3, 2, 2, 2.
  runInPieces(study, {"4/4", "2/4", "1/4", "3/4"}, "render.csv", "3/4",
              "renders 6 to 7 of 9 (2 kept from an earlier run)");
  const std::vector<std::string> times = {"seconds", "denoise_seconds"};
  EXPECT_EQ(withoutColumns(slurpFile(split() / "render.csv"), ',', times),
            withoutColumns(slurpFile(one() / "render.csv"), ',', times));
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(one())) {
    const fs::path name = fs::relative(e.path(), one());
    if (!e.is_regular_file() || name.extension() == ".csv" || name.extension() == ".md" || name.stem() == "render")
      continue;  // the tables (above) and the plot of error against time
    ++files;
    EXPECT_TRUE(slurpFile(e.path()) == slurpFile(split() / name)) << name;
  }
  EXPECT_GE(files, 7 + 1 + 2 + 2);  // the images, reference.png, its two halves, the exported frame

  expectRefused(study + split().string() + " --piece 5/4", {"--piece 5/4", "I must be 1 to 4"});
  expectRefused(study + split().string() + " --piece 1/10", {"--piece 1/10", "N must be 1 to 9"});
  expectRefused(study + split().string() + " --piece 2/3", {"--piece 2/3", "holds pieces of 4"});
  expectRefused(study + split().string() + " --piece 2/4 --repeats 2", {"--piece 2/4", "another render"});
  const fs::path altered = split() / "pieces/render/item-0006.bin";
  std::string bytes = slurpFile(altered);
  bytes[0] ^= 1;
  std::ofstream(altered, std::ios::binary) << bytes;
  expectRefused(study + split().string() + " --gather", {"item-0006.bin", "altered"});
}

}  // namespace
}  // namespace wobble
