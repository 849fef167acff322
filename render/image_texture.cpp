// Bitmap texture: sRGB decoding on load, wrap modes and bilinear lookup (see image_texture.h).
#include "render/image_texture.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "image/png_io.h"

namespace wobble::render {

ImageTexture::ImageTexture(int width, int height, std::vector<Color> texels, Wrap wrap)
    : width_(width), height_(height), texels_(std::move(texels)), wrap_(wrap) {
  if (width <= 0 || height <= 0 || texels_.size() != std::size_t(width) * height)
    throw std::invalid_argument("image texture: " + std::to_string(texels_.size()) + " texels do not make a " +
                                std::to_string(width) + "x" + std::to_string(height) + " image");
}

ImageTexture ImageTexture::load(const std::filesystem::path& file, Wrap wrap) {
  return fromSrgb8(image::readImage(file), wrap);
}

ImageTexture ImageTexture::fromSrgb8(const image::Image8& image, Wrap wrap) {
  if (image.channels < 1 || image.channels > 4)
    throw std::invalid_argument("image texture: unsupported channel count " + std::to_string(image.channels));
  std::vector<Color> texels(std::size_t(image.width) * image.height);
  const bool grey = image.channels < 3;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      Color& c = texels[std::size_t(y) * image.width + x];
      for (int k = 0; k < 3; ++k) c[k] = srgb8ToLinear(image.at(x, y, grey ? 0 : k));
    }
  return ImageTexture(image.width, image.height, std::move(texels), wrap);
}

int ImageTexture::wrapIndex(int i, int n) const {
  if (wrap_ == Wrap::Clamp) return i < 0 ? 0 : (i >= n ? n - 1 : i);
  const int m = i % n;
  return m < 0 ? m + n : m;
}

Color ImageTexture::eval(const Eigen::Vector2f& uv) const {
  // Continuous texel coordinates with texel centres at integers.
  const float fx = uv.x() * static_cast<float>(width_) - 0.5f;
  const float fy = (1.0f - uv.y()) * static_cast<float>(height_) - 0.5f;
  if (!std::isfinite(fx) || !std::isfinite(fy)) return Color::Zero();
  const float x0f = std::floor(fx), y0f = std::floor(fy);
  const float tx = fx - x0f, ty = fy - y0f;
  // Bring huge coordinates into int range first: clamping keeps the edge, and fmod by a multiple of n keeps the
  // residue that Repeat needs.
  const auto reduce = [this](float f, int n) {
    const float nf = static_cast<float>(n);
    return static_cast<int>(wrap_ == Wrap::Clamp ? std::clamp(f, -1.0f, nf) : std::fmod(f, nf * 1024.0f));
  };
  const int x0 = reduce(x0f, width_), y0 = reduce(y0f, height_);
  const int xa = wrapIndex(x0, width_), xb = wrapIndex(x0 + 1, width_);
  const int ya = wrapIndex(y0, height_), yb = wrapIndex(y0 + 1, height_);
  const Color top = (1 - tx) * texel(xa, ya) + tx * texel(xb, ya);
  const Color bottom = (1 - tx) * texel(xa, yb) + tx * texel(xb, yb);
  return (1 - ty) * top + ty * bottom;
}

}  // namespace wobble::render
