// The shutter's poses (app/run/shutter.h) against free fall, where every particle is at x0 + g t^2 / 2 exactly (RK4
// integrates a quadratic exactly): the instants span the stated fraction of the frame interval and close at the
// frame; the recorder's states, blended from the simulation's own steps, are the analytic ones within linear
// interpolation's error (g dt^2 / 8); observing the steps changes nothing in the run; frames blended from an OBJ
// sequence lie on the line between the two frames.
#include "app/run/shutter.h"

#include <gtest/gtest.h>

#include "sim/simulation.h"
#include "tests/app/free_fall_scene.h"
#include "tests/app/scratch_dir.h"

namespace wobble {
namespace {

class Shutter : public testing::ScratchDir {
 protected:
  SceneFile scene(double shutter) {
    write("fall.toml", testing::freeFallSceneText(shutter));
    return loadScene(dir() / "fall.toml");
  }
};

TEST_F(Shutter, InstantsSpanTheFractionOfTheFrameIntervalAndCloseAtTheFrame) {
  for (const double fraction : {0.25, 0.5, 1.0}) {
    const SceneFile s = scene(fraction);
    EXPECT_EQ(shutterTimes(s, 1).size(), 1u);  // t = 0: nothing before it
    const std::vector<double> times = shutterTimes(s, 7);
    ASSERT_EQ(times.size(), std::size_t(kShutterPoses));
    EXPECT_EQ(times.back(), s.frameTime(7));
    EXPECT_NEAR(times.back() - times.front(), fraction / 25, 1e-12);
    for (std::size_t j = 1; j < times.size(); ++j)
      EXPECT_NEAR(times[j] - times[j - 1], fraction / 25 / (kShutterPoses - 1), 1e-12);
  }
  EXPECT_EQ(shutterTimes(scene(0), 7).size(), 1u);
}

TEST_F(Shutter, RecordedStatesAreTheFreeFallAtTheInstants) {
  const SceneFile s = scene(0.7);
  MassSpringSystem& system = *s.system;
  Simulation sim(system, makeIntegrator(s.integrator, s.integrator_options), s.dt);
  const VecX x0 = sim.x();
  ShutterRecorder recorder(s, x0);
  sim.observeSteps([&](double t, const VecX& x) { recorder.step(t, x); });
  // The same run, unobserved: the same states bit for bit.
  const SceneFile twin_scene = scene(0.7);
  Simulation twin(*twin_scene.system, makeIntegrator(s.integrator, s.integrator_options), s.dt);
  const double g = 9.8, dt = 0.003;
  for (int k = 1; k <= 12; ++k) {
    recorder.begin(k);
    ASSERT_FALSE(sim.advanceTo(s.frameTime(k)));
    ASSERT_FALSE(twin.advanceTo(s.frameTime(k)));
    EXPECT_TRUE(sim.x() == twin.x()) << "frame " << k;
    const std::vector<double> times = shutterTimes(s, k);
    const std::vector<VecX> states = recorder.states(sim.x());
    ASSERT_EQ(states.size(), times.size());
    EXPECT_TRUE(states.back() == sim.x());
    for (std::size_t j = 0; j < times.size(); ++j)
      for (Eigen::Index i = 1; i < x0.size(); i += 3)  // heights
        EXPECT_NEAR(states[j][i], x0[i] - 0.5 * g * times[j] * times[j], g * dt * dt / 8 + 1e-9)
            << "frame " << k << " instant " << j;
  }
}

TEST_F(Shutter, BlendedSurfacesLieBetweenTheFrames) {
  const SceneFile s = scene(0.5);
  SurfaceFrame a, b;
  a.positions = {{0, 0, 0}, {1, 0, 0}};
  b.positions = {{0, 4, 0}, {1, 0, 8}};
  a.normals = {{0, 1, 0}, {1, 0, 0}};
  b.normals = {{0, 1, 0}, {0, 1, 0}};
  const std::vector<SurfaceFrame> before = {a}, after = {b};
  const auto poses = blendSurfaces(s, 5, before, after);
  const std::vector<double> times = shutterTimes(s, 5);
  ASSERT_EQ(poses.size(), times.size());
  for (std::size_t j = 0; j < poses.size(); ++j) {
    const float w = float((times[j] - s.frameTime(4)) / (s.frameTime(5) - s.frameTime(4)));
    EXPECT_NEAR(poses[j][0].positions[0].y(), 4 * w, 1e-5f);
    EXPECT_NEAR(poses[j][0].positions[1].z(), 8 * w, 1e-5f);
    EXPECT_NEAR(poses[j][0].normals[1].norm(), 1, 1e-5f);
  }
  EXPECT_NEAR(poses.front()[0].positions[0].y(), 2, 1e-5f);  // half a frame: half way
  EXPECT_EQ(poses.back()[0].positions, b.positions);
}

}  // namespace
}  // namespace wobble
