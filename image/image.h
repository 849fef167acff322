// Image8 and ImageF: plain interleaved images, row 0 at the top.
//   Image8  8-bit codes (PNG files; sRGB-encoded when they hold colour)
//   ImageF  floats (linear radiance, or 8-bit codes / 255 for comparisons)
// channels: 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace wobble::image {

template <typename T>
struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<T> pixels;  // width * height * channels values, row-major, interleaved

  Image() = default;
  Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(std::size_t(w) * h * c, T{}) {}

  std::size_t index(int x, int y, int c = 0) const { return (std::size_t(y) * width + x) * channels + c; }
  T& at(int x, int y, int c = 0) { return pixels[index(x, y, c)]; }
  const T& at(int x, int y, int c = 0) const { return pixels[index(x, y, c)]; }
  bool sameShape(const Image& o) const { return width == o.width && height == o.height && channels == o.channels; }
};

using Image8 = Image<std::uint8_t>;
using ImageF = Image<float>;

// Codes / 255, and back with rounding and clamping.
ImageF toFloat(const Image8& image);
Image8 toImage8(const ImageF& image);

}  // namespace wobble::image
