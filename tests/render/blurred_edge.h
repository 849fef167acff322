// A blurred edge's figures, for the tests that a lens's or a shutter's blur comes out blurred rather than dithered at
// one sample a pixel (depth_of_field_test.cpp, motion_blur_denoise_test.cpp). The edge runs along the image's rows,
// so the converged picture is the same in every column of its band: the mean squared difference between
// horizontally neighbouring pixels there is noise (dither), and the band's RMSE against the converged picture is the
// error.
#pragma once
#include <cmath>
#include <vector>

#include "image/image.h"
#include "render/camera.h"
#include "render/lights.h"

namespace wobble::render::testing {

// The view both tests take: the eye 2.3 m up, 4 m in front of a board whose top edge is 2 m up (the edge's band lies
// in the image's lower half), 96 x 64 at 30 degrees; and a sun from above, behind the eye.
inline CameraParams boardCamera() {
  CameraParams cp;
  cp.position = {0, 2.3f, 6};
  cp.look_at = {0, 2.3f, -10};
  cp.vfov_deg = 30;
  cp.width = 96;
  cp.height = 64;
  return cp;
}
inline SunLight boardSun() {
  SunLight sun;
  sun.direction = Eigen::Vector3f(0.3f, 1, 0.8f);
  return sun;
}

inline double luminance8(const image::Image8& im, int x, int y) {
  return (0.2126 * im.at(x, y, 0) + 0.7152 * im.at(x, y, 1) + 0.0722 * im.at(x, y, 2)) / 255.0;
}

struct EdgeFigures {
  double dither = 0, rmse = 0;  // mean squared neighbour difference along the band; RMSE against the reference
  int rows = 0;
};

// The band: rows whose converged mean lies between 5% and 95% of the way from the bottom row's to the top row's.
inline EdgeFigures edge(const image::Image8& image, const image::Image8& reference) {
  const int w = reference.width, h = reference.height;
  std::vector<double> row(h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) row[y] += luminance8(reference, x, y) / w;
  const double top = row[0], bottom = row[h - 1];
  EdgeFigures f;
  int pairs = 0, pixels = 0;
  for (int y = 0; y < h; ++y) {
    const double s = (row[y] - bottom) / (top - bottom);
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

}  // namespace wobble::render::testing
