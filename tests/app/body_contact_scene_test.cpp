// The shipped contact scenes (jelly_stack, jelly_trampoline, cloth_drop), run as `wobble run` runs them, for RK4
// and backward Euler: zero intersecting triangle pairs at every frame by the independent test of
// tests/sim/triangle_intersection.h (Moller 1997): non-adjacent triangles of one body, any two of different bodies.
// Every run ends without an energy-gain stop (docs/energy.md). Also: the trampoline's jelly comes to rest on the cloth,
// the stack's upper jelly ends on top of the lower; run.json counts the contact work; a collision the fail-safe cannot
// resolve stops the run like a blow-up.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/commands/run_command.h"
#include "app/scene/input_error.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"
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
  RunOptions o;
  o.scene = testing::sourceDir() / "scenes" / (std::string(c.scene) + ".toml");
  o.out = dir() / "out";
  o.render.render = "none";
  o.progress = false;
  o.integrator = c.integrator;
  if (c.dt > 0) o.dt = c.dt;
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

class Stack : public testing::ScratchDir, public ::testing::WithParamInterface<Case> {};

// The upper jelly lands on the lower and stays on it: at the end its centre is above the lower one's top face and
// within its footprint, and it has come to rest (its centre moves less than 2 cm over the last half second).
TEST_P(Stack, UpperJellyEndsOnTopOfTheLower) {
  const Case c = GetParam();
  RunOptions o;
  o.scene = testing::sourceDir() / "scenes" / "jelly_stack.toml";
  o.out = dir() / "out";
  o.render.render = "none";
  o.progress = false;
  o.integrator = c.integrator;
  if (c.dt > 0) o.dt = c.dt;
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

class FailSafe : public testing::ScratchDir {};

// A 3^3 jelly at 20 m/s onto another under backward Euler at 0.01 s: the jellies meet within one step, and with the
// [contact] caps at their least (no rounds of collision impulses, one round of rigid impact zones) the pass cannot
// resolve every collision. The run stops like a blow-up: exit 3, a message naming the integrator, the step, the time,
// the colliding particles and what to try, run.json saying so, and every frame before the failing step kept. The
// control: with the default caps the same scene runs to the end.
// DISABLED: since backward Euler carries body contacts in its implicit solve, this scene no longer reaches the
// fail-safe (the solve leaves the pass nothing to resolve), and the explicit integrators at steps large enough to
// defeat the pass blow up or gain energy first. A configuration that reaches the fail-safe again is open work
// (docs/body-contact.md, Limits). Run it with --gtest_also_run_disabled_tests to see the current behaviour.
TEST_F(FailSafe, DISABLED_UnresolvedCollisionStopsTheRunWithExit3) {
  const std::string scene = R"(
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
[bodies.top]
type = "jelly"
n = 3
size = 0.8
center = [0.1, 1.6, 0.05]
rotation_axis = [1.0, 0.3, 1.0]
rotation_deg = 30.0
velocity = [0.0, -20.0, 0.0]
[colliders.floor]
type = "plane"
)";
  const fs::path capped = write("capped.toml", "[contact]\nccd_iterations = 0\nzone_iterations = 1\n" + scene),
                 log = dir() / "log.txt", out = dir() / "out";
  ASSERT_EQ(testing::runWobble("run " + capped.string() + " --render none --out " + out.string(), log), 3)
      << testing::slurpFile(log);
  const std::string said = testing::slurpFile(log);
  for (const char* part : {"contact between bodies failed", "integrator backward-euler", "step ",
                           "t = ", "collision between body surfaces left after 1 round of rigid impact zones",
                           "particle", "--dt 0.0025", "zone_iterations"})
    EXPECT_NE(said.find(part), std::string::npos) << part << " missing from: " << said;
  std::ifstream in(out / "run.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["blew_up"], true);
  const long step = j["blow_up"]["step"].get<long>();
  EXPECT_EQ(j["steps"].get<long>(), step);
  EXPECT_NE(said.find(j["blow_up"]["message"].get<std::string>()), std::string::npos);
  EXPECT_NE(said.find("step " + std::to_string(step) + ", t = "), std::string::npos);
  EXPECT_GT(j["body_contact"]["failsafe_activations"].get<long>(), 0);
  // A frame a step (fps 100, dt 0.01): frame k holds t = (k - 1) dt, so frames 1 .. step were written before the
  // failing step, and kept.
  const int written = j["frames"]["written"].get<int>();
  EXPECT_EQ(written, step);
  EXPECT_GT(written, 3);
  for (int f = 1; f <= written; ++f)
    for (const char* body : {"base", "top"}) {
      char name[32];
      std::snprintf(name, sizeof name, "%s_%04d.obj", body, f);
      EXPECT_TRUE(fs::exists(out / "mesh" / name)) << name;
    }
  // The control: the default caps resolve every collision of the same scene.
  RunOptions o;
  o.scene = write("default.toml", scene);
  o.out = dir() / "default";
  o.render.render = "none";
  o.progress = false;
  o.stop_on_energy_gain = false;
  const RunReport r = runScene(o);
  EXPECT_FALSE(r.blow_up) << r.blow_up_message;
  EXPECT_EQ(r.frames_written, 30);
}

}  // namespace
}  // namespace wobble
