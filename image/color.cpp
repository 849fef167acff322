// sRGB transfer functions and tone-map curves (see color.h).
#include "image/color.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace wobble::image {

float srgbToLinear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }

float srgb8ToLinear(std::uint8_t code) {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = srgbToLinear(static_cast<float>(i) / 255.0f);
    return t;
  }();
  return table[code];
}

float linearToSrgb(float v) { return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f; }

namespace {

// thresholds[k]: the linear value from which the code is k + 1 (its encoding is (k + 0.5) / 255, rounded up);
// start[i]: the code at linear value i / kBuckets. A bucket spans at most one threshold (the steepest part of the
// curve, near 0, has 12.92 * 255 / kBuckets < 1 code per bucket), so one comparison finishes the lookup.
constexpr int kBuckets = 4096;
struct SrgbTable {
  std::array<float, 256> thresholds{};
  std::array<std::uint8_t, kBuckets + 1> start{};
  SrgbTable() {
    for (int k = 0; k < 255; ++k) thresholds[k] = srgbToLinear((static_cast<float>(k) + 0.5f) / 255.0f);
    thresholds[255] = 2.0f;  // never reached: inputs are clamped to 1
    for (int i = 0; i <= kBuckets; ++i)
      start[i] = static_cast<std::uint8_t>(
          std::upper_bound(thresholds.begin(), thresholds.begin() + 255, static_cast<float>(i) / kBuckets) -
          thresholds.begin());
  }
};

const SrgbTable& srgbTable() {
  static const SrgbTable table;
  return table;
}

std::uint8_t encode(const SrgbTable& table, float linear) {
  // !(x > 0) also sends NaN to black rather than to an arbitrary code.
  if (!(linear > 0)) return 0;
  const float v = std::min(linear, 1.0f);
  // A bucket spans at most one threshold (SrgbTable): one step up at most, taken without a branch to mispredict.
  const int code = table.start[static_cast<int>(v * kBuckets)];
  return static_cast<std::uint8_t>(code + (v >= table.thresholds[code]));
}

template <ToneMap::Curve kCurve>
float curve(float x) {
  float y = x;
  if constexpr (kCurve == ToneMap::Curve::Aces) y = x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f);
  if constexpr (kCurve == ToneMap::Curve::Reinhard) y = x / (1.0f + x);
  return std::clamp(y, 0.0f, 1.0f);
}

// Calls fn with the curve as a function object: one switch per image rather than per value.
template <typename Fn>
void withCurve(ToneMap::Curve c, const Fn& fn) {
  switch (c) {
    case ToneMap::Curve::Aces:
      return fn(curve<ToneMap::Curve::Aces>);
    case ToneMap::Curve::Reinhard:
      return fn(curve<ToneMap::Curve::Reinhard>);
    case ToneMap::Curve::Clamp:
      return fn(curve<ToneMap::Curve::Clamp>);
  }
}

}  // namespace

std::uint8_t linearToSrgb8(float linear) { return encode(srgbTable(), linear); }

float ToneMap::curveOf(float x) const {
  float y = 0;
  withCurve(curve, [&](const auto& f) { y = f(x); });
  return y;
}

void ToneMap::toSrgb8(std::span<const float> linear, std::uint8_t* out) const {
  const SrgbTable& table = srgbTable();
  const float s = scale();
  withCurve(curve, [&](const auto& f) {
    for (std::size_t i = 0; i < linear.size(); ++i) out[i] = encode(table, f(std::max(0.0f, linear[i]) * s));
  });
}

}  // namespace wobble::image
