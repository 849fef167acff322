// The small scene the command tests run (pc2_test, run_test, render_test, blender_test, farm_pieces_test): a
// cat-textured 3^3 jelly of 1 m, stepped at 2 ms and written at 20 frames a second, beside a floor, and what each test
// adds to it. One fixture, so that a change of a key or a default is made once and every such test sees the same scene.
#pragma once
#include <string>

namespace wobble::testing {

struct SmallScene {
  std::string duration = "0.2";        // simulated seconds: 4 frames a 0.2 s
  std::string center = "[0, 0.6, 0]";  // the jelly's
  std::string jelly;                   // more of the jelly's keys, one a line
  std::string floor_name = "floor";    // the plane collider's name (a table [colliders.NAME])
  std::string floor;                   // more of the floor's keys, one a line
  std::string rest;                    // further tables: other bodies, colliders, [camera], [render]
};

// The scene's TOML; its texture is textures/cat.png beside it (ScratchDir::copyCatTexture).
inline std::string smallSceneText(const SmallScene& s) {
  return "[simulation]\ndt = 0.002\nduration = " + s.duration +
         "\nfps = 20\n\n[bodies.jelly]\ntype = \"jelly\"\nn = 3\n" + "size = 1.0\ncenter = " + s.center +
         "\ntexture = \"textures/cat.png\"\n" + s.jelly + "\n[colliders." + s.floor_name + "]\ntype = \"plane\"\n" +
         s.floor + s.rest;
}

// A camera following the jelly and a render of 2 samples: the pictures' tables of the tests that render it
// (render_test, farm_pieces_test), for SmallScene::rest.
inline const std::string kFollowCamera =
    "\n[camera]\nposition = [1, 2, 4]\nlook_at = [0, 0.5, 0]\nfollow = \"jelly\"\n\n[render]\nsamples = 2\n";

}  // namespace wobble::testing
