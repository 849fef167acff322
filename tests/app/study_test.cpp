// The study commands' pieces against oracles: the order fit on synthetic error tables and on a small real sweep
// (1, 2, 4), the stability classification of one spring against theory's limit (explicit Euler, RK4) and theory's
// limits against docs/numerics.md, the CSV and Markdown rows, a missing gnuplot (clear message, CSV still
// written), and `wobble run --estimate-error` against the exact error of explicit Euler in free fall.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "app/commands/run_command.h"
#include "app/scene/scene_file.h"
#include "app/study/order_fit.h"
#include "app/study/stability_theory.h"
#include "app/study/study_accuracy_report.h"
#include "app/study/study_stability_report.h"
#include "io/text_table.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

std::vector<std::string> lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::string slurp(const fs::path& p) {
  std::stringstream s;
  s << std::ifstream(p).rdbuf();
  return s.str();
}

TEST(OrderFit, SyntheticTables) {
  for (int p : {1, 2, 4}) {
    std::vector<double> h, e;
    for (int k = 4; k <= 9; ++k) {
      h.push_back(std::ldexp(1.0, -k));
      e.push_back(3.7 * std::pow(h.back(), p) * (1 + 0.01 * (k % 2)));  // a little noise
    }
    EXPECT_NEAR(fitOrder(h, e), p, 0.02) << p;
  }
  EXPECT_TRUE(std::isnan(fitOrder({0.1}, {0.01})));                          // one point
  EXPECT_NEAR(fitOrder({0.1, 0.05, 0.025}, {NAN, 0.01, 0.0025}), 2, 1e-12);  // NaN skipped
  EXPECT_EQ(convergenceOrder("rk4"), 4);
  EXPECT_EQ(convergenceOrder("midpoint"), 2);
  EXPECT_EQ(convergenceOrder("backward-euler"), 1);
}

TEST(OrderFit, FitAccuracyGroupsByIntegratorAndSkipsPointsOutOfTheFit) {
  std::vector<AccuracyPoint> points;
  for (int k = 3; k <= 6; ++k) {
    const double h = std::ldexp(1.0, -k);
    points.push_back({.integrator = "midpoint",
                      .dt = h,
                      .mean_step = h,
                      .final_error = h * h,
                      .rms_error = h * h / 2,
                      .in_fit = true});
    points.push_back({.integrator = "rk4",
                      .dt = h,
                      .mean_step = h,
                      .final_error = std::pow(h, 4),
                      .rms_error = std::pow(h, 4),
                      .in_fit = k < 6});
  }
  points.push_back({.integrator = "rk4", .dt = 1, .mean_step = 1, .final_error = 1e9, .diverged = true});
  const auto fits = fitAccuracy(points);
  ASSERT_EQ(fits.size(), 2u);
  EXPECT_EQ(fits[0].integrator, "midpoint");
  EXPECT_NEAR(fits[0].order_final, 2, 1e-9);
  EXPECT_NEAR(fits[0].order_rms, 2, 1e-9);
  EXPECT_EQ(fits[1].points, 3);
  EXPECT_NEAR(fits[1].order_final, 4, 1e-9);
}

class Study : public testing::ScratchDir {
 protected:
  // A small soft cloth swinging from its top edge: smooth, no colliders.
  fs::path smoothScene() {
    return write("swing.toml", R"([simulation]
dt = 0.001
[bodies.cloth]
type = "cloth"
nx = 4
ny = 4
size = [1.0, 1.0]
mass = 0.01
ks = 20.0
kd = 0.2
drag = 0.0
pinned = ["top-edge"]
)");
  }
  AccuracyOptions smallSweep(const std::vector<std::string>& integrators) {
    AccuracyOptions o;
    o.scene = smoothScene();
    o.integrators = integrators;
    o.duration = 0.5;
    o.k_min = 7;
    o.k_max = 10;
    o.tol_min = 4;
    o.tol_max = 7;
    o.repeats = 0;
    o.progress = false;
    return o;
  }
};

