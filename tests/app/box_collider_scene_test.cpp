// A box collider in a scene: read with its keys and default look, drawn by the render scene, framed by the camera,
// and refused with a message naming the key when its size is not positive.
#include <gtest/gtest.h>

#include "app/pictures/render_scene.h"
#include "app/run/camera_rig.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "tests/app/scratch_dir.h"

namespace wobble {
namespace {

const std::string kScene = R"([bodies.jelly]
type = "jelly"
n = 3
center = [0, 3, 0]

[colliders.crate]
type = "box"
center = [0, 1, 0]
size = [2, 2, 2]

[render]
png = true
)";

class BoxColliderScene : public testing::ScratchDir {};

TEST_F(BoxColliderScene, IsReadDrawnAndFramed) {
  const SceneFile scene = loadScene(write("box.toml", kScene));
  ASSERT_EQ(scene.system->colliders().size(), 1u);
  const ColliderLook& look = scene.render.colliders.at("crate");
  EXPECT_EQ(look.type, "box");
  EXPECT_EQ(look.texture, "wood");
  EXPECT_NO_THROW(RenderScene{scene});
  // Framed around the jelly (size 4: y in [1, 5]) and the crate (y in [0, 2]): the view looks at their middle.
  const render::CameraParams camera = CameraRig(scene).params();
  EXPECT_NEAR(camera.look_at.y(), 2.5, 1e-5);
}

TEST_F(BoxColliderScene, RefusesANonPositiveSize) {
  std::string text = kScene;
  text.replace(text.find("size = [2, 2, 2]"), 16, "size = [2, 0, 2]");
  try {
    loadScene(write("bad.toml", text));
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("colliders.crate.size"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace wobble
