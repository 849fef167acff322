// Depth of field at the default quality (one sample a pixel, denoised): an out-of-focus edge must come out blurred,
// not dithered. A board near the camera, far out of focus, stands against the sky; the focus is far behind it. With
// one lens sample a pixel, each pixel near the board's edge sees either the board or the sky, a dither; the denoiser
// must average them over the lens's blur (denoiser.h: the film's blur layer), as the converged picture does.
// Oracle: the converged picture (256 lens samples a pixel, not denoised). Measure of dither: along the edge the
// converged picture is the same in every column, so the mean squared difference between horizontally neighbouring
// pixels in the edge's band is noise: the denoised picture's must be near the converged one's.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "image/film.h"
#include "render/denoiser.h"
#include "render/renderer.h"
#include "render/scene.h"

namespace wobble::render {
namespace {

using Eigen::Vector3f;

Scene boardAgainstTheSky() {
  Scene scene;
  scene.addQuad("board", Quad{{0, 0, 2}, {0, 0, 1}, 4, 1},
                scene.addMaterial(Material::diffuse("board", Color(0.5f, 0.3f, 0.2f))));
  SunLight sun;
  sun.direction = Vector3f(0.3f, 1, 0.8f);
  scene.lights.suns = {sun};
  scene.commit();
  return scene;
}

Camera camera(float aperture) {
  CameraParams cp;
  cp.position = {0, 2.3f, 6};
  cp.look_at = {0, 2.3f, -10};
  cp.vfov_deg = 30;
  cp.width = 96;
  cp.height = 64;
  cp.aperture = aperture;  // the board's edge is spread over about 4 pixels; the sky by 0.4
  cp.focus = 50;
  return Camera(cp);
}

double luminance8(const image::Image8& im, int x, int y) {
  return (0.2126 * im.at(x, y, 0) + 0.7152 * im.at(x, y, 1) + 0.0722 * im.at(x, y, 2)) / 255.0;
}

struct EdgeFigures {
  double dither = 0, rmse = 0;  // mean squared neighbour difference along the band; RMSE against the reference
  int rows = 0;
};

// The band: rows whose converged mean lies between 5% and 95% of the way from the board to the sky.
EdgeFigures edge(const image::Image8& image, const image::Image8& reference) {
  const int w = reference.width, h = reference.height;
  std::vector<double> row(h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) row[y] += luminance8(reference, x, y) / w;
  const double sky = row[0], board = row[h - 1];
  EdgeFigures f;
  int pairs = 0, pixels = 0;
  for (int y = 0; y < h; ++y) {
    const double s = (row[y] - board) / (sky - board);
    if (s < 0.05 || s > 0.95) continue;
    ++f.rows;
    for (int x = 0; x < w; ++x) {
      if (x > 0) {
        const double d = luminance8(image, x, y) - luminance8(image, x - 1, y);
        f.dither += d * d, ++pairs;
      }
      for (int c = 0; c < 3; ++c) {
        const double d = (double(image.at(x, y, c)) - double(reference.at(x, y, c))) / 255.0;
        f.rmse += d * d;
      }
      ++pixels;
    }
  }
  f.dither /= pairs;
  f.rmse = std::sqrt(f.rmse / (3.0 * pixels));
  return f;
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