TEST_F(Study, RealSweepRecoversOrdersOneTwoFour) {
  const AccuracyResult r = runAccuracyStudy(smallSweep({"explicit-euler", "midpoint", "rk4"}));
  EXPECT_FALSE(r.has_colliders);
  ASSERT_EQ(r.fits.size(), 3u);
  const double expected[] = {1, 2, 4};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(r.fits[i].points, 4) << r.fits[i].integrator;
    EXPECT_NEAR(r.fits[i].order_final, expected[i], 0.25) << r.fits[i].integrator;
    EXPECT_NEAR(r.fits[i].order_rms, expected[i], 0.25) << r.fits[i].integrator;
  }
}

TEST_F(Study, AccuracyFilesHaveTheRowsAndGnuplotMissingIsAMessage) {
  AccuracyOptions o = smallSweep({"rk4", "rk45"});
  o.k_max = 8;
  const AccuracyResult r = runAccuracyStudy(o);
  ASSERT_EQ(r.points.size(), 2u + 4u);  // rk4: k = 7, 8; rk45: rtol 1e-4 .. 1e-7
  const PlotResult plot = writeAccuracyOutputs(r, dir() / "out", (dir() / "no-such-gnuplot").string());
  EXPECT_FALSE(plot.ok);
  EXPECT_NE(plot.message.find("not found"), std::string::npos) << plot.message;
  EXPECT_FALSE(fs::exists(dir() / "out/accuracy.png"));
  const auto csv = lines(dir() / "out/accuracy.csv");
  ASSERT_EQ(csv.size(), 1u + r.points.size());
  EXPECT_EQ(csv[0].rfind("scene,integrator,dt,rtol,", 0), 0u) << csv[0];
  EXPECT_EQ(csv[1].rfind("swing,rk4,0.0039062", 0), 0u) << csv[1];
  const std::string md = slurp(dir() / "out/accuracy.md");
  EXPECT_NE(md.find("| rk4 | 4 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| rk45 | 5 |"), std::string::npos) << md;
  EXPECT_EQ(md.find("not meaningful"), std::string::npos);

  // The same with PATH naming an empty folder and the default program name.
  fs::create_directories(dir() / "empty");
  const std::string saved = std::getenv("PATH") ? std::getenv("PATH") : "";
  setenv("PATH", (dir() / "empty").c_str(), 1);
  const PlotResult missing = writeAccuracyOutputs(r, dir() / "out2");
  setenv("PATH", saved.c_str(), 1);
  EXPECT_FALSE(missing.ok);
  EXPECT_NE(missing.message.find("'gnuplot' was not found"), std::string::npos) << missing.message;
  EXPECT_TRUE(fs::exists(dir() / "out2/accuracy.csv"));
  EXPECT_TRUE(fs::exists(dir() / "out2/accuracy.md"));
}

TEST_F(Study, CollidersAreFlaggedInTheMarkdown) {
  AccuracyResult r;
  r.scene_name = "slope";
  r.has_colliders = true;
  r.duration = 1;
  EXPECT_NE(accuracyMarkdown(r).find("orders below are not meaningful"), std::string::npos);
}

