// Helpers shared by the renderer tests: a scratch directory removed at the end of the test, small scenes, and the
// error of a region of a displayed picture.
#pragma once
#include <cmath>
#include <utility>
#include <vector>

#include "image/film.h"
#include "render/scene.h"
#include "tests/temp_dir.h"

namespace wobble::render::test {

using wobble::test::TempDir;

// Whether inside(u, v) holds at the pixel's four corners and its centre (image coordinates).
template <class Inside>
bool wholePixel(int x, int y, const Inside& inside) {
  for (const auto& [dx, dy] : {std::pair{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}, {1.0f, 1.0f}, {0.5f, 0.5f}})
    if (!inside(float(x) + dx, float(y) + dy)) return false;
  return true;
}

// RMSE over R, G and B of the displayed (tone-mapped, 8-bit) pictures, as docs/rendering.md measures frames, over
// the pixels (x, y) where region(x, y) holds.
template <class Region>
double displayRmse(int width, int height, const std::vector<Color>& image, const std::vector<Color>& reference,
                   const Region& region) {
  const image::Image8 a = image::develop(width, height, image);
  const image::Image8 b = image::develop(width, height, reference);
  double sq = 0;
  int n = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (!region(x, y)) continue;
      for (int c = 0; c < 3; ++c) {
        const double d = (double(a.at(x, y, c)) - double(b.at(x, y, c))) / 255.0;
        sq += d * d;
      }
      ++n;
    }
  return std::sqrt(sq / (3.0 * n));
}

}  // namespace wobble::render::test
