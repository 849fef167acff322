// The shipped contact scenes (jelly_stack, jelly_trampoline, cloth_drop), run as `wobble run` runs them, for RK4
// and backward Euler: zero intersecting triangle pairs at every frame by the independent test of
// tests/sim/triangle_intersection.h (Moller 1997): non-adjacent triangles of one body, any two of different bodies.
// Every run ends without an energy-gain stop (docs/energy.md). Also: the trampoline's jelly comes to rest on the cloth,
// the stack's upper jelly ends on top of the lower; run.json counts the contact work; a collision the fail-safe cannot
// resolve stops the run like a blow-up; cloth_sphere's cloth, never near itself, skips nearly every pass.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/commands/run_command.h"
#include "app/output/pc2.h"
#include "app/output/pc2_writer.h"
#include "app/scene/input_error.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"
#include "tests/app/simulate_only.h"
#include "tests/sim/triangle_intersection.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

struct Case {
  const char* scene;
  const char* integrator;
  double dt;        // 0: the scene's
  double duration;  // 0: the scene's; RK4 runs stop after the first impacts, to keep the suite's time modest
};

// jelly_trampoline's jelly has come to rest on the cloth: at the last frame its centre moves slower than 5 cm/s (from
// the last two frames; a hundredth of its landing speed, about 5 m/s: the cloth's drag leaves a faint bob), its lowest
// particle is above the cloth's lowest (it sits in the cloth's sag, not below it), and its centre is below the cloth's
// starting height (it rests on the sagging cloth, not in the air).
void expectJellyAtRestOnCloth(const SceneFile& scene, const VecX& before_last, const VecX& last) {
  ASSERT_GT(before_last.size(), 0);
  const int jelly_first = scene.system->bodies()[1].first, count = scene.system->particleCount();
  const auto center = [&](const VecX& x) {
    Vec3 c = Vec3::Zero();
    for (int i = jelly_first; i < count; ++i) c += particle(x, i);
    return Vec3(c / (count - jelly_first));
  };
  EXPECT_LT((center(last) - center(before_last)).norm() * scene.fps, 0.05);
  double jelly_low = 1e9, cloth_low = 1e9;
  for (int i = 0; i < count; ++i) {
    double& low = i >= jelly_first ? jelly_low : cloth_low;
    low = std::min(low, particle(last, i).y());
  }
  EXPECT_GT(jelly_low, cloth_low);
  EXPECT_LT(center(last).y(), 1.0);  // the cloth starts at y = 1
}

class ContactScene : public testing::ScratchDir, public ::testing::WithParamInterface<Case> {};

TEST_P(ContactScene, NoTrianglesIntersectAtAnyFrame) {
  const Case c = GetParam();
  RunOptions o = testing::simulateOnly(c.scene, dir() / "out", c.integrator, c.dt);
  if (c.duration > 0) o.sets.push_back("simulation.duration=" + std::to_string(c.duration));
  const SceneFile scene = loadRunScene(o);
  testing::ParticleTriangles tris;
  for (std::size_t b = 0; b < scene.system->bodies().size(); ++b)
    testing::addSurface(tris, scene.system->bodies()[b].body.surface, scene.system->bodies()[b].first, int(b));
  int frames = 0, worst = 0;
  std::string first;       // the first intersecting pair seen: frame, bodies, triangles' particles
  VecX last, before_last;  // the last two frames
  o.on_frame = [&](int frame, const VecX& x) {
    ++frames;
    before_last.swap(last);
    last = x;
    std::vector<std::array<int, 2>> pairs;
    worst = std::max(worst, testing::intersectingPairs(tris, x, &pairs));
    if (pairs.empty() || !first.empty()) return;
    std::ostringstream m;
    m << "frame " << frame << ":";
    for (const int t : pairs[0]) {
      m << " body " << tris.body[t] << " triangle (";
      for (const int p : tris.triangles[t]) m << p << " ";
      m << ")";
    }
    first = m.str();
  };
  const RunReport r = runScene(o);
  ASSERT_FALSE(r.blow_up) << r.blow_up_message;
  EXPECT_EQ(frames, scene.frameCount());
  EXPECT_EQ(worst, 0) << c.scene << " " << c.integrator << ", first at " << first;
  std::ifstream in(dir() / "out" / "run.json");
  const auto j = nlohmann::json::parse(in);
  ASSERT_TRUE(j.contains("body_contact"));
  EXPECT_EQ(j["body_contact"]["steps_checked"].get<long>(), r.steps);
  // The bodies did touch. Not asked of cloth_drop under backward Euler at 1/60 s: whether its damped cloth lays its
  // layers within the thickness is chaotic there (a dt differing in the 14th digit decides it), so that case checks
  // only that nothing intersects.
  if (!(std::string(c.scene) == "cloth_drop" && c.dt > 1.0 / 100)) {
    EXPECT_GT(j["body_contact"]["contacts"].get<long>(), 0);
    EXPECT_LT(j["body_contact"]["min_distance_m"].get<double>(), 0.02);
  }
  if (std::string(c.scene) == "jelly_trampoline") expectJellyAtRestOnCloth(scene, before_last, last);
}