// The shared work-precision writer (work_precision.h) on a synthetic result: one data block per integrator holding
// exactly its finite points (error, RMS error, time), both panels naming every block, and the real gnuplot draws it.
TEST_F(Study, WorkPrecisionPlotHasOneCurvePerIntegratorAndGnuplotDrawsIt) {
  AccuracyResult r;
  r.scene_name = "synthetic";
  r.duration = 1;
  for (int k = 0; k < 3; ++k) {
    AccuracyPoint a{"rk4", 1.0 / (8 << k)}, b{"midpoint", 1.0 / (8 << k)};
    a.final_error = a.rms_error = std::pow(a.dt, 4);
    b.final_error = b.rms_error = std::pow(b.dt, 2);
    a.seconds = b.seconds = 0.01 * (k + 1);
    r.points.push_back(a);
    r.points.push_back(b);
  }
  r.points.push_back({"midpoint", 1.0 / 4});
  r.points.back().diverged = true;  // left out of the plot, though its errors are finite
  r.points.back().final_error = r.points.back().rms_error = 1;
  r.fits = fitAccuracy(r.points);
  const PlotResult plot = writeAccuracyOutputs(r, dir() / "out");
  if (plot.message.find("not found") != std::string::npos) GTEST_SKIP() << plot.message;
  EXPECT_TRUE(plot.ok) << plot.message;
  EXPECT_GT(fs::file_size(dir() / "out/accuracy.png"), 1000u);
  const auto gp = lines(dir() / "out/accuracy.gp");
  std::vector<std::vector<std::string>> blocks;
  for (std::size_t i = 0; i < gp.size(); ++i)
    if (gp[i].rfind("$d", 0) == 0 && gp[i].find("<< EOD") != std::string::npos)
      for (blocks.emplace_back(); gp[++i] != "EOD";) blocks.back().push_back(gp[i]);
  ASSERT_EQ(blocks.size(), 2u);  // rk4, midpoint: in the fits' order
  ASSERT_EQ(blocks[0].size(), 3u);
  ASSERT_EQ(blocks[1].size(), 3u);  // the diverged point is not drawn
  EXPECT_EQ(blocks[0][2],
            io::formatNumber(std::pow(1.0 / 32, 4), 10) + " " + io::formatNumber(std::pow(1.0 / 32, 4), 10) + " 0.03");
  int plots = 0;
  for (const std::string& line : gp)
    if (line.rfind("plot ", 0) == 0) {
      ++plots;
      EXPECT_NE(line.find("$d0 using"), std::string::npos) << line;
      EXPECT_NE(line.find("title 'midpoint'"), std::string::npos) << line;
    }
  EXPECT_EQ(plots, 2);
}

TEST(StabilityTheory, LimitsMatchNumericsTable) {
  EXPECT_NEAR(stableOmegaH("rk4", 0), 2.828, 0.01);
  EXPECT_NEAR(stableOmegaH("symplectic-euler", 0), 2, 0.01);
  EXPECT_NEAR(stableOmegaH("pc-euler", 0), 1, 0.01);
  EXPECT_NEAR(stableOmegaH("explicit-euler", 0.1), 0.2, 0.01);
  EXPECT_NEAR(stableOmegaH("midpoint", 0.1), 1.05, 0.02);
  EXPECT_NEAR(stableOmegaH("rk4", 0.5), 2.623, 0.02);
  EXPECT_LT(stableOmegaH("explicit-euler", 0), 1e-5);  // grows at any step (round-off allows 1e-6)
  EXPECT_TRUE(std::isinf(stableOmegaH("backward-euler", 0)));
}

// One free particle on a spring to a pinned one, along x: omega = sqrt(k / m).
MassSpringSystem spring(double omega, double zeta) {
  Body body;
  body.name = "spring";
  body.kind = "test";
  body.x = VecX::Zero(6);
  body.x[3] = 1.01;  // stretched by 1%
  body.v = VecX::Zero(6);
  body.mass = VecX::Ones(2);
  body.pinned = {true, false};
  body.springs.add(0, 1, 1.0, omega * omega, 2 * zeta * omega, SpringType::Structural);
  MassSpringSystem system(Vec3::Zero());
  system.addBody(std::move(body));
  return system;
}

TEST(StabilityStudy, OneSpringFlipsWhereTheoryPutsTheLimit) {
  struct Case {
    const char* integrator;
    double zeta;
  };
  for (const Case c : {Case{"rk4", 0.0}, Case{"explicit-euler", 0.1}}) {
    // omega = 1e4: a blow-up (|v| > 1000) needs an amplitude of only 0.1, where the spring is still linear.
    const double omega = 1e4, limit = stableOmegaH(c.integrator, c.zeta) / omega;
    MassSpringSystem system = spring(omega, c.zeta);
    EXPECT_NEAR(gershgorinOmegaMax(system), omega * std::sqrt(2.0), 1e-9);  // the bound, sqrt(2) above the truth
    EXPECT_NEAR(powerIterationOmegaMax(system), omega, 1e-6);
    // Grid cells a factor 1.25 apart around the limit: the one below stays stable, the one above blows up.
    const StabilityCell below = classifyCell(system, c.integrator, limit / 1.25, 0.5, 10);
    const StabilityCell above = classifyCell(system, c.integrator, limit * 1.25, 0.5, 10);
    EXPECT_EQ(below.outcome, Outcome::Stable) << c.integrator << " " << below.note;
    EXPECT_EQ(above.outcome, Outcome::BlewUp) << c.integrator << " limit " << limit << " steps " << above.steps
                                              << " strain " << above.max_strain << " speed " << above.max_speed;
  }
}

