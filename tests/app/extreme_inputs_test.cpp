// Extreme inputs through `wobble run` (runScene) on small scenes: none may crash or hang; each gives a sensible
// result or a clear error. A dt longer than a frame, no damping, ks 1e9, every particle pinned, a jelly starting
// inside the slope, huge initial velocities, one-particle-thick cloths (2 x N and N x 2 strips), nothing moving.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

#include "app/commands/run_command.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "sim/simulation.h"
#include "sim/springs.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

const char* const kIntegrators[] = {"explicit-euler", "symplectic-euler", "pc-euler", "midpoint", "rk4",
                                    "rk45",           "backward-euler"};

class ExtremeInputs : public testing::ScratchDir {
 protected:
  RunReport run(const std::string& scene_text, const std::string& integrator = "", bool estimate = false) {
    RunOptions o;
    o.scene = write("scene.toml", "[output]\nobj = false\n" + scene_text);
    o.out = dir() / "out";
    o.render.render = "none";
    if (!integrator.empty()) o.integrator = integrator;
    o.estimate_error = estimate;
    return runScene(o);
  }
  nlohmann::json runJson() const { return nlohmann::json::parse(std::ifstream(dir() / "out/run.json")); }
};

const std::string kSmallJelly = R"(
[bodies.jelly]
type = "jelly"
n = 3
size = 1.0
center = [0, 1.0, 0]
)";

TEST_F(ExtremeInputs, StepLongerThanAFrameBecomesOneStepPerFrame) {
  // Backward Euler is stable at any step: one step per frame interval, 0.5 s at 30 fps = 15 frames, 14 steps.
  const RunReport r = run("[simulation]\ndt = 0.1\nduration = 0.5\nfps = 30\n" + kSmallJelly, "backward-euler");
  EXPECT_FALSE(r.blow_up);
  EXPECT_EQ(r.steps, 14);
  EXPECT_NEAR(r.simulated_time, 14.0 / 30, 1e-12);
  // run.json reports the linear solves: the tolerance they were held to and the worst residual they reached.
  const auto solver = runJson()["linear_solver"];
  EXPECT_EQ(solver["cg_tolerance"].get<double>(), IntegratorOptions{}.cg_tolerance);
  EXPECT_GT(solver["cg_iterations"].get<long>(), 0);
  EXPECT_GT(solver["max_relative_residual"].get<double>(), 0);
  EXPECT_EQ(solver["cg_error_fraction"].get<double>(), IntegratorOptions{}.cg_error_fraction);
  // Above the tolerance only where the error rule stopped a solve earlier.
  if (solver["error_rule_stops"].get<long>() == 0) {
    EXPECT_LE(solver["max_relative_residual"].get<double>(), IntegratorOptions{}.cg_tolerance);
  }
  // An explicit method at omega h >> 3 diverges, and stops and says so with a hint, without crashing: here the energy
  // check at a frame's end (one step per frame) catches it before a particle reaches |v| = 1000 (docs/energy.md).
  const RunReport e = run("[simulation]\ndt = 0.1\nduration = 0.5\nfps = 30\n" + kSmallJelly + "ks = 1e5\n", "rk4");
  ASSERT_TRUE(e.blow_up || e.energy_gain);
  const std::string& message = e.blow_up ? e.blow_up_message : e.energy_gain_message;
  EXPECT_NE(message.find("--dt"), std::string::npos) << message;
  // A step longer than the whole run: the one frame interval is one step.
  const RunReport whole = run("[simulation]\ndt = 10\nduration = 0.1\nfps = 20\n" + kSmallJelly, "rk4");
  EXPECT_FALSE(whole.blow_up);
  EXPECT_EQ(whole.steps, 1);
}

TEST_F(ExtremeInputs, ZeroDampingConservesEnergy) {
  // A cloth swinging from its top edge with no dampers and no drag: RK4 loses a little energy, never gains.
  const std::string scene = R"([simulation]
dt = 0.001
duration = 1.0
gravity = [0, -9.8, 0]
[bodies.cloth]
type = "cloth"
nx = 5
ny = 5
size = [1.0, 1.0]
mass = 0.04
ks = 200.0
kd = 0.0
drag = 0.0
pinned = ["top-edge"]
)";
  const RunReport r = run(scene, "rk4");
  ASSERT_FALSE(r.blow_up);
  EXPECT_NEAR(r.energy_end, r.energy_start, 1e-3 * std::abs(r.energy_start) + 1e-3);
  EXPECT_LE(r.energy_end, r.energy_start);  // RK4's amplitude factor is below 1 at every omega h
  const RunReport s = run(scene, "symplectic-euler");
  ASSERT_FALSE(s.blow_up);
  EXPECT_NEAR(s.energy_end, s.energy_start, 2e-2 * std::abs(s.energy_start) + 1e-2);  // bounded, no drift
}

