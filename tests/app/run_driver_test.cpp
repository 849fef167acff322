// The run driver (app/run/run_driver.h) against free fall, where every particle is at x0 + g t^2 / 2 exactly (RK4
// integrates a quadratic exactly): frames land on their times; watching a run (camera rig, shutter recorder) changes
// nothing in it; a posed frame holds the surfaces at its shutter's instants, and a follow camera's move over the
// shutter is the shutter's fraction of its move from the frame before. A sequence of the run's frames (an OBJ
// sequence's, SequencePoser) is posed at the same instants with the same camera, its poses on the line between frames.
#include "app/run/run_driver.h"

#include <gtest/gtest.h>

#include "app/run/sequence_poser.h"

#include "tests/app/free_fall_scene.h"
#include "tests/app/scratch_dir.h"

namespace wobble {
namespace {

constexpr double kG = 9.8, kDt = 0.003;

class RunDriverTest : public testing::ScratchDir {
 protected:
  SceneFile scene(double shutter) const {
    write("fall.toml", testing::freeFallSceneText(shutter, "follow = \"jelly\"\nfollow_smoothing = 0\n"));
    return loadScene(dir() / "fall.toml");
  }
};

TEST_F(RunDriverTest, WatchingChangesNothingAndFramesLandOnTheirTimes) {
  const SceneFile watched_scene = scene(0.5), plain_scene = scene(0.5), bare_scene = scene(0.5);
  RunDriver watched(watched_scene, true), plain(plain_scene);
  RunDriver bare(*bare_scene.system, bare_scene.integrator, bare_scene.integrator_options, bare_scene.dt);
  for (int k = 1; k <= 10; ++k) {
    ASSERT_FALSE(watched.next());
    ASSERT_FALSE(plain.next());
    ASSERT_FALSE(bare.advanceTo(watched_scene.frameTime(k)));
    EXPECT_EQ(watched.frame(), k);
    EXPECT_EQ(watched.simulation().time(), watched_scene.frameTime(k));
    EXPECT_TRUE(watched.x() == plain.x()) << "frame " << k;
    EXPECT_TRUE(watched.x() == bare.x()) << "frame " << k;
    if (k > 1) {
      EXPECT_EQ(watched.posed().poses.back()[0].positions, plain.surfaces()[0].positions);
    }
  }
  EXPECT_THROW(plain.posed(), std::logic_error);  // nothing watched: no camera, no poses
  EXPECT_THROW(bare.next(), std::logic_error);    // a bare system has no frames
}

TEST_F(RunDriverTest, PosesAreTheFreeFallAtTheShutterInstants) {
  const SceneFile s = scene(0.5);
  const BodySlot& slot = s.system->bodies()[0];
  const SurfaceFrame start = evaluateSurface(slot.body.surface, slot.body.x, 0);
  RunDriver run(s, true);
  ASSERT_FALSE(run.next());
  PosedFrame posed = run.posed();
  EXPECT_FALSE(posed.motionBlur());  // frame 1, t = 0: nothing before it
  ASSERT_EQ(posed.poses.size(), 1u);
  EXPECT_EQ(posed.poses[0][0].positions, start.positions);
  EXPECT_EQ(posed.camera.shutter_motion, Eigen::Vector3f::Zero());
  for (int k = 2; k <= 12; ++k) {
    const render::CameraParams before = run.posed().camera;
    ASSERT_FALSE(run.next());
    posed = run.posed();
    ASSERT_TRUE(posed.motionBlur());
    EXPECT_EQ(posed.times, shutterTimes(s, k));
    ASSERT_EQ(posed.poses.size(), posed.times.size());
    for (std::size_t j = 0; j < posed.times.size(); ++j) {
      const double drop = 0.5 * kG * posed.times[j] * posed.times[j];
      for (std::size_t v = 0; v < start.positions.size(); ++v)
        EXPECT_NEAR(posed.poses[j][0].positions[v].y(), start.positions[v].y() - drop, kG * kDt * kDt / 8 + 1e-5)
            << "frame " << k << " instant " << j;
    }
    // An unsmoothed follow camera falls with the body; over the shutter it moves back by half its fall since k - 1.
    const Eigen::Vector3f fall = posed.camera.position - before.position;
    EXPECT_LT(fall.y(), 0);
    EXPECT_NEAR((posed.camera.shutter_motion - 0.5f * fall).norm(), 0, 1e-6f) << "frame " << k;
  }
}

TEST_F(RunDriverTest, ASequenceIsPosedAsTheRunPosedIt) {
  const SceneFile s = scene(0.5);
  RunDriver run(s, true);
  SequencePoser sequence(s);
  std::vector<SurfaceFrame> before;
  for (int k = 1; k <= 6; ++k) {
    ASSERT_FALSE(run.next());
    sequence.observe(k, run.surfaces());
    const PosedFrame a = run.posed(), b = sequence.posed();
    EXPECT_EQ(b.frame, k);
    EXPECT_EQ(b.times, a.times) << "frame " << k;  // frame 2 too: blended from frame 1
    EXPECT_EQ(b.camera.position, a.camera.position);
    EXPECT_EQ(b.camera.shutter_motion, a.camera.shutter_motion) << "frame " << k;
    ASSERT_EQ(b.poses.size(), b.times.size());
    EXPECT_EQ(b.poses.back()[0].positions, run.surfaces()[0].positions);
    for (std::size_t j = 0; j + 1 < b.poses.size(); ++j) {  // on the line from frame k - 1 to frame k
      const float w = float((b.times[j] - s.frameTime(k - 1)) / (s.frameTime(k) - s.frameTime(k - 1)));
      for (std::size_t v = 0; v < before[0].positions.size(); ++v)
        EXPECT_NEAR((b.poses[j][0].positions[v] -
                     ((1 - w) * before[0].positions[v] + w * run.surfaces()[0].positions[v]))
                        .norm(),
                    0, 1e-5f);
    }
    before = run.surfaces();
  }
}

}  // namespace
}  // namespace wobble
