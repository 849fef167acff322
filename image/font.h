// Font: a TrueType font file drawn with stb_truetype (Debian's libstb): text as anti-aliased glyph coverage blended
// into an RGB Image8, with the font's own advances and kerning. `wobble compare` labels its tiles with it.
// Text is UTF-8; a character the font lacks is drawn as the font's missing-glyph box.
#pragma once
#include <filesystem>
#include <memory>
#include <string_view>

#include "image/compose.h"
#include "image/image.h"

namespace wobble::image {

class Font {
 public:
  // Reads the whole file. Throws std::runtime_error naming it when it cannot be read or is not a font.
  static Font load(const std::filesystem::path& file);

  // Distance from one line's top to the next at pixel height px (ascent - descent + line gap), rounded up.
  int lineHeight(float px) const;
  // Width in pixels of text drawn at px (the sum of the advances, kerning included), rounded up.
  int width(std::string_view text, float px) const;
  // Draws text with its line's top at y (the baseline one ascent below) and the pen starting at x; clipped to the
  // image. Throws std::invalid_argument unless the image is RGB.
  void draw(Image8& image, int x, int y, std::string_view text, float px, Rgb8 color) const;

 private:
  struct Data;
  explicit Font(std::shared_ptr<const Data> data) : data_(std::move(data)) {}
  std::shared_ptr<const Data> data_;
};

}  // namespace wobble::image
