// Film: the rendered frame, linear and unclamped, with the per-pixel layers written to EXR.
//   color    mean radiance over the pixel's samples (linear RGB)
//   albedo   mean base colour at the first hit (zero where the sky shows)
//   normal   mean shading normal at the first hit, world space, turned towards the camera (not renormalised: it
//            shortens along silhouettes, as denoisers expect; zero where the sky shows)
//   depth    nearest first-hit distance along the optical axis (camera z) over the samples; +inf where every
//            sample saw the sky
// Pixels are stored row-major, row 0 at the top.
#pragma once
#include <vector>

#include <Eigen/Core>

#include "color.h"
#include "image.h"

namespace wobble::render {

struct Film {
  int width = 0, height = 0;
  std::vector<Color> color, albedo;
  std::vector<Eigen::Vector3f> normal;
  std::vector<float> depth;

  Film() = default;
  Film(int w, int h);
  std::size_t index(int x, int y) const { return std::size_t(y) * width + x; }
};

// Tone maps colour to an 8-bit sRGB RGB image (see color.h for the curve).
Image8 develop(const Film& film, const ToneMap& tone_map = {});

}  // namespace wobble::render
