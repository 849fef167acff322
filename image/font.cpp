#include "image/font.h"

#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <vector>

#include <stb/stb_truetype.h>

namespace wobble::image {

struct Font::Data {
  std::vector<unsigned char> bytes;  // stbtt_fontinfo points into them
  stbtt_fontinfo info{};
};

namespace {

// The code points of UTF-8 text; a byte that does not start a well-formed sequence stands for itself (Latin-1).
std::vector<int> codePoints(std::string_view text) {
  std::vector<int> points;
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char lead = byte(i);
    const std::size_t extra = lead >= 0xF0 ? 3 : lead >= 0xE0 ? 2 : lead >= 0xC0 ? 1 : 0;
    int cp = lead & (0x3F >> extra);
    std::size_t k = 1;
    for (; k <= extra && i + k < text.size() && (byte(i + k) & 0xC0) == 0x80; ++k)
      cp = (cp << 6) | (byte(i + k) & 0x3F);
    const bool whole = extra > 0 && k == extra + 1;
    points.push_back(whole ? cp : lead);
    i += whole ? extra + 1 : 1;
  }
  return points;
}

struct Placed {
  int code;
  float pen;  // x where the glyph's origin is
};

// Where each character of text goes at this scale (advances and kerning), and the pen's end.
std::vector<Placed> layOut(const stbtt_fontinfo& info, std::string_view text, float scale, float start, float& end) {
  std::vector<Placed> placed;
  const std::vector<int> points = codePoints(text);
  float pen = start;
  for (std::size_t i = 0; i < points.size(); ++i) {
    placed.push_back({points[i], pen});
    int advance = 0, bearing = 0;
    stbtt_GetCodepointHMetrics(&info, points[i], &advance, &bearing);
    pen += float(advance) * scale;
    if (i + 1 < points.size()) pen += float(stbtt_GetCodepointKernAdvance(&info, points[i], points[i + 1])) * scale;
  }
  end = pen;
  return placed;
}

}  // namespace

Font Font::load(const std::filesystem::path& file) {
  auto data = std::make_shared<Data>();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot read the font file");
  data->bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  const int offset = data->bytes.size() < 12 ? -1 : stbtt_GetFontOffsetForIndex(data->bytes.data(), 0);
  if (offset < 0 || !stbtt_InitFont(&data->info, data->bytes.data(), offset))
    throw std::runtime_error(file.string() + ": not a TrueType font stb_truetype can read");
  return Font(std::move(data));
}

int Font::lineHeight(float px) const {
  int ascent = 0, descent = 0, gap = 0;
  stbtt_GetFontVMetrics(&data_->info, &ascent, &descent, &gap);
  return int(std::ceil(float(ascent - descent + gap) * stbtt_ScaleForPixelHeight(&data_->info, px)));
}

int Font::width(std::string_view text, float px) const {
  float end = 0;
  layOut(data_->info, text, stbtt_ScaleForPixelHeight(&data_->info, px), 0, end);
  return int(std::ceil(end));
}

void Font::draw(Image8& image, int x, int y, std::string_view text, float px, Rgb8 color) const {
  if (image.channels != 3) throw std::invalid_argument("Font::draw: expected an RGB image");
  const stbtt_fontinfo& info = data_->info;
  const float scale = stbtt_ScaleForPixelHeight(&info, px);
  int ascent = 0, descent = 0, gap = 0;
  stbtt_GetFontVMetrics(&info, &ascent, &descent, &gap);
  const int baseline = y + int(std::lround(float(ascent) * scale));
  float end = 0;
  std::vector<unsigned char> coverage;
  for (const auto& [code, pen] : layOut(info, text, scale, float(x), end)) {
    const float shift = pen - std::floor(pen);  // subpixel placement keeps the spacing even
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    stbtt_GetCodepointBitmapBoxSubpixel(&info, code, scale, scale, shift, 0, &x0, &y0, &x1, &y1);
    const int w = x1 - x0, h = y1 - y0;
    if (w <= 0 || h <= 0) continue;  // a space
    coverage.assign(std::size_t(w) * h, 0);
    stbtt_MakeCodepointBitmapSubpixel(&info, coverage.data(), w, h, w, scale, scale, shift, 0, code);
    const int left = int(std::floor(pen)) + x0, top = baseline + y0;
    for (int row = 0; row < h; ++row)
      for (int col = 0; col < w; ++col) {
        const int px_x = left + col, px_y = top + row;
        const unsigned char a = coverage[std::size_t(row) * w + col];
        if (a == 0 || px_x < 0 || px_y < 0 || px_x >= image.width || px_y >= image.height) continue;
        blendPixel(image, px_x, px_y, color, float(a) / 255.0f);
      }
  }
}

}  // namespace wobble::image
