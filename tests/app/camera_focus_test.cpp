// Depth of field through the scene (camera.aperture, camera.focus) as the camera rig hands it to the renderer frame
// by frame, the values `wobble blend` keys as Blender's focus distance: a number is the focus at every frame; the
// followed body's name is that body's distance along the view, which stays what it was at frame 1 while the camera
// follows it (the camera moves with the body's smoothed centroid). Oracle: the scene's numbers, (c - p) . (l - p) /
// |l - p| for the body's centre c, the eye p and the look_at point l.
#include <gtest/gtest.h>

#include "app/run/camera_rig.h"
#include "app/scene/scene_file.h"
#include "tests/app/scratch_dir.h"

namespace wobble {
namespace {

class CameraFocus : public testing::ScratchDir {
 protected:
  SceneFile scene(const std::string& camera) {
    return loadScene(write("focus.toml", R"([bodies.jelly]
type = "jelly"
n = 3
size = 1.0
center = [0.5, 1.6, -1]

[camera]
position = [2, 3, 6]
look_at = [0, 1.5, 0]
aperture = 0.1
)" + camera + "\n"));
  }
  // The focus of frames 1..frames with the body moved by `step` a frame (as a fall and a drift would move it).
  static std::vector<float> focusByFrame(const SceneFile& s, const Vec3& step, int frames) {
    CameraRig rig(s);
    std::vector<float> focus;
    for (int k = 1; k <= frames; ++k) {
      VecX x = s.system->initialPositions();
      for (Eigen::Index i = 0; i < x.size() / 3; ++i) particle(x, i) += (k - 1) * step;
      rig.observe(k, *s.system, x);
      EXPECT_FLOAT_EQ(rig.params().aperture, 0.1f);
      focus.push_back(rig.params().focus);
    }
    return focus;
  }
};

TEST_F(CameraFocus, AGivenDistanceIsTheFocusOfEveryFrame) {
  for (const float f : focusByFrame(scene("focus = 3.25"), Vec3(0.02, -0.1, 0.01), 12)) EXPECT_FLOAT_EQ(f, 3.25f);
}

TEST_F(CameraFocus, TheFollowedBodysDistanceAlongTheViewIsTheFocusOfEveryFrame) {
  const Vec3 p(2, 3, 6), l(0, 1.5, 0), c(0.5, 1.6, -1);
  const double expected = (c - p).dot((l - p).normalized());  // 7.25 m: not the look_at point's 6.5
  const std::vector<float> focus =
      focusByFrame(scene("follow = \"jelly\"\nfocus = \"jelly\""), Vec3(0.03, -0.2, 0.02), 12);
  ASSERT_EQ(focus.size(), 12u);
  for (std::size_t k = 0; k < focus.size(); ++k) EXPECT_NEAR(focus[k], expected, 1e-5 * expected) << "frame " << k + 1;
}

}  // namespace
}  // namespace wobble