TEST_F(ExtremeInputs, StiffnessOneBillion) {
  const std::string scene = "[simulation]\ndt = 0.001\nduration = 0.2\n" + kSmallJelly + "ks = 1e9\n" +
                            "[colliders.floor]\ntype = \"plane\"\npoint = [0, 0.45, 0]\n";
  // Explicit: omega h ~ 300 at dt 1e-3. The blow-up rule stops it within a few steps: no hang, a clear report.
  const RunReport e = run(scene, "explicit-euler");
  ASSERT_TRUE(e.blow_up);
  EXPECT_LT(e.steps, 50);
  // Backward Euler stays finite and keeps the jelly's shape: no spring stretched or compressed by 0.1%.
  const RunReport b = run(scene, "backward-euler");
  EXPECT_FALSE(b.blow_up);
  EXPECT_TRUE(std::isfinite(b.energy_end));
  {
    const SceneFile file = loadScene(dir() / "scene.toml", {});
    Simulation sim(*file.system, makeIntegrator("backward-euler"), file.dt);
    ASSERT_FALSE(sim.advanceTo(0.2));
    EXPECT_LT(maxStrain(file.system->springs(), sim.x()), 1e-3);
  }
  // rk45 takes substeps as small as stiffness needs; it must finish or give up with its message, not hang.
  try {
    const RunReport a = run("[simulation]\ndt = 0.001\nduration = 0.02\n" + kSmallJelly + "ks = 1e9\n", "rk45");
    EXPECT_FALSE(a.blow_up);
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("rk45"), std::string::npos) << error.what();
  }
}

TEST_F(ExtremeInputs, EveryParticlePinnedStaysPut) {
  const std::string scene = R"([simulation]
dt = 0.01
duration = 0.2
[bodies.cloth]
type = "cloth"
nx = 3
ny = 3
pinned = [0, 1, 2, 3, 4, 5, 6, 7, 8]
)";
  for (const char* integrator : kIntegrators) {
    const RunReport r = run(scene, integrator, true);
    EXPECT_FALSE(r.blow_up) << integrator;
    EXPECT_EQ(r.max_speed, 0) << integrator;
    EXPECT_DOUBLE_EQ(r.energy_end, r.energy_start) << integrator;
    ASSERT_TRUE(r.error_estimate) << integrator;
    EXPECT_EQ(r.error_estimate->max_error, 0) << integrator;  // no moving particle: nothing to be wrong about
  }
}

TEST_F(ExtremeInputs, NothingMovingWithoutGravity) {
  // Free particles, springs at rest, no gravity, no velocity: every method must return exactly the initial state.
  const std::string scene = "[simulation]\ndt = 0.01\nduration = 0.2\ngravity = [0, 0, 0]\n" + kSmallJelly;
  for (const char* integrator : kIntegrators) {
    const RunReport r = run(scene, integrator, true);
    EXPECT_FALSE(r.blow_up) << integrator;
    EXPECT_EQ(r.max_speed, 0) << integrator;
    ASSERT_TRUE(r.error_estimate) << integrator;
    EXPECT_EQ(r.error_estimate->max_error, 0) << integrator;
  }
}

TEST_F(ExtremeInputs, JellyStartingInsideTheSlopeIsPushedOut) {
  // The slope of jelly_slope.toml; the jelly's centre 0.2 m below it, so its lower half starts inside.
  const std::string scene = R"([simulation]
dt = 0.001
duration = 0.5
[bodies.jelly]
type = "jelly"
n = 3
size = 1.0
center = [0, -0.2, 0]
[colliders.slope]
type = "plane"
normal = [0.3420201433256687, 0.9396926207859084, 0.0]
)";
  for (const char* integrator : {"rk4", "backward-euler", "symplectic-euler"}) {
    const RunReport r = run(scene, integrator);
    EXPECT_FALSE(r.blow_up) << integrator << ": " << r.blow_up_message;
    EXPECT_TRUE(std::isfinite(r.energy_end)) << integrator;
  }
  // Every particle ends on the free side of the plane (within the contact tolerance epsilon = 0.01), whichever
  // integrator pushed it out.
  const SceneFile s = loadScene(dir() / "scene.toml", {});
  const Vec3 normal = Vec3(0.3420201433256687, 0.9396926207859084, 0).normalized();
  for (const char* integrator : {"rk4", "backward-euler", "symplectic-euler"}) {
    Simulation sim(*s.system, makeIntegrator(integrator), s.dt);
    ASSERT_FALSE(sim.advanceTo(0.5)) << integrator;
    for (int i = 0; i < s.system->particleCount(); ++i)
      EXPECT_GT(normal.dot(particle(sim.x(), i)), -0.011) << integrator << " particle " << i;
  }
}

