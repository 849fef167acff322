#include "image/compose.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace wobble::image {
namespace {

void requireRgb(const Image8& image, const char* what) {
  if (image.channels != 3) throw std::invalid_argument(std::string(what) + ": expected an RGB image");
}

// rect clipped to the image.
PixelRect clip(const Image8& image, PixelRect r) {
  const int x0 = std::max(0, r.x), y0 = std::max(0, r.y);
  const int x1 = std::min(image.width, r.x + r.width), y1 = std::min(image.height, r.y + r.height);
  return {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
}

}  // namespace

void paste(Image8& target, const Image8& source, int x, int y) {
  requireRgb(target, "paste target");
  requireRgb(source, "paste source");
  const PixelRect r = clip(target, {x, y, source.width, source.height});
  for (int row = r.y; row < r.y + r.height; ++row)
    std::memcpy(&target.at(r.x, row), &source.at(r.x - x, row - y), std::size_t(r.width) * 3);
}

void fill(Image8& target, PixelRect rect, Rgb8 color) { blend(target, rect, color, 1); }

void blend(Image8& target, PixelRect rect, Rgb8 color, float alpha) {
  requireRgb(target, "blend target");
  const PixelRect r = clip(target, rect);
  for (int y = r.y; y < r.y + r.height; ++y)
    for (int x = r.x; x < r.x + r.width; ++x) blendPixel(target, x, y, color, alpha);
}

}  // namespace wobble::image