TEST(StabilityStudy, GainedEnergyIsAnOutcomeOfItsOwn) {
  // Explicit Euler on an undamped spring multiplies the energy by 1 + (omega h)^2 every step: at omega h = 0.2, 50
  // steps make it 7 times the start, with the strain at 3% and the speed far from a blow-up. RK4 at that step loses
  // a little.
  MassSpringSystem gaining = spring(10, 0);
  const StabilityCell cell = classifyCell(gaining, "explicit-euler", 0.02, 1.0, 0.5);
  EXPECT_EQ(cell.outcome, Outcome::GainedEnergy) << cell.note;
  EXPECT_STREQ(toString(cell.outcome), "gained-energy");
  EXPECT_NE(cell.note.find("gained energy at t = "), std::string::npos) << cell.note;
  EXPECT_LT(cell.max_strain, 0.05);
  MassSpringSystem steady = spring(10, 0);
  EXPECT_EQ(classifyCell(steady, "rk4", 0.02, 1.0, 0.5).outcome, Outcome::Stable);
}

// The contact case's cause (docs/energy.md, "Contact that adds no energy"): jelly_stack at ks 1e5 under backward Euler
// at 1/60 s for 1 s, with the scene's own options as the study passes them. With the contacts in the solve (the
// default) the landing is stable; with [contact] in_solve = false the impulses of the pass after the step gain energy.
TEST(StabilityStudy, ContactCaseTakesTheScenesInSolve) {
  for (const bool in_solve : {true, false}) {
    std::vector<std::string> sets = {"bodies.base.ks=1e5", "bodies.top.ks=1e5"};
    if (!in_solve) sets.push_back("contact.in_solve=false");
    SceneFile scene = loadScene(testing::sourceDir() / "scenes/jelly_stack.toml", sets);
    ASSERT_EQ(scene.integrator_options.body_contact_in_solve, in_solve);
    const StabilityCell c = classifyCell(*scene.system, "backward-euler", 1.0 / 60, 1.0, 0.5, scene.integrator_options);
    EXPECT_EQ(c.outcome, in_solve ? Outcome::Stable : Outcome::GainedEnergy) << in_solve << " " << c.note;
    if (in_solve) {
      EXPECT_LT(c.max_strain, 0.05);
    }
  }
}

// The study run again on one thread gives the same cells as r.
void expectSameOnOneThread(StabilityOptions o, const StabilityResult& r) {
  o.jobs = 1;
  const StabilityResult one = runStabilityStudy(o);
  ASSERT_EQ(one.cells.size(), r.cells.size());
  for (std::size_t i = 0; i < r.cells.size(); ++i) {
    EXPECT_EQ(one.cells[i].outcome, r.cells[i].outcome) << i;
    EXPECT_EQ(one.cells[i].steps, r.cells[i].steps) << i;
  }
}