INSTANTIATE_TEST_SUITE_P(
    Shipped, ContactScene,
    ::testing::Values(Case{"jelly_stack", "rk4", 0}, Case{"jelly_stack", "backward-euler", 1.0 / 120},
                      Case{"jelly_stack", "backward-euler", 1.0 / 60}, Case{"jelly_trampoline", "rk4", 0},
                      Case{"jelly_trampoline", "backward-euler", 1.0 / 120},
                      Case{"jelly_trampoline", "backward-euler", 1.0 / 60}, Case{"cloth_drop", "rk4", 0},
                      Case{"cloth_drop", "backward-euler", 1.0 / 120}, Case{"cloth_drop", "backward-euler", 1.0 / 60}),
    [](const auto& info) {
      std::string name = std::string(info.param.scene) + "_" + info.param.integrator;
      if (info.param.dt > 0) name += "_" + std::to_string(int(std::lround(1 / info.param.dt)));
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

class SkippedPasses : public testing::ScratchDir {};

// cloth_sphere's cloth under explicit Euler at 1e-4 s (the course's setting) never comes within its thickness of
// itself: run.json counts the passes skipped without detection (sim/contact/candidates/clearance.h), nearly all.
TEST_F(SkippedPasses, ClothSphereSkipsThePassWhereNothingIsNear) {
  RunOptions o = testing::simulateOnly("cloth_sphere", dir() / "out", "explicit-euler", 1e-4);
  o.sets.push_back("simulation.duration=0.3");
  const RunReport r = runScene(o);
  ASSERT_FALSE(r.blow_up) << r.blow_up_message;
  std::ifstream in(dir() / "out" / "run.json");
  const auto j = nlohmann::json::parse(in)["body_contact"];
  EXPECT_EQ(j["steps_checked"].get<long>(), r.steps);
  EXPECT_EQ(j["contacts"].get<long>(), 0);
  EXPECT_GT(j["passes_skipped"].get<long>(), r.steps * 95 / 100);
}

class Stack : public testing::ScratchDir, public ::testing::WithParamInterface<Case> {};

// The upper jelly lands on the lower and stays on it: at the end its centre is above the lower one's top face and
// within its footprint, and it has come to rest (its centre moves less than 2 cm over the last half second).
TEST_P(Stack, UpperJellyEndsOnTopOfTheLower) {
  const Case c = GetParam();
  RunOptions o = testing::simulateOnly("jelly_stack", dir() / "out", c.integrator, c.dt);
  const SceneFile scene = loadRunScene(o);
  const BodySlot &lower = scene.system->bodies()[0], &upper = scene.system->bodies()[1];
  std::vector<VecX> frames;
  o.on_frame = [&](int, const VecX& x) { frames.push_back(x); };
  const RunReport r = runScene(o);
  ASSERT_FALSE(r.blow_up) << r.blow_up_message;
  ASSERT_FALSE(r.energy_gain) << r.energy_gain_message;
  const auto center = [&](const VecX& x, const BodySlot& b) {
    Vec3 sum = Vec3::Zero();
    for (int i = 0; i < b.body.particleCount(); ++i) sum += particle(x, b.first + i);
    return Vec3(sum / b.body.particleCount());
  };
  double lower_top = -1e9;
  const VecX& end = frames.back();
  for (int i = 0; i < lower.body.particleCount(); ++i)
    lower_top = std::max(lower_top, particle(end, lower.first + i).y());
  const Vec3 u = center(end, upper), l = center(end, lower);
  EXPECT_GT(u.y(), lower_top) << c.integrator;
  EXPECT_LT(std::abs(u.x() - l.x()), 0.5) << c.integrator;  // the lower jelly is 1 m wide
  EXPECT_LT(std::abs(u.z() - l.z()), 0.5) << c.integrator;
  const int half_second = int(scene.fps / 2);
  EXPECT_LT((u - center(frames[frames.size() - 1 - half_second], upper)).norm(), 0.02) << c.integrator;
}

INSTANTIATE_TEST_SUITE_P(Shipped, Stack,
                         ::testing::Values(Case{"jelly_stack", "rk4", 0},
                                           Case{"jelly_stack", "backward-euler", 1.0 / 60}),
                         [](const auto& info) {
                           std::string name = info.param.integrator;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// run.json's counters of backward Euler's solve (docs/body-contact.md, Reported) on jelly_stack at 1/60 s for its first
// second (the upper jelly lands at about 0.35 s): with the contacts in the solve it carried pairs, re-solved for the
// active set and for friction; with [contact] in_solve = false the bodies touch all the same (the pass counts them)
// but the solve carries nothing, and its solves are one a step plus the floor's impact and friction solves, exactly.
class ContactCounters : public testing::ScratchDir {};

TEST_F(ContactCounters, InSolveCountersFollowTheKey) {
  for (const bool in_solve : {true, false}) {
    const fs::path out = dir() / (in_solve ? "in_solve" : "pass_alone");
    RunOptions o = testing::simulateOnly("jelly_stack", out, "backward-euler", 1.0 / 60);
    o.stop_on_energy_gain = false;  // the pass alone gains energy at this step (Energy at the impacts)
    o.sets = {"simulation.duration=1.0", "output.pc2=false", "output.obj=false"};
    if (!in_solve) o.sets.push_back("contact.in_solve=false");
    const RunReport r = runScene(o);
    ASSERT_FALSE(r.blow_up) << r.blow_up_message;
    // The pass alone gains energy here (docs/body-contact.md, Energy at the impacts), and the message says what to try.
    EXPECT_EQ(r.energy_gain.has_value(), !in_solve);
    if (r.energy_gain) {
      EXPECT_NE(r.energy_gain_message.find("[contact] in_solve = true"), std::string::npos);
    }
    std::ifstream in(out / "run.json");
    const auto j = nlohmann::json::parse(in);
    const auto& c = j["body_contact"];
    const long steps = j["steps"].get<long>(), impact_solves = j["linear_solver"]["impact_solves"].get<long>(),
               friction_solves = j["linear_solver"]["friction_solves"].get<long>();
    const long pairs = c["pairs_in_solve"].get<long>(), with_pairs = c["steps_with_pairs_in_solve"].get<long>(),
               active = c["active_set_solves"].get<long>();
    const double solves = c["solves_per_step"].get<double>() * double(steps);
    EXPECT_EQ(c["in_solve"], in_solve);
    EXPECT_GT(c["contacts"].get<long>() + c["ccd_hits"].get<long>(), 0) << "the bodies never touched";
    if (in_solve) {
      EXPECT_GT(with_pairs, 0);
      EXPECT_GE(pairs, with_pairs);  // each such step carried at least one
      EXPECT_LE(with_pairs, steps);
      EXPECT_GT(active, 0);
      // Every step solves once; an impact and an active-set change found together share one more solve; friction
      // brought within Coulomb's cone solves again (and may check impacts and pairs again).
      EXPECT_GE(solves + 0.5, double(steps + std::max(impact_solves, active) + friction_solves));
      EXPECT_LE(solves - 0.5, double(steps + impact_solves + active + friction_solves));
    } else {
      EXPECT_EQ(pairs, 0);
      EXPECT_EQ(with_pairs, 0);
      EXPECT_EQ(active, 0);
      EXPECT_NEAR(solves, double(steps + impact_solves + friction_solves), 0.5);
    }
  }
}

// cloth_drop at 30 x 30 under backward Euler at 1/60 s, its first 0.6 s: the sphere stops the cloth's lowest row within
// one step, whose linearized solve made up energy (42 J of the scene's 76 J, and the run's check stopped it); that
// step is solved exactly (docs/energy.md), the run ends without an energy gain, run.json counts the exact steps, and
// the Newton solves are among the run's solves (solves_per_step).
TEST_F(ContactCounters, ExactStepsAreCountedAndKeepTheLandingClothsEnergy) {
  const fs::path out = dir() / "drop";
  RunOptions o = testing::simulateOnly("cloth_drop", out, "backward-euler", 1.0 / 60);
  o.sets = {"simulation.duration=0.6", "output.pc2=false", "output.obj=false", "cloth.nx=30", "cloth.ny=30",
            "cloth.mass=0.0044"};
  const RunReport r = runScene(o);
  ASSERT_FALSE(r.blow_up) << r.blow_up_message;
  EXPECT_FALSE(r.energy_gain) << r.energy_gain_message;
  std::ifstream in(out / "run.json");
  const auto j = nlohmann::json::parse(in);
  const long steps = j["steps"].get<long>(), exact = j["linear_solver"]["exact_steps"].get<long>();
  EXPECT_GE(exact, 1);
  EXPECT_LE(exact, steps / 4) << "exact steps are for the steps whose linearization failed";
  EXPECT_LE(j["energy"]["end"].get<double>(), j["energy"]["start"].get<double>());
  // Each exact step solved at least once more (Newton) beyond the step's own solve.
  EXPECT_GE(j["body_contact"]["solves_per_step"].get<double>() * double(steps), double(steps + exact) - 0.5);
}

// A fail-safe case: the [contact] table before the scene, and whether backward Euler carries the contacts in its solve.
struct Caps {
  const char* name;
  const char* contact;
  bool in_solve;
};

class Sandwich : public testing::ScratchDir {
 protected:
  // `wobble run FILE --render none --out DIR` on the scene with contact_table before it; returns the exit status and
  // keeps what it said and its run.json.
  int run(const std::string& name, const std::string& contact_table) {
    const fs::path file = write(name + ".toml", contact_table + kScene), log = dir() / (name + ".log");
    const int status =
        testing::runWobble("run " + file.string() + " --render none --out " + (dir() / name).string(), log);
    said = testing::slurpFile(log);
    std::ifstream in(dir() / name / "run.json");
    json = nlohmann::json::parse(in);
    return status;
  }
  // A sandwich under backward Euler at 0.01 s, a frame a step: a 3^3 jelly resting on the floor, a light cloth 4 cm
  // above it, and a smaller jelly falling onto the cloth at 20 m/s, which it reaches in the fifth step. A rigid impact
  // zone of the falling jelly's face and the cloth under it moves on with most of the jelly's momentum, 20 cm in a
  // step, and meets the lower jelly within the same step: one round of impact zones cannot end such a step clean.
  static constexpr const char* kScene = R"(
[simulation]
integrator = "backward-euler"
dt = 0.01
duration = 0.3
fps = 100
[output]
pc2 = true
[bodies.base]
type = "jelly"
n = 3
size = 1.0
center = [0.0, 0.52, 0.0]
[bodies.sheet]
type = "cloth"
nx = 8
ny = 8
size = [1.2, 1.2]
center = [0.0, 1.06, 0.0]
mass = 0.05
ks = 2000.0
kd = 5.0
[bodies.top]
type = "jelly"
n = 3
size = 0.6
center = [0.05, 2.2, -0.05]
velocity = [0.0, -20.0, 0.0]
[colliders.floor]
type = "plane"
)";
  // The scene written by run(name) run again in this process (no files): each frame it writes, counted in frames,
  // has no two triangles intersecting by the independent test.
  RunReport runCheckingFrames(const std::string& name, int& frames) {
    RunOptions o;
    o.scene = dir() / (name + ".toml");
    o.out = dir() / (name + "_again");
    o.render.render = "none";
    o.progress = false;
    const SceneFile scene = loadRunScene(o);
    testing::ParticleTriangles tris;
    for (std::size_t b = 0; b < scene.system->bodies().size(); ++b)
      testing::addSurface(tris, scene.system->bodies()[b].body.surface, scene.system->bodies()[b].first, int(b));
    o.on_frame = [&](int frame, const VecX& x) {
      ++frames;
      EXPECT_EQ(testing::intersectingPairs(tris, x), 0) << "frame " << frame;
    };
    return runScene(o);
  }
  std::string said;
  nlohmann::json json;
};

class FailSafe : public Sandwich, public ::testing::WithParamInterface<Caps> {};

// The fail-safe reached as a user reaches it: the pass's caps at their least in [contact] (no rounds of collision
// impulses, one round of rigid impact zones), with backward Euler's contacts in its solve (the default) or left to the
// pass alone (in_solve = false). The run stops like a blow-up: exit 3, a message naming the integrator, the step, the
// time, what is left and what to try, run.json saying so, and every frame before the failing step kept (OBJ files and
// point caches), each free of intersections by the independent test.
TEST_P(FailSafe, UnresolvedCollisionStopsTheRunWithExit3) {
  const Caps c = GetParam();
  ASSERT_EQ(run("capped", c.contact), 3) << said;
  for (const char* part : {"contact between bodies failed", "integrator backward-euler", "step ",
                           "t = ", "between body surfaces left after 1 round of rigid impact zones", "particle",
                           "--dt 0.0025", "a larger contact thickness", "zone_iterations = 1", "ccd_iterations = 0"})
    EXPECT_NE(said.find(part), std::string::npos) << part << " missing from: " << said;
  // The solve is suggested only where it was left out.
  EXPECT_EQ(said.find("[contact] in_solve = true") != std::string::npos, !c.in_solve) << said;
  EXPECT_EQ(json["blew_up"], true);
  const long step = json["blow_up"]["step"].get<long>();
  EXPECT_EQ(json["steps"].get<long>(), step);
  EXPECT_NEAR(json["blow_up"]["time"].get<double>(), 0.01 * double(step), 1e-12);
  EXPECT_NE(said.find(json["blow_up"]["message"].get<std::string>()), std::string::npos);
  EXPECT_NE(said.find("step " + std::to_string(step) + ", t = "), std::string::npos);
  const auto& contact = json["body_contact"];
  EXPECT_EQ(contact["in_solve"], c.in_solve);
  EXPECT_EQ(contact["pairs_in_solve"].get<long>() > 0, c.in_solve);
  EXPECT_EQ(contact["ccd_hits"].get<long>(), 0);  // no rounds of impulses: every collision went to impact zones
  EXPECT_GT(contact["failsafe_activations"].get<long>(), 0);
  EXPECT_GT(contact["largest_impact_zone"].get<int>(), 0);
  // Frame k holds t = (k - 1) dt, so frames 1 .. step were written before the failing step, and kept, as OBJ files and
  // in each body's point cache.
  const int written = json["frames"]["written"].get<int>();
  EXPECT_EQ(written, step);
  EXPECT_GT(written, 3);
  EXPECT_NE(said.find("wrote " + std::to_string(written) + " frame(s)"), std::string::npos) << said;
  for (const char* body : {"base", "sheet", "top"}) {
    for (int f = 1; f <= written + 1; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "%s_%04d.obj", body, f);
      EXPECT_EQ(fs::exists(dir() / "capped" / "mesh" / name), f <= written) << name;
    }
    EXPECT_EQ(readPc2(Pc2Writer::path(dir() / "capped" / "mesh", body)).header.samples, written) << body;
  }
  // The kept frames, from the same run in this process: no two triangles intersect in any of them.
  int frames = 0;
  const RunReport r = runCheckingFrames("capped", frames);
  ASSERT_TRUE(r.blow_up);
  EXPECT_EQ(r.blow_up->step, step);
  EXPECT_EQ(frames, written);
}

// The control: with the default [contact] settings the same scene runs to its end, without the fail-safe and without
// an energy-gain stop.
TEST_F(Sandwich, DefaultContactSettingsRunItToTheEnd) {
  ASSERT_EQ(run("default", ""), 0) << said;
  EXPECT_EQ(json["frames"]["written"].get<int>(), 30);
  EXPECT_EQ(json["blew_up"], false);
  EXPECT_EQ(json["gained_energy"], false);
  EXPECT_EQ(json["body_contact"]["in_solve"], true);
  EXPECT_GT(json["body_contact"]["pairs_in_solve"].get<long>(), 0);
}

// A step the pass cannot end clean within its caps is taken again as two halves ([contact] split_steps, 4 by
// default): the capped sandwich that stops with exit 3 above (split_steps = 0) runs to its end when its failing steps
// may be halved, with every written frame free of intersections by the independent test, no energy gained, and
// run.json counting the halved steps. A step is still a step of dt in what the run reports: as many as without caps.
TEST_F(Sandwich, AStepThePassFailsOnIsTakenAgainInHalves) {
  ASSERT_EQ(run("default", ""), 0) << said;
  EXPECT_EQ(json["body_contact"]["split_steps"].get<long>(), 0);
  const long steps = json["steps"].get<long>();
  const std::string capped = "[contact]\nccd_iterations = 0\nzone_iterations = 1\n";
  ASSERT_EQ(run("halved", capped), 0) << said;
  EXPECT_EQ(json["steps"].get<long>(), steps);
  EXPECT_EQ(json["frames"]["written"].get<int>(), 30);
  EXPECT_EQ(json["blew_up"], false);
  EXPECT_EQ(json["gained_energy"], false);
  const auto& contact = json["body_contact"];
  EXPECT_GT(contact["split_steps"].get<long>(), 0);
  EXPECT_GT(contact["failsafe_activations"].get<long>(), 0);  // the failed attempts, and perhaps some halves
  int frames = 0;
  const RunReport r = runCheckingFrames("halved", frames);
  EXPECT_FALSE(r.blow_up) << r.blow_up_message;
  EXPECT_EQ(frames, 30);
}

// Halving has its cap too: with the pass alone (in_solve = false) the capped sandwich fails even in quarter steps, and
// the run stops as above, saying in which part of the step and how often it was halved; the step it names is a step
// of dt (frames 1 .. step written before it), its time the end of the part that failed, within that step.
TEST_F(Sandwich, HalvingsPastTheirCapStopTheRun) {
  ASSERT_EQ(run("quartered", "[contact]\nin_solve = false\nccd_iterations = 0\nzone_iterations = 1\nsplit_steps = 2\n"),
            3)
      << said;
  for (const char* part :
       {"contact between bodies failed", "s of the step, halved 2 times: [contact] split_steps", "split_steps = 2"})
    EXPECT_NE(said.find(part), std::string::npos) << part << " missing from: " << said;
  const long step = json["blow_up"]["step"].get<long>();
  EXPECT_EQ(json["steps"].get<long>(), step);
  EXPECT_EQ(json["frames"]["written"].get<int>(), step);
  const double time = json["blow_up"]["time"].get<double>();
  EXPECT_GT(time, 0.01 * double(step - 1) + 1e-9);
  EXPECT_LE(time, 0.01 * double(step) + 1e-12);
  EXPECT_GE(json["body_contact"]["split_steps"].get<long>(), 2);
}

INSTANTIATE_TEST_SUITE_P(
    Capped, FailSafe,
    ::testing::Values(Caps{"in_solve", "[contact]\nccd_iterations = 0\nzone_iterations = 1\nsplit_steps = 0\n", true},
                      Caps{"pass_alone",
                           "[contact]\nin_solve = false\nccd_iterations = 0\nzone_iterations = 1\nsplit_steps = 0\n",
                           false}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace wobble
