// Conversions between 8-bit and float images (see image.h).
#include "image/image.h"

#include <algorithm>
#include <cmath>

namespace wobble::image {

ImageF toFloat(const Image8& image) {
  ImageF out(image.width, image.height, image.channels);
  std::transform(image.pixels.begin(), image.pixels.end(), out.pixels.begin(),
                 [](std::uint8_t c) { return static_cast<float>(c) / 255.0f; });
  return out;
}

Image8 toImage8(const ImageF& image) {
  Image8 out(image.width, image.height, image.channels);
  std::transform(image.pixels.begin(), image.pixels.end(), out.pixels.begin(), [](float v) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(std::isnan(v) ? 0.0f : v, 0.0f, 1.0f) * 255.0f));
  });
  return out;
}

}  // namespace wobble::image