TEST_F(Study, StabilityFilesAndInference) {
  StabilityOptions o;
  o.scene = write("jelly.toml",
                  "[bodies.jelly]\ntype = \"jelly\"\nn = 3\nsize = 1.0\nvelocity = [0, 0, 0]\n"
                  "center = [0, 0.6, 0]\n[colliders.floor]\ntype = \"plane\"\n");
  o.integrators = {"explicit-euler", "backward-euler"};
  o.duration = 0.1;
  o.ks_min = 1e3;
  o.ks_max = 1e5;
  o.ks_points = 2;
  o.dt_min = 1e-3;
  o.dt_max = 1e-2;
  o.dt_points = 3;
  o.cases = {{5e4, 1.2e-3}};
  o.contact_scene.clear();  // the contact case: below
  o.progress = false;
  o.jobs = 2;
  const StabilityResult r = runStabilityStudy(o);
  ASSERT_EQ(r.cells.size(), 2u * (2 * 3 + 1));
  // Backward Euler survives the largest dt, so the smaller ones are inferred.
  int inferred = 0;
  for (const StabilityCell& c : r.cells) inferred += c.integrator == "backward-euler" && c.inferred;
  EXPECT_EQ(inferred, 2 * 2);
  const auto plots = writeStabilityOutputs(r, dir() / "out", (dir() / "no-gnuplot").string());
  ASSERT_EQ(plots.size(), 2u);
  EXPECT_FALSE(plots[0].ok);
  EXPECT_EQ(lines(dir() / "out/stability.csv").size(), 1u + r.cells.size());
  const std::string md = slurp(dir() / "out/stability.md");
  EXPECT_NE(md.find("## The users' cases"), std::string::npos);
  EXPECT_NE(md.find("### explicit-euler"), std::string::npos);
  expectSameOnOneThread(o, r);
}

// The contact case: a stiff 3^3 jelly (ks 1e5) dropped onto another at steps far beyond RK4's limit for that ks
// (theory's dt_max, stability_theory.h): RK4 blows up, backward Euler (no step limit, the contacts in its solve) runs
// to the end, stable: no energy gained, the shape kept. The cells stay out of the maps, and the report and
// the CSV give them a section and a column of their own, in the same order whatever the thread count.
TEST_F(Study, ContactCaseLandsAStiffJellyOnAJelly) {
  StabilityOptions o;
  o.scene =
      write("jelly.toml", "[bodies.jelly]\ntype = \"jelly\"\nn = 2\nsize = 1.0\n[colliders.floor]\ntype = \"plane\"\n");
  o.contact_scene = write("stack.toml",
                          "[bodies.base]\ntype = \"jelly\"\nn = 3\nsize = 1.0\nmass = 0.1\ncenter = [0, 0.52, 0]\n"
                          "[bodies.top]\ntype = \"jelly\"\nn = 3\nsize = 0.8\nmass = 0.1\ncenter = [0.1, 1.6, 0.05]\n"
                          "rotation_axis = [1, 0.3, 1]\nrotation_deg = 30\n[colliders.floor]\ntype = \"plane\"\n");
  o.integrators = {"rk4", "backward-euler"};
  o.duration = 0.05;
  o.ks_min = o.ks_max = 1e3;
  o.ks_points = o.dt_points = 1;
  o.dt_min = o.dt_max = 1e-3;
  o.cases = {};
  o.contact_cases = {{1e5, 1.0 / 60}, {1e5, 1.0 / 120}};
  o.contact_duration = 0.6;  // the top jelly lands at about 0.4 s
  o.progress = false;
  o.jobs = 2;
  const StabilityResult r = runStabilityStudy(o);
  ASSERT_EQ(r.cells.size(), 2u * (1 + 2));
  const auto stack = loadScene(o.contact_scene, {"bodies.base.ks=1e5", "bodies.top.ks=1e5"});
  const double omega = powerIterationOmegaMax(*stack.system), zeta = damperRatio(*stack.system);
  int contact = 0;
  for (const StabilityCell& c : r.cells) {
    if (!c.contact_case) continue;
    ++contact;
    EXPECT_FALSE(c.user_case);
    EXPECT_EQ(c.ks, 1e5);
    if (c.integrator == "rk4") {
      ASSERT_LT(stableStep("rk4", omega, zeta), c.dt / 4);
      EXPECT_EQ(c.outcome, Outcome::BlewUp) << c.dt << " " << c.note;
    } else {
      // Its contacts in its solve: the landing gains no energy (docs/energy.md), and the stack keeps its shape.
      EXPECT_EQ(c.outcome, Outcome::Stable) << c.dt << " " << c.note;
      EXPECT_NEAR(c.end_time, 0.6, 1e-9);
    }
  }
  EXPECT_EQ(contact, 4);
  writeStabilityOutputs(r, dir() / "out", (dir() / "no-gnuplot").string());
  const std::string md = slurp(dir() / "out/stability.md");
  EXPECT_NE(md.find("## Contact: a stiff jelly landing on a jelly"), std::string::npos);
  EXPECT_NE(md.find("BLOW"), std::string::npos);
  const auto csv = lines(dir() / "out/stability.csv");
  ASSERT_EQ(csv.size(), 1u + r.cells.size());
  EXPECT_NE(csv[0].find("contact_case"), std::string::npos);
  EXPECT_EQ(csv.back().rfind("stack,backward-euler,", 0), 0u) << csv.back();
  expectSameOnOneThread(o, r);
}

