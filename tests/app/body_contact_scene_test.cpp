// The shipped contact scenes (jelly_stack, jelly_trampoline, cloth_drop), run as `wobble run` runs them, for RK4
// and backward Euler: zero intersecting triangle pairs at every frame by the independent test of
// tests/sim/triangle_intersection.h (Moller 1997): non-adjacent triangles of one body, any two of different bodies.
// Also: the trampoline's jelly comes to rest on the cloth; run.json counts the contact work; bad contact keys.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/commands/run_command.h"
#include "app/scene/input_error.h"
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

}  // namespace
}  // namespace wobble
