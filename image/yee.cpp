// idiff -p as OpenImageIO 2.4 computes it (see yee.h).
#include "image/yee.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace wobble::image {

namespace {

using Lab = std::array<float, 3>;

// OpenImageIO's constants: Adobe RGB (1998), reference white D65 -> XYZ (Bruce Lindbloom's matrix), then L*a*b*
// relative to the white the matrix maps (1, 1, 1) to.
Lab adobeRgbToLab(float r, float g, float b) {
  const float xyz[3] = {r * 0.576700f + g * 0.185556f + b * 0.188212f, r * 0.297361f + g * 0.627355f + b * 0.0752847f,
                        r * 0.0270328f + g * 0.0706879f + b * 0.991248f};
  const float white[3] = {0.576700f + 0.185556f + 0.188212f, 0.297361f + 0.627355f + 0.0752847f,
                          0.0270328f + 0.0706879f + 0.991248f};
  const float epsilon = 216.0f / 24389.0f, kappa = 24389.0f / 27.0f;
  float f[3];
  for (int i = 0; i < 3; ++i) {
    const float t = xyz[i] / white[i];
    f[i] = t > epsilon ? std::pow(t, 1.0f / 3.0f) : (kappa * t + 16.0f) / 116.0f;
  }
  return {116.0f * f[1] - 16.0f, 500.0f * (f[0] - f[1]), 200.0f * (f[1] - f[2])};
}

float channelOrBlack(const ImageF& i, int x, int y, int c) {
  return x < i.width && y < i.height && c < i.channels ? i.at(x, y, c) : 0.0f;
}

Lab labAt(const ImageF& i, int x, int y) {
  return adobeRgbToLab(channelOrBlack(i, x, y, 0), channelOrBlack(i, x, y, 1), channelOrBlack(i, x, y, 2));
}

}  // namespace

long yeeFailures(const ImageF& a, const ImageF& b) {
  // The luminance terms as 2.4 evaluates them (yee.h): adaptation 1e-5 (< 10 cd/m^2, so the colour scale is
  // (1 - (10 - 1) / 10)^2 = 0.01) and the threshold factor clamped up to 1.
  constexpr float kColorScale = 0.01f, kFactor = 1.0f;
  const int width = std::max(a.width, b.width), height = std::max(a.height, b.height);
  long failures = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Lab la = labAt(a, x, y), lb = labAt(b, x, y);
      const float da = la[1] - lb[1], db = la[2] - lb[2];
      if ((da * da + db * db) * kColorScale > kFactor) ++failures;
    }
  return failures;
}

}  // namespace wobble::image
