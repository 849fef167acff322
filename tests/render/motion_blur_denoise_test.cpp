// Motion blur at the default quality (one sample a pixel, denoised): the edge of a fast-moving shape must come out
// blurred, not dithered. A board's top edge sweeps up across the sky, about 9 pixels while the shutter is open; with
// one instant a pixel, each pixel in the swept band sees either the board or the sky, a dither; the denoiser must
// average them along the motion (denoiser.h: the film's motion layer), as the converged picture does. The same with
// the board still and the eye moving down (the image moves the same way), and with a still wall behind the board
// instead of the sky (its pixels in the swept band must mix too, though they do not move).
// Oracle: the converged picture (256 instants a pixel, not denoised). Measure of dither: along the edge the converged
// picture is the same in every column, so the mean squared difference between horizontally neighbouring pixels in
// the swept band is noise: the denoised picture's must be near the converged one's (blurred_edge.h).
#include <vector>

#include <gtest/gtest.h>

#include "image/film.h"
#include "render/denoiser.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "tests/render/blurred_edge.h"

namespace wobble::render {
namespace {

using testing::edge;
using testing::EdgeFigures;

constexpr float kRise = 0.3f;  // m over the shutter: about 9 pixels at the board's distance

// The board facing the camera, its top edge at y = 2 + lift.
Quad board(float lift) { return Quad{{0, lift, 2}, {0, 0, 1}, 4, 1}; }

Scene boardAgainst(bool moving, bool wall) {
  Scene scene;
  if (wall)
    scene.addQuad("wall", Quad{{0, 0, -4}, {0, 0, 1}, 40, 1},
                  scene.addMaterial(Material::diffuse("wall", Color(0.2f, 0.5f, 0.7f))));
  const ShapeId id =
      scene.addQuad("board", board(0), scene.addMaterial(Material::diffuse("board", Color(0.5f, 0.3f, 0.2f))));
  if (moving) {
    const Quad path[] = {board(-kRise / 2), board(kRise / 2)};
    scene.updateQuadMotion(id, path);
  }
  scene.lights.suns = {testing::boardSun()};
  scene.commit();
  return scene;
}

Camera camera(bool moving) {
  CameraParams cp = testing::boardCamera();
  if (moving) {  // down by kRise, ending where the still eye is: the edge rises across the image as the board's does
    cp.position.y() -= kRise / 2, cp.look_at.y() -= kRise / 2;
    cp.shutter_motion = {0, -kRise, 0};
  }
  return Camera(cp);
}

struct Pictures {
  EdgeFigures converged, denoised, without_layer;
};

Pictures render(bool board_moves, bool wall) {
  const Scene scene = boardAgainst(board_moves, wall);
  const Camera cam = camera(!board_moves);
  RenderSettings reference;
  reference.samples_per_pixel = 256;
  reference.motion_blur = true;
  const image::Image8 ref = image::develop(render(scene, cam, reference));

  RenderSettings one;
  one.samples_per_pixel = 1;
  one.motion_blur = true;
  one.frame = 3;
  image::Film film = render(scene, cam, one);
  const image::Image8 out = image::develop(cam.width(), cam.height(), denoise(film));
  for (auto& m : film.motion) m = Eigen::Vector2f::Zero();  // the denoiser as for a still picture
  const image::Image8 plain = image::develop(cam.width(), cam.height(), denoise(film));
  return {edge(ref, ref), edge(out, ref), edge(plain, ref)};
}

// The film's motion layer: the image of the board's edge moves about 9 pixels up, of the sky not at all.
TEST(MotionBlurDenoise, TheFilmRecordsEachPixelsMotionOverTheShutter) {
  for (const bool board_moves : {true, false}) {
    SCOPED_TRACE(board_moves ? "board moving" : "eye moving");
    const Scene scene = boardAgainst(board_moves, false);
    const Camera cam = camera(!board_moves);
    RenderSettings one;
    one.samples_per_pixel = 1;
    one.motion_blur = true;
    const image::Film film = render(scene, cam, one);
    // The board at the image's centre column, near its bottom: 4 m away, 64 px over 2 * 4 tan(15 deg) = 2.14 m.
    const Eigen::Vector2f m = film.motion[film.index(48, 62)];
    EXPECT_NEAR(m.x(), 0, 0.05f);
    EXPECT_NEAR(m.y(), -kRise * 64 / (8 * std::tan(15 * float(M_PI) / 180)), 0.3f);  // up: -8.96 pixels
    EXPECT_EQ(film.motion[film.index(48, 0)], Eigen::Vector2f::Zero());              // the sky
    // Without motion blur nothing is recorded.
    one.motion_blur = false;
    const image::Film still = render(scene, cam, one);
    for (const auto& v : still.motion) ASSERT_EQ(v, Eigen::Vector2f::Zero());
  }
}

// Measured (one sample, frame 3): converged dither 4e-6 (its own noise); denoised 1.5e-4, RMSE 0.026 over the band
// (before the wall: 8e-6 and 0.028). Without the motion layer (the denoiser as for a still picture): 3.7e-3 and 0.061
// (pixels jump between the board and the sky); before the wall 8.3e-4 and 0.092 (the board's pixels in the band
// are filtered apart from the wall's, each side's mean off the ramp).
TEST(MotionBlurDenoise, AFastEdgeIsBlurredNotDithered) {
  struct Case {
    const char* name;
    bool board_moves, wall;
  };
  for (const Case c : {Case{"board moving", true, false}, Case{"eye moving", false, false},
                       Case{"board moving before a wall", true, true}}) {
    SCOPED_TRACE(c.name);
    const Pictures p = render(c.board_moves, c.wall);
    std::printf("%s: converged dither %.2e over %d rows; denoised %.2e, RMSE %.4f; without the layer %.2e, RMSE %.4f\n",
                c.name, p.converged.dither, p.converged.rows, p.denoised.dither, p.denoised.rmse,
                p.without_layer.dither, p.without_layer.rmse);
    EXPECT_GE(p.converged.rows, 6);  // the edge is spread over several rows
    EXPECT_LT(p.converged.dither, 2e-5);
    EXPECT_LT(p.denoised.dither, 1e-3);
    EXPECT_LT(p.denoised.rmse, 0.045);
  }
}

}  // namespace
}  // namespace wobble::render
