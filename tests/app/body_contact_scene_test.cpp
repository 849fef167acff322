// The shipped contact scenes (jelly_stack, jelly_trampoline, cloth_drop), run as `wobble run` runs them, for RK4
// and backward Euler: zero intersecting triangle pairs at every frame by the independent test of
// tests/sim/triangle_intersection.h (Moller 1997): non-adjacent triangles of one body, any two of different bodies.
// Also: the trampoline's jelly comes to rest on the cloth; run.json counts the contact work; a collision the fail-safe
// cannot resolve stops the run like a blow-up.
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

class ContactScene : public testing::ScratchDir, public ::testing::WithParamInterface<Case> {};

TEST_P(ContactScene, NoTrianglesIntersectAtAnyFrame) {
  const Case c = GetParam();
  RunOptions o;
  o.scene = testing::sourceDir() / "scenes" / (std::string(c.scene) + ".toml");
  o.out = dir() / "out";
  o.render.render = "none";
  o.progress = false;
  // Intersections only, at every frame: under backward Euler the bodies' first impact in jelly_stack and
  // jelly_trampoline gains 12-16% energy, which the run's energy check reports (docs/body-contact.md, known limits).
  o.stop_on_energy_gain = false;
  o.integrator = c.integrator;
  if (c.dt > 0) o.dt = c.dt;
  if (c.duration > 0) o.sets.push_back("simulation.duration=" + std::to_string(c.duration));
  const SceneFile scene = loadRunScene(o);
  testing::ParticleTriangles tris;
  for (std::size_t b = 0; b < scene.system->bodies().size(); ++b)
    testing::addSurface(tris, scene.system->bodies()[b].body.surface, scene.system->bodies()[b].first, int(b));
  int frames = 0, worst = 0;
  std::string first;  // the first intersecting pair seen: frame, bodies, triangles' particles
  o.on_frame = [&](int frame, const VecX& x) {
    ++frames;
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
  EXPECT_GT(j["body_contact"]["contacts"].get<long>(), 0);  // the bodies did touch
  EXPECT_EQ(j["body_contact"]["steps_checked"].get<long>(), r.steps);
  EXPECT_LT(j["body_contact"]["min_distance_m"].get<double>(), 0.02);
}

INSTANTIATE_TEST_SUITE_P(
    Shipped, ContactScene,
    ::testing::Values(Case{"jelly_stack", "rk4", 0}, Case{"jelly_stack", "backward-euler", 1.0 / 120},
                      Case{"jelly_trampoline", "rk4", 0}, Case{"jelly_trampoline", "backward-euler", 1.0 / 120},
                      Case{"cloth_drop", "rk4", 0}, Case{"cloth_drop", "backward-euler", 1.0 / 120}),
    [](const auto& info) {
      std::string name = std::string(info.param.scene) + "_" + info.param.integrator;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

class Trampoline : public testing::ScratchDir {};

// The jelly comes to rest on the cloth: over the last half second it moves less than 2 cm, and its lowest particle
// stays above the cloth's lowest (it sits in the cloth's sag, not below it). Backward Euler at 1/240 s, for the
// suite's time (the scene's RK4 run: docs/body-contact.md).
TEST_F(Trampoline, JellyComesToRestOnTheCloth) {
  RunOptions o;
  o.scene = testing::sourceDir() / "scenes" / "jelly_trampoline.toml";
  o.out = dir() / "out";
  o.render.render = "none";
  o.progress = false;
  o.integrator = "backward-euler";
  o.dt = 1.0 / 240;
  const SceneFile scene = loadRunScene(o);
  const int jelly_first = scene.system->bodies()[1].first, count = scene.system->particleCount();
  std::vector<VecX> frames;
  o.on_frame = [&](int, const VecX& x) { frames.push_back(x); };
  const RunReport r = runScene(o);
  ASSERT_FALSE(r.blow_up) << r.blow_up_message;
  const auto center = [&](const VecX& x) {
    Vec3 c = Vec3::Zero();
    for (int i = jelly_first; i < count; ++i) c += particle(x, i);
    return Vec3(c / (count - jelly_first));
  };
  const int last = int(frames.size()) - 1, half_second = int(scene.fps / 2);
  EXPECT_LT((center(frames[last]) - center(frames[last - half_second])).norm(), 0.02);
  double jelly_low = 1e9, cloth_low = 1e9;
  for (int i = 0; i < count; ++i) {
    double& low = i >= jelly_first ? jelly_low : cloth_low;
    low = std::min(low, particle(frames[last], i).y());
  }
  EXPECT_GT(jelly_low, cloth_low);
  EXPECT_LT(center(frames[last]).y(), 1.0);  // it rests on the sagging cloth (at y = 1 before), not in the air
}

class FailSafe : public testing::ScratchDir {};

// A 3^3 jelly at 20 m/s onto another under backward Euler at 0.01 s: the jellies meet within one step, and with the
// [contact] caps at their least (no rounds of collision impulses, one round of rigid impact zones) the pass cannot
// resolve every collision. The run stops like a blow-up: exit 3, a message naming the integrator, the step, the time,
// the colliding particles and what to try, run.json saying so, and every frame before the failing step kept. The
// control: with the default caps the same scene runs to the end.
TEST_F(FailSafe, UnresolvedCollisionStopsTheRunWithExit3) {
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
