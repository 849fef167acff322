// CIE76 colour difference of two sRGB images (see color_difference.h).
#include "image/color_difference.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "image/color.h"

namespace wobble::image {

Eigen::Vector3d srgb8ToLab(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  // Linear Rec.709 (sRGB primaries) -> XYZ, D65 (IEC 61966-2-1).
  const Eigen::Vector3d rgb(srgb8ToLinear(r), srgb8ToLinear(g), srgb8ToLinear(b));
  Eigen::Matrix3d m;
  m << 0.4124564, 0.3575761, 0.1804375,  //
      0.2126729, 0.7151522, 0.0721750,   //
      0.0193339, 0.1191920, 0.9503041;
  const Eigen::Vector3d xyz = m * rgb, white(0.95047, 1.0, 1.08883);
  const auto f = [](double t) {
    constexpr double d = 6.0 / 29;
    return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29;
  };
  const double fx = f(xyz.x() / white.x()), fy = f(xyz.y() / white.y()), fz = f(xyz.z() / white.z());
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

ColorDifference cie76(const Image8& a, const Image8& b) {
  if (a.width != b.width || a.height != b.height || a.channels < 3 || b.channels < 3)
    throw std::invalid_argument("cie76: images of " + std::to_string(a.width) + " x " + std::to_string(a.height) +
                                " (" + std::to_string(a.channels) + " channels) and " + std::to_string(b.width) +
                                " x " + std::to_string(b.height) + " (" + std::to_string(b.channels) +
                                " channels): need the same size and RGB");
  std::vector<double> d;
  d.reserve(std::size_t(a.width) * a.height);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      d.push_back((srgb8ToLab(a.at(x, y, 0), a.at(x, y, 1), a.at(x, y, 2)) -
                   srgb8ToLab(b.at(x, y, 0), b.at(x, y, 1), b.at(x, y, 2)))
                      .norm());
  ColorDifference result;
  if (d.empty()) return result;
  double sum = 0;
  for (const double v : d) sum += v;
  result.mean = sum / double(d.size());
  result.max = *std::max_element(d.begin(), d.end());
  const auto k = d.begin() + std::ptrdiff_t(0.95 * double(d.size() - 1));
  std::nth_element(d.begin(), k, d.end());
  result.p95 = *k;
  return result;
}

}  // namespace wobble::image
