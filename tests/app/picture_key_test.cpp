// The picture key a frame records (app/output/picture_key.h): every input that changes a picture changes it, and the
// inputs that only choose which files are written do not.
#include "app/output/picture_key.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

class PictureKeyTest : public testing::ScratchDir {
 protected:
  void SetUp() override {
    ScratchDir::SetUp();
    copyCatTexture();
    write("key.toml", R"([simulation]
duration = 1

[bodies.jelly]
type = "jelly"
n = 3
texture = "textures/cat.png"

[colliders.floor]
type = "plane"

[render]
samples = 2
)");
  }
  std::string settings(const std::vector<std::string>& overrides = {}) {
    return PictureKey(loadScene(dir() / "key.toml", overrides)).settings();
  }
};

TEST_F(PictureKeyTest, SettingsChangeWithWhatChangesThePicture) {
  const std::string base = settings();
  EXPECT_EQ(base.size(), 32u);
  EXPECT_EQ(settings(), base);
  for (const std::vector<std::string>& same : {std::vector<std::string>{"render.video=true"},
                                               {"render.exr=true"},
                                               {"output.pc2=true"},
                                               {"output.obj=false"},
                                               {"simulation.duration=2"}})
    EXPECT_EQ(settings(same), base) << same[0];
  std::vector<std::string> keys = {base};
  for (const char* other :
       {"render.samples=4", "camera.resolution=[64, 36]", "render.quality=\"preview\"", "camera.fov=50",
        "jelly.color=[1, 0, 0]", "floor.texture=\"wood\"", "simulation.fps=25", "jelly.ks=3000"}) {
    keys.push_back(settings({other}));
    for (std::size_t i = 0; i + 1 < keys.size(); ++i) EXPECT_NE(keys[i], keys.back()) << other;
  }
  // The texture's bytes, not only its name.
  std::ofstream(dir() / "textures/cat.png", std::ios::app) << "one more byte";
  EXPECT_NE(settings(), base);
}

TEST_F(PictureKeyTest, FrameKeyChangesWithFrameCameraAndSurfaces) {
  const SceneFile scene = loadScene(dir() / "key.toml");
  const PictureKey key(scene);
  render::CameraParams camera;
  std::vector<SurfaceFrame> surfaces(1);
  surfaces[0].positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  surfaces[0].normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  const std::string base = key.frame(3, camera, surfaces);
  EXPECT_EQ(key.frame(3, camera, surfaces), base);
  EXPECT_NE(key.frame(4, camera, surfaces), base);
  render::CameraParams moved = camera;
  moved.position.x() += 1e-3f;
  EXPECT_NE(key.frame(3, moved, surfaces), base);
  std::vector<SurfaceFrame> bent = surfaces;
  bent[0].normals[2] = {0, 1, 0};
  EXPECT_NE(key.frame(3, camera, bent), base);
  bent = surfaces;
  bent[0].positions[1].y() = std::nextafter(0.0f, 1.0f);  // the smallest change a float can make
  EXPECT_NE(key.frame(3, camera, bent), base);
  const auto text = key.text(base);
  EXPECT_EQ(text.at(PictureKey::kFrameName), base);
  EXPECT_EQ(text.at(PictureKey::kSettingsName), key.settings());
}

}  // namespace
}  // namespace wobble
