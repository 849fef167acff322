// Procedural textures: checker and plank-floor wood (see texture.h).
#include "render/texture.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace wobble::render {

Color Texture::evalFootprint(const Eigen::Vector2f& uv, const TextureFootprint& f) const {
  // Lookups along each of the footprint's two edges in proportion to its length over the finest feature.
  const auto count = [&](const Eigen::Vector2f& edge) {
    const float ratio = edge.norm() / featureSize();
    return !(ratio > 1) ? 1 : ratio >= kMaxLookups ? kMaxLookups : static_cast<int>(std::ceil(ratio));
  };
  const int kx = count(f.duvdx), ky = count(f.duvdy);  // !(ratio > 1) also catches NaN footprints
  if (kx == 1 && ky == 1) return eval(uv);
  Color sum = Color::Zero();
  for (int j = 0; j < ky; ++j)
    for (int i = 0; i < kx; ++i) {
      const float a = (static_cast<float>(i) + f.jitter.x()) / static_cast<float>(kx) - 0.5f;
      const float b = (static_cast<float>(j) + f.jitter.y()) / static_cast<float>(ky) - 0.5f;
      sum += eval(uv + a * f.duvdx + b * f.duvdy);
    }
  return sum / static_cast<float>(kx * ky);
}

Color CheckerTexture::eval(const Eigen::Vector2f& uv) const {
  const auto i = static_cast<long>(std::floor(uv.x() * squares_));
  const auto j = static_cast<long>(std::floor(uv.y() * squares_));
  return ((i + j) & 1) == 0 ? a_ : b_;
}

Color CheckerTexture::evalFootprint(const Eigen::Vector2f& uv, const TextureFootprint& f) const {
  // pbrt's box-filtered checkerboard: in units of squares, bump(x) integrates the 0/1 square wave of period 2.
  const float ds = 0.5f * squares_ * (std::abs(f.duvdx.x()) + std::abs(f.duvdy.x()));
  const float dt = 0.5f * squares_ * (std::abs(f.duvdx.y()) + std::abs(f.duvdy.y()));
  const float s = uv.x() * squares_, t = uv.y() * squares_;
  if (!std::isfinite(ds) || !std::isfinite(dt) ||
      (std::floor(s - ds) == std::floor(s + ds) && std::floor(t - dt) == std::floor(t + dt)))
    return eval(uv);
  const auto bump = [](float x) {
    const float half = std::floor(0.5f * x);
    return half + 2.0f * std::max(0.5f * x - half - 0.5f, 0.0f);
  };
  const float bs = ds > 0 ? (bump(s + ds) - bump(s - ds)) / (2 * ds) : float(int(std::floor(s)) & 1);
  const float bt = dt > 0 ? (bump(t + dt) - bump(t - dt)) / (2 * dt) : float(int(std::floor(t)) & 1);
  const float share_b = bs + bt - 2 * bs * bt;  // odd squares: exactly one of the two coordinates odd
  return (1 - share_b) * a_ + share_b * b_;
}

