// Putting pictures together: paste one image into another (the tiles of `wobble compare`'s grid), fill a rectangle
// (an empty cell), or blend a colour over one (the shaded box behind a label). 3-channel (RGB) Image8 only; every
// operation is clipped to the target, so a rectangle may reach past its edges.
#pragma once
#include <array>
#include <cstdint>

#include "image/image.h"

namespace wobble::image {

using Rgb8 = std::array<std::uint8_t, 3>;

struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;
};

// source's pixels at (x, y) of target. Throws std::invalid_argument unless both are RGB.
void paste(Image8& target, const Image8& source, int x, int y);
void fill(Image8& target, PixelRect rect, Rgb8 color);
// Each pixel of rect moved towards color by alpha (0: unchanged, 1: color).
void blend(Image8& target, PixelRect rect, Rgb8 color, float alpha);

// One pixel moved towards color by alpha in [0, 1], in 8-bit codes, rounded.
inline void blendPixel(Image8& target, int x, int y, Rgb8 color, float alpha) {
  for (int c = 0; c < 3; ++c) {
    std::uint8_t& v = target.at(x, y, c);
    v = static_cast<std::uint8_t>(float(v) + (float(color[c]) - float(v)) * alpha + 0.5f);
  }
}

}  // namespace wobble::image
