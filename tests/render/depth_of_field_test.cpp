// Depth of field at the default quality (one sample a pixel, denoised): an out-of-focus edge must come out blurred,
// not dithered. A board near the camera, far out of focus, stands against the sky; the focus is far behind it. With
// one lens sample a pixel, each pixel near the board's edge sees either the board or the sky, a dither; the denoiser
// must average them over the lens's blur (denoiser.h: the film's blur layer), as the converged picture does.
// Oracle: the converged picture (256 lens samples a pixel, not denoised). Measure of dither: along the edge the
// converged picture is the same in every column, so the mean squared difference between horizontally neighbouring
// pixels in the edge's band is noise: the denoised picture's must be near the converged one's (blurred_edge.h).
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

Scene boardAgainstTheSky() {
  Scene scene;
  scene.addQuad("board", Quad{{0, 0, 2}, {0, 0, 1}, 4, 1},
                scene.addMaterial(Material::diffuse("board", Color(0.5f, 0.3f, 0.2f))));
  scene.lights.suns = {testing::boardSun()};
  scene.commit();
  return scene;
}

Camera camera(float aperture) {
  CameraParams cp = testing::boardCamera();
  cp.aperture = aperture;  // the board's edge is spread over about 4 pixels; the sky by 0.4
  cp.focus = 50;
  return Camera(cp);
}

// Measured: converged dither 5e-6 (its own noise); one sample denoised 1.5e-4, RMSE 0.031 over the band. Without the
// blur layer (the denoiser as for a pinhole): dither 3.1e-3 (pixels jump between sky and board), RMSE 0.056; one
// sample not denoised: dither 6e-3.
TEST(DepthOfField, AnOutOfFocusEdgeIsBlurredNotDithered) {
  const Scene scene = boardAgainstTheSky();
  const Camera cam = camera(0.15f);
  RenderSettings reference;
  reference.samples_per_pixel = 256;
  const image::Film converged = render(scene, cam, reference);
  const image::Image8 ref = image::develop(converged);

  RenderSettings one;
  one.samples_per_pixel = 1;
  one.frame = 3;
  const image::Film film = render(scene, cam, one);
  const std::vector<Color> denoised = denoise(film);
  const image::Image8 out = image::develop(cam.width(), cam.height(), denoised);

  const EdgeFigures conv = edge(ref, ref), def = edge(out, ref);
  EXPECT_GE(conv.rows, 4);  // the edge is spread over several rows
  EXPECT_LT(conv.dither, 2e-5);
  EXPECT_LT(def.dither, 1e-3);
  EXPECT_LT(def.rmse, 0.045);
}

}  // namespace
}  // namespace wobble::render
