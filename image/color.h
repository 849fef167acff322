// Colour: linear RGB values (Eigen::Vector3f, scene-referred, Rec.709 primaries), the sRGB transfer functions and
// the tone map from linear radiance to display values.
//
// Tone map (ToneMap), applied per channel:
//   exposure   stops; the linear value is first multiplied by 2^exposure
//   curve      Aces:     Narkowicz's 2015 fit of the ACES filmic curve, x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14);
//                        soft highlight roll-off, slight toe; maps 0 to 0 and saturates at 1 near x = 10
//              Reinhard: x / (1 + x)
//              Clamp:    min(x, 1), no curve (tests, albedo previews)
// The result is clamped to [0, 1], encoded with the sRGB transfer function and rounded to 8 bits.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

#include <Eigen/Core>

namespace wobble::image {

using Color = Eigen::Vector3f;

// sRGB electro-optical transfer: encoded value in [0, 1] -> linear.
float srgbToLinear(float encoded);
// Exact decode of an 8-bit sRGB code (table lookup).
float srgb8ToLinear(std::uint8_t code);
// Linear in [0, 1] -> sRGB encoded value in [0, 1].
float linearToSrgb(float linear);
// Linear -> 8-bit sRGB code, clamping to [0, 1] and rounding to nearest (a binary search of the 255 linear values
// where the code changes, rather than a pow per value).
std::uint8_t linearToSrgb8(float linear);

inline float luminance(const Color& c) { return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z(); }

struct ToneMap {
  enum class Curve { Aces, Reinhard, Clamp };
  float exposure = 0;  // stops
  Curve curve = Curve::Aces;

  // Linear radiance -> display-linear value in [0, 1] (before the sRGB encoding).
  float apply(float linear) const { return curveOf(std::max(0.0f, linear) * scale()); }
  float scale() const { return std::exp2(exposure); }
  // The curve alone, of an already exposed value >= 0.
  float curveOf(float x) const;
  // apply() then linearToSrgb8() of every value (the same codes), in one pass: out has linear.size() bytes.
  void toSrgb8(std::span<const float> linear, std::uint8_t* out) const;
};

}  // namespace wobble::image
