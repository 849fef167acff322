// Film storage and tone mapping to 8-bit sRGB (see film.h).
#include "render/image/film.h"

#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace wobble::render {

Film::Film(int w, int h) : width(w), height(h) {
  // The colour layers are sized without a fill (Eigen's vectors have no default value) and filled on threads: a
  // 720p film is 59 MB, and one thread zeroing it held up every frame by about 5 ms.
  const std::size_t n = std::size_t(w) * h;
  color.resize(n), albedo.resize(n), normal.resize(n), diffuse.resize(n);
  depth.assign(n, std::numeric_limits<float>::infinity());
  variance_diffuse.assign(n, -1.0f), variance_other.assign(n, -1.0f);
  samples.assign(n, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      color[i] = albedo[i] = normal[i] = diffuse[i] = Eigen::Vector3f::Zero();
  });
}

Image8 develop(int width, int height, std::span<const Color> color, const ToneMap& tone_map) {
  if (color.size() != std::size_t(width) * height) throw std::invalid_argument("develop: wrong number of pixels");
  Image8 image(width, height, 3);
  static_assert(sizeof(Color) == 3 * sizeof(float), "a Color is three packed floats");
  tone_map.toSrgb8(std::span<const float>(color.data()->data(), 3 * color.size()), image.pixels.data());
  return image;
}

}  // namespace wobble::render
