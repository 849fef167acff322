// RMSE of display values and relative MSE, over the frame and its worst tile (see image_error.h).
#include "image/image_error.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace wobble::image {

ImageError imageError(int width, int height, std::span<const Color> image, std::span<const Color> reference,
                      const ToneMap& tone_map, int tile_size) {
  const std::size_t n = std::size_t(width) * height;
  if (width <= 0 || height <= 0 || tile_size <= 0 || image.size() != n || reference.size() != n)
    throw std::invalid_argument("imageError: images of different or empty sizes");
  const auto display = [&](float linear) { return linearToSrgb(tone_map.apply(linear)); };
  const int tiles_x = (width + tile_size - 1) / tile_size, tiles_y = (height + tile_size - 1) / tile_size;
  std::vector<double> tile_sq(std::size_t(tiles_x) * tiles_y, 0), tile_rel(tile_sq.size(), 0);
  std::vector<long> tile_values(tile_sq.size(), 0);
  double sq = 0, rel = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t i = std::size_t(y) * width + x, t = std::size_t(y / tile_size) * tiles_x + x / tile_size;
      for (int c = 0; c < 3; ++c) {
        const double d = double(display(image[i][c])) - double(display(reference[i][c]));
        const double r = reference[i][c], e = double(image[i][c]) - r;
        const double re = e * e / (r * r + 0.01);
        sq += d * d, rel += re;
        tile_sq[t] += d * d, tile_rel[t] += re, tile_values[t] += 1;
      }
    }
  ImageError error;
  error.rmse = std::sqrt(sq / double(3 * n));
  error.relmse = rel / double(3 * n);
  const long full = 3L * tile_size * tile_size;
  for (std::size_t t = 0; t < tile_sq.size(); ++t) {
    if (2 * tile_values[t] < full && tile_values[t] < long(3 * n)) continue;  // a sliver at the edge
    error.worst_tile_rmse = std::max(error.worst_tile_rmse, std::sqrt(tile_sq[t] / double(tile_values[t])));
    error.worst_tile_relmse = std::max(error.worst_tile_relmse, tile_rel[t] / double(tile_values[t]));
  }
  return error;
}

}  // namespace wobble::image
