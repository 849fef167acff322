#include "app/compare/tile_label.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace wobble {

TileView tileView(const VariantTrack& track, int frame, double time) {
  TileView view;
  if (frame <= track.last_frame) {
    view.picture = frame;
    view.status = "t = " + labelSeconds(time) + " s";
    if (track.lost_shape_frame && frame >= *track.lost_shape_frame) {
      view.status += ", lost its shape at " + labelSeconds(track.lost_shape_time) + " s (strain " +
                     shortNumber(track.lost_shape_strain) + " > " + shortNumber(track.strain_bound) + ")";
      view.color = kLostShapeColor;
    }
    return view;
  }
  view.picture = track.last_frame >= track.first_frame ? track.last_frame : 0;
  view.frozen = true;
  view.color = kBlewUpColor;
  view.status = track.blow_up_time ? "blew up at t = " + labelSeconds(*track.blow_up_time) + " s (step " +
                                         std::to_string(track.blow_up_step) + ")"
                                   : "stopped";
  return view;
}

std::string shortNumber(double x) {
  char text[32];
  const double magnitude = std::fabs(x);
  if (x != 0 && (magnitude < 0.01 || magnitude >= 1e4)) {
    std::snprintf(text, sizeof text, "%.2e", x);  // "1.20e-03": trim to "1.2e-3"
    std::string s = text;
    const auto e = s.find('e');
    std::string mantissa = s.substr(0, e), exponent = s.substr(e + 1);
    while (mantissa.back() == '0') mantissa.pop_back();
    if (mantissa.back() == '.') mantissa.pop_back();
    const bool negative = exponent[0] == '-';
    exponent.erase(0, 1);
    exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
    return mantissa + "e" + (negative ? "-" : "") + exponent;
  }
  // Three significant digits without an exponent, trailing zeros dropped: 1400, 1.98, 0.0333, 0.5.
  const int decimals = x == 0 ? 0 : std::max(0, 2 - int(std::floor(std::log10(magnitude))));
  std::snprintf(text, sizeof text, "%.*f", decimals, x);
  std::string s = text;
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

std::string labelSeconds(double t) {
  char text[32];
  std::snprintf(text, sizeof text, t >= 0.1 || t == 0 ? "%.2f" : "%.2g", t);
  return text;
}

float labelPixels(int tile_height) { return std::clamp(float(tile_height) / 18.0f, 9.0f, 40.0f); }

void drawLabel(image::Image8& tile, const image::Font& font, const std::string& title, const TileView& view) {
  const float px = labelPixels(tile.height);
  const int pad = std::max(2, int(px / 4)), line = font.lineHeight(px);
  const int width = std::max(font.width(title, px), font.width(view.status, px)) + 2 * pad;
  image::blend(tile, {0, 0, width, 2 * line + 2 * pad}, {0, 0, 0}, 0.6f);
  font.draw(tile, pad, pad, title, px, {255, 255, 255});
  font.draw(tile, pad, pad + line, view.status, px, view.color);
}

}  // namespace wobble