namespace {

// A pseudo-random value in [0, 1) for an integer (per-plank variation; any good integer hash will do).
float hash01(long k) {
  auto x = static_cast<std::uint32_t>(k * 0x9E3779B1u + 0x7F4A7C15u);
  x ^= x >> 16, x *= 0x85EBCA6Bu, x ^= x >> 13, x *= 0xC2B2AE35u, x ^= x >> 16;
  return static_cast<float>(x >> 8) * 0x1p-24f;
}

// sin(x) to within 1e-3 (a parabola refined once): the grain needs its shape, not libm's last bits, and the texture
// is evaluated up to 16 times per first hit when filtered.
float fastSin(float x) {
  float t = x * (0.5f / std::numbers::pi_v<float>);
  t -= std::floor(t + 0.5f);  // [-0.5, 0.5): one period
  const float y = 8.0f * t - 16.0f * t * std::abs(t);
  return 0.225f * (y * std::abs(y) - y) + y;
}

// The share of [x - width/2, x + width/2] within `half` of an integer (bands of width 2 half around each integer);
// width 0 is the indicator at x.
float bandCoverage(float x, float width, float half) {
  if (!(width > 1e-6f)) {
    const float d = x - std::floor(x + 0.5f);
    return std::abs(d) < half ? 1.0f : 0.0f;
  }
  // Integral of the indicator from a fixed origin: whole periods, then the part of the last one.
  const auto integral = [half](float z) {  // z = y + half: the band is [0, 2 half) of each period
    const float whole = std::floor(z);
    return whole * 2.0f * half + std::min(z - whole, 2.0f * half);
  };
  return std::clamp((integral(x + 0.5f * width + half) - integral(x - 0.5f * width + half)) / width, 0.0f, 1.0f);
}

// A sine's amplitude after a box filter spanning `phase_width` radians: sinc(phase_width / 2), cut at its first
// zero so the wave fades out instead of flipping sign.
float boxedSineAmplitude(float phase_width) {
  const float z = 0.5f * phase_width;
  if (z < 1e-3f) return 1.0f;
  return z >= std::numbers::pi_v<float> ? 0.0f : fastSin(z) / z;
}

// Mean of frac(x)^5 over [x - width/2, x + width/2]: from its integral floor(x) / 6 + frac(x)^6 / 6.
float boxedLateWood(float x, float width) {
  const auto integral = [](float z) {  // times 6
    const float whole = std::floor(z), f = z - whole, f2 = f * f;
    return whole + f2 * f2 * f2;
  };
  return (integral(x + 0.5f * width) - integral(x - 0.5f * width)) / (6.0f * width);
}

// A board's tone, 0.88 to 1.12 (mean 1), averaged over the boards in [across - width/2, across + width/2] by their
// share of it.
float boardTone(float across, float width) {
  const auto tone = [](long board) { return 0.88f + 0.24f * hash01(board + 7919); };
  const float a = across - 0.5f * width, b = across + 0.5f * width;
  const auto first = static_cast<long>(std::floor(a)), last = static_cast<long>(std::floor(b));
  if (first == last) return tone(first);
  if (last - first > 16) return 1.0f;  // the mean, to within the spread of a few dozen boards
  float sum = 0;
  for (long board = first; board <= last; ++board)
    sum += tone(board) * (std::min(b, static_cast<float>(board + 1)) - std::max(a, static_cast<float>(board)));
  return sum / width;
}

}  // namespace

float WoodTexture::featureSize() const { return 2.0f * std::numbers::pi_v<float> / 240.0f / planks_; }

Color WoodTexture::evalFootprint(const Eigen::Vector2f& uv, const TextureFootprint& f) const {
  const float fu = std::abs(f.duvdx.x()) + std::abs(f.duvdy.x());
  const float fw = (std::abs(f.duvdx.y()) + std::abs(f.duvdy.y())) * planks_;
  if (!std::isfinite(fu) || !std::isfinite(fw)) return shade(uv, 0, 0);
  return shade(uv, fu, fw);
}

Color WoodTexture::shade(const Eigen::Vector2f& uv, float fu, float fw) const {
  const float across = uv.y() * planks_;
  if (!(fw > 1e-6f)) return board(static_cast<long>(std::floor(across)), uv.x(), across, 0, fu);
  // The boards the box [across - fw/2, across + fw/2] spans, each over its own part of the box, by its share; beyond a
  // few boards their grain has averaged out, and each counts with its mean colour.
  const float a = across - 0.5f * fw, b = across + 0.5f * fw;
  const auto first = static_cast<long>(std::floor(a)), last = static_cast<long>(std::floor(b));
  if (last - first > kMaxBoards) return meanColor(a, b, uv.x(), fu);
  Color sum = Color::Zero();
  for (long p = first; p <= last; ++p) {
    const float lo = std::max(a, static_cast<float>(p)), hi = std::min(b, static_cast<float>(p + 1));
    if (hi > lo) sum += (hi - lo) * board(p, uv.x(), 0.5f * (lo + hi), hi - lo, fu);
  }
  return sum / fw;
}

