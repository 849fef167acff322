// Film storage and tone mapping to 8-bit sRGB (see film.h).
#include "render/image/film.h"

#include <limits>
#include <stdexcept>

namespace wobble::render {

Film::Film(int w, int h)
    : width(w),
      height(h),
      color(std::size_t(w) * h, Color::Zero()),
      albedo(std::size_t(w) * h, Color::Zero()),
      normal(std::size_t(w) * h, Eigen::Vector3f::Zero()),
      depth(std::size_t(w) * h, std::numeric_limits<float>::infinity()),
      diffuse(std::size_t(w) * h, Color::Zero()),
      variance_diffuse(std::size_t(w) * h, -1.0f),
      variance_other(std::size_t(w) * h, -1.0f),
      samples(std::size_t(w) * h, 0) {}

Image8 develop(int width, int height, std::span<const Color> color, const ToneMap& tone_map) {
  if (color.size() != std::size_t(width) * height) throw std::invalid_argument("develop: wrong number of pixels");
  Image8 image(width, height, 3);
  static_assert(sizeof(Color) == 3 * sizeof(float), "a Color is three packed floats");
  tone_map.toSrgb8(std::span<const float>(color.data()->data(), 3 * color.size()), image.pixels.data());
  return image;
}

}  // namespace wobble::render
