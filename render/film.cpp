// Film storage and tone mapping to 8-bit sRGB (see film.h).
#include "film.h"

#include <limits>

namespace wobble::render {

Film::Film(int w, int h)
    : width(w),
      height(h),
      color(std::size_t(w) * h, Color::Zero()),
      albedo(std::size_t(w) * h, Color::Zero()),
      normal(std::size_t(w) * h, Eigen::Vector3f::Zero()),
      depth(std::size_t(w) * h, std::numeric_limits<float>::infinity()) {}

Image8 develop(const Film& film, const ToneMap& tone_map) {
  Image8 image(film.width, film.height, 3);
  for (std::size_t i = 0; i < film.color.size(); ++i)
    for (int c = 0; c < 3; ++c) image.pixels[3 * i + c] = linearToSrgb8(tone_map.apply(film.color[i][c]));
  return image;
}

}  // namespace wobble::render
