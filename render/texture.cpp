// Procedural textures: checker and plank-floor wood (see texture.h).
#include "texture.h"

#include <cmath>
#include <cstdint>

namespace wobble::render {

Color CheckerTexture::eval(const Eigen::Vector2f& uv) const {
  const auto i = static_cast<long>(std::floor(uv.x() * squares_));
  const auto j = static_cast<long>(std::floor(uv.y() * squares_));
  return ((i + j) & 1) == 0 ? a_ : b_;
}

namespace {

// A pseudo-random value in [0, 1) for an integer (per-plank variation; any good integer hash will do).
float hash01(long k) {
  auto x = static_cast<std::uint32_t>(k * 0x9E3779B1u + 0x7F4A7C15u);
  x ^= x >> 16, x *= 0x85EBCA6Bu, x ^= x >> 13, x *= 0xC2B2AE35u, x ^= x >> 16;
  return static_cast<float>(x >> 8) * 0x1p-24f;
}

}  // namespace

Color WoodTexture::eval(const Eigen::Vector2f& uv) const {
  const float u = uv.x(), across = uv.y() * planks_;
  const auto plank = static_cast<long>(std::floor(across));
  const float w = across - static_cast<float>(plank);  // position across the board, [0, 1)
  const float h1 = hash01(plank), h2 = hash01(plank + 7919), h3 = hash01(plank + 104729);
  // Boards are 2 UV units long, their ends staggered from row to row.
  const float along = 0.5f * u + h1;
  const float end = along - std::floor(along);
  if (w < 0.025f || w > 0.975f || end < 0.004f || end > 0.996f) return 0.35f * dark_;  // joints
  // Grain: lines along the board, bent by slow waves so each board looks sawn from a different log.
  const float bend = 0.25f * std::sin(1.7f * u + 6.2832f * h2) + 0.06f * std::sin(7.3f * u + 3.0f * h3);
  const float phase = rings_ * (w + bend) + 10.0f * h3;
  const float ring = phase - std::floor(phase);
  const float late = std::pow(ring, 5.0f);  // late wood: a narrow dark band at the end of each ring
  const float fibre = 0.5f + 0.5f * std::sin(240.0f * w + 13.0f * std::sin(2.3f * u + 5.0f * h1));
  const float t = std::min(1.0f, 0.8f * late + 0.1f * fibre);
  const float tone = 0.88f + 0.24f * h2;  // board-to-board colour variation
  return (tone * (light_ + t * (dark_ - light_))).cwiseMin(1.0f);
}

}  // namespace wobble::render
