// ImageTexture: a bitmap texture with bilinear filtering.
//
// Parameters:
//   file or texels   an 8-bit image (PNG, JPEG, ... anything stb_image reads) holds sRGB-encoded colour and is
//                    decoded to linear on load; alpha is ignored. Texels given directly are linear RGB.
//   wrap             Repeat (tiles: u = 1.25 reads like u = 0.25) or Clamp (edge texels extend outwards)
// Lookup: image row = (1 - v) * height (OBJ convention, v up), column = u * width; texel centres sit at half-integer
// positions, so uv exactly at a texel centre returns that texel and halfway between two centres their mean.
#pragma once
#include <algorithm>
#include <filesystem>
#include <span>
#include <vector>

#include "image/image.h"
#include "render/color.h"
#include "render/texture.h"

namespace wobble::render {

enum class Wrap { Repeat, Clamp };

class ImageTexture final : public Texture {
 public:
  ImageTexture(int width, int height, std::vector<Color> linear_texels, Wrap wrap = Wrap::Repeat);

  // Throws std::runtime_error naming the file when it cannot be read.
  static ImageTexture load(const std::filesystem::path& file, Wrap wrap = Wrap::Repeat);
  // From 8-bit sRGB codes with 1 to 4 channels (grey is replicated to RGB; alpha is ignored).
  static ImageTexture fromSrgb8(const image::Image8& image, Wrap wrap = Wrap::Repeat);

  Color eval(const Eigen::Vector2f& uv) const override;
  float featureSize() const override { return 1.0f / static_cast<float>(std::max(width_, height_)); }  // a texel
  const Color& texel(int x, int y) const { return texels_[std::size_t(y) * width_ + x]; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int wrapIndex(int i, int n) const;

  int width_, height_;
  std::vector<Color> texels_;  // row 0 at the top of the image
  Wrap wrap_;
};

}  // namespace wobble::render