TEST_F(ExtremeInputs, JellyStartingInsideAWallIsWarnedOfAndNamedWhenItGains) {
  // A 5^3 jelly (0.76 m) whose left face starts 8 cm inside a wall (inner face at x = -0.4; contact band 1 cm), under
  // backward Euler at 1/240 s: the wall pushes it out with energy no smaller step removes. Oracle: the scene's
  // geometry (the face's 25 particles, 0.08 m deep), not the detection's own numbers.
  const std::string wall = R"(
[colliders.floor]
type = "plane"
[colliders.left]
type = "box"
center = [-0.65, 1.5, 0.0]
size = [0.5, 3.0, 3.0]
)";
  const auto scene = [&](double x) {
    return "[simulation]\nintegrator = \"backward-euler\"\ndt = 0.00416666666666667\nduration = 0.1\nfps = 30\n"
           "[bodies.jelly]\ntype = \"jelly\"\nn = 5\nsize = 0.76\nmass = 2.0\nks = 100.0\nkd = 1.0\ncenter = [" +
           std::to_string(x) + ", 1.4, 0.0]\n" + wall;
  };
  ::testing::internal::CaptureStderr();
  const RunReport r = run(scene(-0.1));
  const std::string err = ::testing::internal::GetCapturedStderr();
  // One warning line before step 1: body, collider, count, depth.
  const auto warning = err.find(
      "wobble: warning: body 'jelly' starts with 25 particles inside collider 'left', up to "
      "0.08 m deep");
  ASSERT_NE(warning, std::string::npos) << err;
  EXPECT_EQ(err.find("warning:", warning + std::string("wobble: warning:").size()), std::string::npos) << err;
  EXPECT_EQ(err.find("collider 'floor'"), std::string::npos) << err;  // the floor's band is not entered 8 cm deep
  // It stops at step 8 with exit 3 today; wherever it stops, the message names the cause and its advice before the
  // smaller step.
  if (r.energy_gain) {
    const std::string& m = r.energy_gain_message;
    const auto cause = m.find("collider 'left', up to 0.08 m deep");
    const auto advice = m.find("move the body out of the collider (or start it above)");
    EXPECT_NE(cause, std::string::npos) << m;
    ASSERT_NE(advice, std::string::npos) << m;
    EXPECT_LT(advice, m.find("smaller time step")) << m;
    EXPECT_EQ(m.find("taken again in halves"), std::string::npos) << m;  // those steps were not
  }
  // The same jelly 2 cm clear of the wall: no warning, and no cause named if anything fires.
  ::testing::internal::CaptureStderr();
  const RunReport clear = run(scene(0.0));
  const std::string clear_err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(clear_err.find("warning"), std::string::npos) << clear_err;
  EXPECT_EQ(clear.energy_gain_message.find("move the body out"), std::string::npos) << clear.energy_gain_message;
}

TEST_F(ExtremeInputs, HugeInitialVelocity) {
  // Above the blow-up speed (|v|^2 > 1e6): a clear input error naming the key, not a "blew up at step 1".
  try {
    run("[simulation]\nduration = 0.1\n" + kSmallJelly + "velocity = [0, 0, 5000]\n");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies.jelly.velocity"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1000"), std::string::npos) << e.what();
  }
  // Below it: the jelly flies off and hits the floor at 900 m/s; the run finishes or reports a blow-up cleanly.
  const RunReport r = run("[simulation]\nduration = 0.1\n" + kSmallJelly +
                              "velocity = [0, -900, 0]\n[colliders.floor]\ntype = \"plane\"\n",
                          "rk4");
  if (r.blow_up) EXPECT_FALSE(r.blow_up_message.empty());
  else EXPECT_TRUE(std::isfinite(r.energy_end));
}

TEST_F(ExtremeInputs, OneParticleThickCloth) {
  // "One particle thick": a 2 x N strip (two particles across, so no bending springs across it) and an N x 2 one,
  // hanging from the top edge. The validator needs nx, ny >= 2; both must swing without trouble.
  for (const char* size : {"nx = 2\nny = 8\n", "nx = 8\nny = 2\n"}) {
    const RunReport r =
        run(std::string("[simulation]\ndt = 0.0005\nduration = 0.5\n[bodies.strip]\ntype = \"cloth\"\n") + size +
                "hanging = true\nsize = [0.5, 0.5]\nks = 2000.0\nkd = 5.0\npinned = [\"top-edge\"]\n",
            "rk4");
    EXPECT_FALSE(r.blow_up) << size << r.blow_up_message;
    EXPECT_TRUE(std::isfinite(r.energy_end)) << size;
    EXPECT_GT(r.max_speed, 0) << size;
  }
}

}  // namespace
}  // namespace wobble