Color WoodTexture::board(long plank, float u, float across, float fw, float fu) const {
  const float w = across - static_cast<float>(plank);  // position across the board, [0, 1]
  const float h1 = hash01(plank), h2 = hash01(plank + 7919), h3 = hash01(plank + 104729);
  // Boards are 2 UV units long, their ends staggered from row to row; joints are the dark bands between them.
  const float along = 0.5f * u + h1;
  const float side = bandCoverage(across, fw, 0.025f), end = bandCoverage(along, 0.5f * fu, 0.004f);
  const float joint = side + end - side * end;
  const Color joint_color = 0.35f * dark_;
  if (joint >= 1) return joint_color;
  // Grain: lines along the board, bent by slow waves so each board looks sawn from a different log.
  const float bend = 0.25f * fastSin(1.7f * u + 6.2832f * h2) + 0.06f * fastSin(7.3f * u + 3.0f * h3);
  const float phase = rings_ * (w + bend) + 10.0f * h3;
  // ring^5: late wood, a narrow dark band at the end of each ring. Box-filtered exactly over a box of phases as wide
  // (in the sense of its spread) as those the footprint spans: rings per board across, rings times the bend's slope
  // along.
  constexpr float kQuarter = 1.5707963f;  // cos(x) = sin(x + pi / 2)
  // The slopes along u matter only once the footprint's extent along u spans a visible part of a wave (far floor).
  const bool along_matters = fu > 1e-3f;  // below: under 0.007 of a ring and 0.03 radians of fibre
  const float slope = along_matters ? 0.25f * 1.7f * fastSin(1.7f * u + 6.2832f * h2 + kQuarter) +
                                          0.06f * 7.3f * fastSin(7.3f * u + 3.0f * h3 + kQuarter)
                                    : 0.0f;
  const float phase_width = rings_ * std::sqrt(fw * fw + slope * slope * fu * fu);
  float late;
  if (phase_width > 1e-4f) {
    late = boxedLateWood(phase, phase_width);
  } else {
    const float ring = phase - std::floor(phase), ring2 = ring * ring;
    late = ring2 * ring2 * ring;
  }
  // Fibre: 240 radians per board across, 13 * 2.3 cos(2.3 u + 5 h1) per unit along; a box damps a sine wave by the
  // sinc of each axis' phase width.
  // Once the box spans a whole fibre period across the board (fw >= 2 pi / 240, most of the far floor) the fibre
  // has faded to its mean and its waves are not evaluated.
  float fibre = 0.5f;
  if (const float across_amplitude = boxedSineAmplitude(240.0f * fw); across_amplitude > 0) {
    const float fibre_slope = along_matters ? 13.0f * 2.3f * fastSin(2.3f * u + 5.0f * h1 + kQuarter) : 0.0f;
    const float along_amplitude = boxedSineAmplitude(std::abs(fibre_slope) * fu);
    if (along_amplitude > 0)
      fibre += 0.5f * fastSin(240.0f * w + 13.0f * fastSin(2.3f * u + 5.0f * h1)) * across_amplitude * along_amplitude;
  }
  const float t = 0.8f * late + 0.1f * fibre;  // at most 0.9
  const float tone = 0.88f + 0.24f * h2;       // board-to-board colour variation, mean 1
  const Color wood = tone * (light_ + t * (dark_ - light_));
  return (1 - joint) * wood + joint * joint_color;
}

Color WoodTexture::meanColor(float a, float b, float u, float fu) const {
  // Mean grain: late wood 1/6, fibre 1/2; the side joints' share of [a, b] exactly; the end joints' share along u.
  const float t = 0.8f / 6.0f + 0.1f * 0.5f;
  const float side = bandCoverage(0.5f * (a + b), b - a, 0.025f);
  const float end = bandCoverage(0.5f * u, std::max(0.5f * fu, 1.0f), 0.004f);  // ends staggered: their mean share
  const float joint = side + end - side * end;
  const Color wood = boardTone(0.5f * (a + b), b - a) * (light_ + t * (dark_ - light_));
  return (1 - joint) * wood + joint * 0.35f * dark_;
}

}  // namespace wobble::render
