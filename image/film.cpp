// Film storage and tone mapping to 8-bit sRGB (see film.h).
#include "image/film.h"

#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace wobble::image {

Film Film::unfilled(int w, int h) {
  Film film;
  film.width = w, film.height = h;
  const std::size_t n = std::size_t(w) * h;
  // Eigen's vectors have no default value: sizing them writes nothing.
  film.color.resize(n), film.albedo.resize(n), film.normal.resize(n), film.diffuse.resize(n);
  film.depth.resize(n), film.variance_diffuse.resize(n), film.variance_other.resize(n), film.blur.resize(n);
  film.motion.resize(n), film.samples.resize(n);
  return film;
}

Film::Film(int w, int h) : Film(unfilled(w, h)) {
  // Filled on threads: a 720p film is 59 MB.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, color.size(), 1 << 14),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) clearPixel(i);
                    });
}

Image8 develop(int width, int height, std::span<const Color> color, const ToneMap& tone_map) {
  if (color.size() != std::size_t(width) * height) throw std::invalid_argument("develop: wrong number of pixels");
  Image8 image(width, height, 3);
  static_assert(sizeof(Color) == 3 * sizeof(float), "a Color is three packed floats");
  tone_map.toSrgb8(std::span<const float>(color.data()->data(), 3 * color.size()), image.pixels.data());
  return image;
}

}  // namespace wobble::image
