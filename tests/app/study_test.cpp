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
#include "sim/simulation.h"
#include "tests/app/output_check.h"
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
  // A stability study of RK4 and backward Euler whose map is one short cell, no users' cases: for its contact cases.
  StabilityOptions contactStudy(double duration) {
    StabilityOptions o;
    o.scene = write("jelly.toml",
                    "[bodies.jelly]\ntype = \"jelly\"\nn = 2\nsize = 1.0\n[colliders.floor]\ntype = \"plane\"\n");
    o.integrators = {"rk4", "backward-euler"};
    o.duration = duration;
    o.ks_min = o.ks_max = 1e3;
    o.ks_points = o.dt_points = 1;
    o.dt_min = o.dt_max = 1e-3;
    o.cases = {};
    o.progress = false;
    o.jobs = 2;
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
  o.contact.clear();  // the contact cases: below
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
  StabilityOptions o = contactStudy(0.05);
  const fs::path stack =
      write("stack.toml",
            "[bodies.base]\ntype = \"jelly\"\nn = 3\nsize = 1.0\nmass = 0.1\ncenter = [0, 0.52, 0]\n"
            "[bodies.top]\ntype = \"jelly\"\nn = 3\nsize = 0.8\nmass = 0.1\ncenter = [0.1, 1.6, 0.05]\n"
            "rotation_axis = [1, 0.3, 1]\nrotation_deg = 30\n[colliders.floor]\ntype = \"plane\"\n");
  // the top jelly lands at about 0.4 s
  o.contact = {{"landing", "a stiff jelly landing on a jelly", stack, {{1e5, 1.0 / 60}, {1e5, 1.0 / 120}}, 0.6}};
  const StabilityResult r = runStabilityStudy(o);
  ASSERT_EQ(r.cells.size(), 2u * (1 + 2));
  const auto stiff = loadScene(stack, {"bodies.base.ks=1e5", "bodies.top.ks=1e5"});
  const double omega = powerIterationOmegaMax(*stiff.system), zeta = damperRatio(*stiff.system);
  int contact = 0;
  for (const StabilityCell& c : r.cells) {
    if (c.contact_case.empty()) continue;
    EXPECT_EQ(c.contact_case, "landing");
    // a floor and gravity act: no momentum to keep
    EXPECT_TRUE(std::isnan(c.momentum_drift) && std::isnan(c.angular_momentum_drift));
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
  EXPECT_NE(csv.back().find(",landing,"), std::string::npos) << csv.back();
  expectSameOnOneThread(o, r);
}

// A small jelly shot into a larger one, off its centre, no colliders: the momentum columns against the conservation
// laws and against momenta summed here from the run's own end state. Without gravity only internal forces act
// (springs, dampers, contact between the bodies): RK4 keeps the total momentum to round-off, backward Euler to 0.1%
// (its correction of a solve stopped at a tolerance, docs/body-contact.md "Momentum"). With gravity the momentum is the
// start's plus M g t, and the angular momentum has nothing to be compared with (NaN). The cells come back the same
// from two farm pieces.
TEST_F(Study, FreePairMomentumColumnsKeepTheConservationLaws) {
  const std::string pair =
      "[bodies.bullet]\ntype = \"jelly\"\nn = 3\nsize = 0.3\nmass = 0.02\nks = 2000\nkd = 5\n"
      "center = [-0.8, 0.15, 0.1]\nvelocity = [10, 0, 0]\n"
      "[bodies.target]\ntype = \"jelly\"\nn = 4\nsize = 0.8\nmass = 0.05\nks = 2000\nkd = 5\n"
      "center = [0, 0, 0]\nrotation_axis = [0, 1, 0.3]\nrotation_deg = 20\n";
  const fs::path free = write("pair.toml", "[simulation]\ngravity = [0, 0, 0]\n" + pair);
  const fs::path falling = write("falling.toml", pair);
  StabilityOptions o = contactStudy(0.01);
  const double duration = 0.12;  // they meet at about 0.03 s
  o.contact = {{"free-pair", "a free pair", free, {{2000, 2.5e-4}, {2000, 1.0 / 60}}, duration},
               {"falling", "a falling pair", falling, {{2000, 2.5e-4}}, duration}};
  const StabilityResult r = runStabilityStudy(o);

  int checked = 0;
  for (const StabilityCell& c : r.cells) {
    if (c.contact_case.empty()) continue;
    const bool rk4 = c.integrator == "rk4";
    if (rk4 != (c.dt < 1e-3)) continue;  // RK4 blows up at 1/60 s; backward Euler at the small step: nothing new
    SCOPED_TRACE(c.contact_case + " " + c.integrator + " dt " + std::to_string(c.dt));
    ASSERT_EQ(c.outcome, Outcome::Stable) << c.note;
    ASSERT_NEAR(c.end_time, duration, 1e-12);
    // The same run here, its momenta summed from its particles.
    const SceneFile scene = loadScene(c.contact_case == "falling" ? falling : free, {});
    MassSpringSystem& system = *scene.system;
    Simulation sim(system, makeIntegrator(c.integrator, scene.integrator_options), c.dt);
    const VecX& m = system.mass();
    Vec3 p0 = Vec3::Zero(), l0 = Vec3::Zero(), c0 = Vec3::Zero(), bullet0 = Vec3::Zero();
    double p_scale = 0, l_scale = 0;
    for (int i = 0; i < system.particleCount(); ++i) {
      const Vec3 x = system.initialPositions().segment<3>(3 * i), v = system.initialVelocities().segment<3>(3 * i);
      p0 += m[i] * v, l0 += m[i] * x.cross(v), c0 += m[i] * x, p_scale += m[i] * v.norm();
      if (i < 27) bullet0 += m[i] * v;
    }
    c0 /= m.sum();
    for (int i = 0; i < system.particleCount(); ++i)
      l_scale +=
          m[i] *
          (system.initialPositions().segment<3>(3 * i) - c0).cross(system.initialVelocities().segment<3>(3 * i)).norm();
    // Stepped as the study steps it (to a check every 0.01 s, classifyCell): each advanceTo lands its last step on
    // its end, so other ends would give steps that differ in rounding, which contact's thresholds may amplify.
    const long per_check = std::max(1L, std::lround(0.01 / c.dt));
    for (long k = 1;; ++k) {
      const double t = std::min(duration, double(k * per_check) * c.dt);
      ASSERT_FALSE(sim.advanceTo(t));
      if (t >= duration) break;
    }
    Vec3 p = Vec3::Zero(), l = Vec3::Zero(), bullet = Vec3::Zero();
    for (int i = 0; i < system.particleCount(); ++i) {
      p += m[i] * sim.v().segment<3>(3 * i), l += m[i] * sim.x().segment<3>(3 * i).cross(sim.v().segment<3>(3 * i));
      if (i < 27) bullet += m[i] * sim.v().segment<3>(3 * i);
    }
    ASSERT_GT((bullet - bullet0).norm(), 0.5 * bullet0.norm()) << "the jellies did not meet";
    const Vec3 gravity_impulse = m.sum() * system.gravity() * duration;
    const double drift = (p - p0 - gravity_impulse).norm() / p_scale;
    EXPECT_NEAR(c.momentum_drift, drift, 1e-12);
    EXPECT_LT(c.momentum_drift, rk4 ? 1e-12 : 1e-3);  // round-off; backward Euler's 0.1%
    if (c.contact_case == "falling") {
      EXPECT_GT(gravity_impulse.norm(), 0.1 * p_scale);  // gravity's share is no rounding
      EXPECT_TRUE(std::isnan(c.angular_momentum_drift));
    } else {
      EXPECT_NEAR(c.angular_momentum_drift, (l - l0).norm() / l_scale, 1e-12);
    }
    ++checked;
  }
  EXPECT_EQ(checked, 3);

  // Two farm pieces and a gather: the same cells, momenta included, bit for bit.
  o.out = dir() / "pieces";
  StabilityOptions first = o, second = o, gather = o;
  first.piece = Piece{1, 2};
  second.piece = Piece{2, 2};
  gather.gather = true;
  runStabilityStudy(second);
  runStabilityStudy(first);
  const StabilityResult gathered = runStabilityStudy(gather);
  ASSERT_EQ(gathered.cells.size(), r.cells.size());
  for (std::size_t i = 0; i < r.cells.size(); ++i) {
    EXPECT_EQ(gathered.cells[i].contact_case, r.cells[i].contact_case) << i;
    EXPECT_EQ(std::isnan(gathered.cells[i].momentum_drift), std::isnan(r.cells[i].momentum_drift)) << i;
    if (!std::isnan(r.cells[i].momentum_drift)) {
      EXPECT_EQ(gathered.cells[i].momentum_drift, r.cells[i].momentum_drift) << i;
    }
    if (!std::isnan(r.cells[i].angular_momentum_drift)) {
      EXPECT_EQ(gathered.cells[i].angular_momentum_drift, r.cells[i].angular_momentum_drift) << i;
    }
  }
  writeStabilityOutputs(gathered, dir() / "out", (dir() / "no-gnuplot").string());
  const std::string md = slurp(dir() / "out/stability.md");
  const std::size_t section = md.find("## Contact: a free pair"), falling_section = md.find("## Contact: a falling");
  ASSERT_NE(section, std::string::npos);
  ASSERT_NE(falling_section, std::string::npos);
  EXPECT_NE(md.find("| momentum drift | angular drift |", section), std::string::npos);
  const std::size_t falling_head = md.find("| momentum drift |", falling_section);
  ASSERT_NE(falling_head, std::string::npos);
  EXPECT_EQ(md.find("angular drift", falling_section), std::string::npos) << "no angular momentum under gravity";
  EXPECT_NE(lines(dir() / "out/stability.csv")[0].find("momentum_drift,angular_momentum_drift"), std::string::npos);
}

// The contact cases' flags: an unknown key, a scene without its key, a case not run: exit 2 naming the flag, the value
// and what is allowed, nothing written.
TEST_F(Study, ContactFlagsNameTheAllowedCases) {
  const fs::path out = dir() / "out", log = dir() / "log.txt";
  const std::string study = "study stability --out " + out.string() + " ";
  const auto refused = [&](const std::string& flags, const std::vector<std::string>& parts) {
    EXPECT_EQ(testing::runWobble(study + flags, log), 2) << flags;
    const std::string said = slurp(log);
    for (const std::string& part : parts) EXPECT_NE(said.find(part), std::string::npos) << part << " in " << said;
    EXPECT_FALSE(fs::exists(out)) << flags;
  };
  refused("--contact landing,nope", {"--contact 'nope'", "allowed: landing, free-pair"});
  refused("--contact-scene my.toml", {"--contact-scene 'my.toml'", "expected KEY=FILE"});
  refused("--contact-scene nope=my.toml", {"--contact-scene 'nope'", "allowed: landing, free-pair"});
  refused("--contact free-pair --contact-scene landing=my.toml", {"--contact-scene 'landing=my.toml'", "not run"});
}

// A gained-energy contact cell is reported as GAIN in the contact section, not in the maps.
TEST(StabilityReport, ContactCellsHaveTheirOwnSection) {
  StabilityResult r;
  r.scene_name = "jelly";
  r.contact = {{"landing", "a stiff jelly landing on a jelly", "stack.toml", {{1e5, 1.0 / 60}}, 1}};
  r.contact_scenes = {"stack"};
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
  gain.contact_case = "landing";
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
