// A backward Euler step whose end fails the run's energy check is taken again in halves ([contact] split_steps;
// docs/energy.md, "A step that gains is taken again"). Two impacts that gained energy at 1/60 s: the default scene's
// jelly with every spring at ks 1e7 landing on the slope (it left at step 68 with 1.4 times the start's energy), and
// a jelly thrown at 150 m/s into the trampoline's pinned cloth (2.3 times in the first step). Oracles independent of
// the check: the total energy recomputed from the frames' state never rises above the start's (nothing moves a
// collider), and the bodies' centre of mass never rises above where the energy at the start could lift it. The
// control, split_steps = 0 (no retakes), gains and stops, so that the test can fail.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "app/commands/run_command.h"
#include "app/scene/scene_file.h"
#include "tests/app/scratch_dir.h"

namespace wobble {
namespace {

struct Outcome {
  RunReport report;
  int frames = 0;
  double highest_centre = -1e300;  // m, the largest height of the centre of mass over the frames
  double start_centre = 0, mass = 0, gravity = 0;
  long energy_split_steps = 0;
};

class EnergyRetake : public testing::ScratchDir {
 protected:
  Outcome run(const std::string& scene, std::vector<std::string> sets) {
    RunOptions o;
    o.scene = std::string(WOBBLE_SOURCE_DIR) + "/scenes/" + scene;
    o.out = dir() / "out";
    o.render.render = "none";
    o.progress = false;
    sets.insert(sets.end(), {"simulation.integrator=backward-euler", "simulation.dt=0.0166666666666667",
                             "output.pc2=false", "output.obj=false"});
    o.sets = sets;
    const SceneFile loaded = loadRunScene(o);
    const VecX& mass = loaded.system->mass();
    Outcome out;
    for (int i = 0; i < mass.size(); ++i) out.mass += loaded.system->inverseMass()[i] > 0 ? mass[i] : 0;
    out.gravity = loaded.system->gravity().norm();
    const auto centre = [&](const VecX& x) {
      double y = 0;
      for (int i = 0; i < mass.size(); ++i) y += loaded.system->inverseMass()[i] > 0 ? mass[i] * x[3 * i + 1] : 0;
      return y / out.mass;
    };
    out.start_centre = centre(loaded.system->initialPositions());
    o.on_frame = [&](int, const VecX& x) {
      ++out.frames;
      out.highest_centre = std::max(out.highest_centre, centre(x));
    };
    out.report = runScene(o);
    std::ifstream in(*o.out / "run.json");
    out.energy_split_steps = nlohmann::json::parse(in)["energy"]["split_steps"].get<long>();
    return out;
  }
};

// The energy of the start, kinetic included, bounds every later height: M g (y - y0) <= E_kinetic,0 + E_elastic,0.
void expectNoGain(const Outcome& o, double start_kinetic) {
  EXPECT_FALSE(o.report.blow_up) << o.report.blow_up_message;
  EXPECT_FALSE(o.report.energy_gain) << o.report.energy_gain_message;
  EXPECT_LE(o.report.energy_end, o.report.energy_start);
  EXPECT_LE(o.mass * o.gravity * (o.highest_centre - o.start_centre), start_kinetic + 1e-9 * o.report.energy_start);
  EXPECT_GT(o.energy_split_steps, 0);
}

TEST_F(EnergyRetake, StiffJellyLandingOnTheSlopeAtALargeStepGainsNothing) {
  const std::vector<std::string> stiff = {"jelly.ks=1e7", "simulation.duration=1.6"};
  const Outcome retaken = run("jelly_slope.toml", stiff);
  EXPECT_EQ(retaken.frames, 48);
  expectNoGain(retaken, 0);

  auto control = stiff;
  control.push_back("contact.split_steps=0");
  const Outcome off = run("jelly_slope.toml", control);
  ASSERT_TRUE(off.report.energy_gain);
  EXPECT_EQ(off.report.energy_gain->step, 68);
  EXPECT_NE(off.report.energy_gain_message.find("not taken again in halves: [contact] split_steps = 0"),
            std::string::npos)
      << off.report.energy_gain_message;
  EXPECT_EQ(off.energy_split_steps, 0);
}

TEST_F(EnergyRetake, JellyThrownAt150MetresASecondIntoAPinnedClothGainsNothing) {
  // A frame a step (fps 60), so that the check at the frames sees the first step's gain.
  const std::vector<std::string> throw_ = {"jelly.velocity=[0,-150,0]", "simulation.fps=60", "simulation.duration=1.0"};
  const Outcome retaken = run("jelly_trampoline.toml", throw_);
  EXPECT_EQ(retaken.frames, 60);
  // The jelly's 64 particles of 0.05 kg at 150 m/s.
  expectNoGain(retaken, 0.5 * 64 * 0.05 * 150 * 150);

  auto control = throw_;
  control.push_back("contact.split_steps=0");
  const Outcome off = run("jelly_trampoline.toml", control);
  ASSERT_TRUE(off.report.energy_gain);
  EXPECT_EQ(off.report.energy_gain->step, 1);
  EXPECT_GT(off.report.energy_gain->energy, 2 * off.report.energy_start);
}

}  // namespace
}  // namespace wobble
