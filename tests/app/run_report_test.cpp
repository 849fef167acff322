// run.json says what happened (docs/running.md): the end state over the last frame, why each linear solve stopped,
// and what the contact thickness guarantees. Oracles: the run simulated again (its last frame's particle speeds and
// kinetic energy, recomputed here), and the solve counts, which must add up to the run's solves (steps times solves
// per step).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "app/commands/run_command.h"
#include "app/scene/scene_file.h"
#include "tests/app/scratch_dir.h"
#include "tests/app/simulate_only.h"

namespace wobble {
namespace {

class RunReportTest : public testing::ScratchDir {};

// jelly_stack under backward Euler at 1/60 s, 3 s: the upper jelly lands at about 0.5 s at 5 m/s and both rest by the
// end. The end state is the last frame's, far below the run's largest speed.
TEST_F(RunReportTest, EndStateAndSolveStopsOfAStackComingToRest) {
  RunOptions o = testing::simulateOnly("jelly_stack", dir() / "out", "backward-euler", 1.0 / 60);
  o.sets.push_back("simulation.fps=60");
  const RunReport r = runScene(o);
  ASSERT_FALSE(r.blow_up);
  // The same run again, frame by frame as `wobble run` steps it: its last frame's largest speed and kinetic energy
  // (one step a frame at fps 60: the state at the last frame's end).
  const SceneFile scene = loadRunScene(o);
  Simulation sim(*scene.system, makeIntegrator(scene.integrator, scene.integrator_options), scene.dt);
  for (int frame = 1; frame <= scene.frameCount(); ++frame) ASSERT_FALSE(sim.advanceTo(scene.frameTime(frame)));
  double frame_speed = 0, frame_kinetic = 0;
  for (int i = 0; i < scene.system->particleCount(); ++i) {
    frame_speed = std::max(frame_speed, particle(sim.v(), i).norm());
    frame_kinetic += 0.5 * scene.system->mass()[i] * particle(sim.v(), i).squaredNorm();
  }
  const auto j = nlohmann::json::parse(std::ifstream(o.out.value() / "run.json"));
  const auto& end = j.at("end_state");
  EXPECT_DOUBLE_EQ(end.at("max_speed").get<double>(), frame_speed);
  EXPECT_DOUBLE_EQ(end.at("max_kinetic_energy").get<double>(), frame_kinetic);
  EXPECT_GT(j.at("max_speed").get<double>(), 3.0);  // the landing
  EXPECT_LT(end.at("max_speed").get<double>(), 0.5);
  // Every solve stopped for one of the three reasons.
  const auto& solver = j.at("linear_solver");
  const auto& stops = solver.at("stops");
  const long counted = stops.at("cg_tolerance").get<long>() + stops.at("error_rule").at("solves").get<long>() +
                       stops.at("cg_max_iterations").at("solves").get<long>();
  const double solves = j.at("body_contact").at("solves_per_step").get<double>() * j.at("steps").get<double>();
  EXPECT_NEAR(double(counted), solves, 1e-6 * solves);
  EXPECT_EQ(stops.at("error_rule").at("solves").get<long>(), solver.at("error_rule_stops").get<long>());
  EXPECT_NE(j.at("body_contact").at("thickness_guarantee").get<std::string>().find("penalty"), std::string::npos);
}

}  // namespace
}  // namespace wobble