// A gained-energy contact cell is reported as GAIN in the contact section, not in the maps.
TEST(StabilityReport, ContactCellsHaveTheirOwnSection) {
  StabilityResult r;
  r.scene_name = "jelly";
  r.contact_scene_name = "stack";
  r.contact_scene_file = "stack.toml";
  r.contact_duration = 1;
  r.integrators = {"backward-euler"};
  r.ks = {1e3};
  r.dt = {1e-3};
  StabilityTheory t;
  t.ks = 1e3;
  t.dt_power = t.dt_gershgorin = {std::numeric_limits<double>::infinity()};
  r.theory = {t};
  StabilityCell grid;
  grid.integrator = "backward-euler";
  grid.ks = 1e3;
  grid.dt = 1e-3;
  StabilityCell gain = grid;
  gain.ks = 1e5;
  gain.dt = 1.0 / 60;
  gain.contact_case = true;
  gain.outcome = Outcome::GainedEnergy;
  gain.note = "gained energy at t = 0.45 s, step 27: 900 J from 800 J";
  r.cells = {grid, gain};
  const std::string md = stabilityMarkdown(r);
  const std::size_t section = md.find("## Contact: a stiff jelly landing on a jelly"), maps = md.find("## Maps");
  ASSERT_NE(section, std::string::npos);
  const std::size_t row = md.find("| GAIN |");
  EXPECT_GT(row, section);
  EXPECT_LT(row, maps);
  EXPECT_NE(md.find(gain.note), std::string::npos);
  EXPECT_EQ(md.find("GAIN", maps), std::string::npos);  // the maps hold the grid only
}

TEST_F(Study, EstimateErrorMatchesExplicitEulerInFreeFall) {
  // Explicit Euler's position error in free fall is exactly g t h / 2 (docs/numerics.md); step halving with
  // Richardson order 1 recovers it. The largest is at the last frame, t = 0.9 s. No springs: at this step explicit
  // Euler would amplify round-off in the jelly's stiff overdamped modes (h |lambda| > 2) and blow up.
  RunOptions o;
  o.scene = write("fall.toml",
                  "[simulation]\ndt = 0.01\nduration = 1.0\nfps = 10\n[output]\nobj = false\n"
                  "[bodies.jelly]\ntype = \"jelly\"\nn = 2\nsize = 1.0\nks = 0.0\nkd = 0.0\n");
  o.out = dir() / "out";
  o.render.render = "none";
  o.estimate_error = true;
  o.integrator = "explicit-euler";
  const RunReport r = runScene(o);
  ASSERT_TRUE(r.error_estimate);
  EXPECT_EQ(r.error_estimate->failure, "");
  const double exact = 9.8 * 0.9 * 0.01 / 2;
  EXPECT_EQ(r.error_estimate->order, 1);
  EXPECT_EQ(r.error_estimate->frames, 10);
  EXPECT_NEAR(r.error_estimate->max_error, exact, 1e-9 * exact + 1e-12);
  EXPECT_NEAR(r.error_estimate->final_max_error, exact, 1e-9 * exact + 1e-12);
  EXPECT_NE(slurp(dir() / "out/run.json").find("\"error_estimate\""), std::string::npos);
  // RK4 is exact in free fall: the estimate is round-off.
  o.integrator = "rk4";
  EXPECT_LT(runScene(o).error_estimate->max_error, 1e-12);
}

}  // namespace
}  // namespace wobble
