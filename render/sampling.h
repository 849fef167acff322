// Sampling helpers: an orthonormal frame around a normal, and warps from the unit square to directions.
// Directions are returned in the local frame (z = the frame's normal) unless said otherwise.
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Core>

namespace wobble::render {

// Orthonormal basis (s, t, n) around a unit normal n (Duff et al. 2017, branchless and continuous enough).
struct Frame {
  Eigen::Vector3f s, t, n;

  explicit Frame(const Eigen::Vector3f& normal) : n(normal) {
    const float sign = std::copysign(1.0f, n.z());
    const float a = -1.0f / (sign + n.z());
    const float b = n.x() * n.y() * a;
    s = Eigen::Vector3f(1.0f + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
    t = Eigen::Vector3f(b, sign + n.y() * n.y() * a, -n.y());
  }
  Eigen::Vector3f toWorld(const Eigen::Vector3f& v) const { return v.x() * s + v.y() * t + v.z() * n; }
  Eigen::Vector3f toLocal(const Eigen::Vector3f& v) const { return {v.dot(s), v.dot(t), v.dot(n)}; }
};

// (cos, sin) of 2 pi u for u in [0, 1) (any finite u works), to within 3e-7: the quarter turn nearest u is taken
// exactly, the rest (at most an eighth of a turn) by Taylor polynomials. The samplers call it once per sample, where
// libm's sincosf is a noticeable share of a frame's render time.
inline Eigen::Vector2f cosSin2Pi(float u) {
  const float quarter = std::nearbyint(4.0f * u);  // the nearest quarter turn (round half to even)
  const float x = 2.0f * std::numbers::pi_v<float> * (u - 0.25f * quarter), x2 = x * x;  // |x| <= pi / 4
  const float s = x * (1.0f - x2 / 6.0f * (1.0f - x2 / 20.0f * (1.0f - x2 / 42.0f * (1.0f - x2 / 72.0f))));
  const float c = 1.0f - x2 / 2.0f * (1.0f - x2 / 12.0f * (1.0f - x2 / 30.0f * (1.0f - x2 / 56.0f)));
  switch (static_cast<int>(quarter) & 3) {  // rotate (c, s) by that many quarter turns
    case 0:
      return {c, s};
    case 1:
      return {-s, c};
    case 2:
      return {-c, -s};
    default:
      return {s, -c};
  }
}

// Cosine-weighted hemisphere (Malley's method); pdf = cos(theta) / pi.
inline Eigen::Vector3f sampleCosineHemisphere(float u1, float u2) {
  const float r = std::sqrt(u1);
  const Eigen::Vector2f phi = cosSin2Pi(u2);
  return {r * phi.x(), r * phi.y(), std::sqrt(std::max(0.0f, 1.0f - u1))};
}

// Uniform over the cone of directions within acos(cos_max) of +z; pdf = 1 / (2 pi (1 - cos_max)).
inline Eigen::Vector3f sampleUniformCone(float u1, float u2, float cos_max) {
  const float cos_theta = 1.0f - u1 * (1.0f - cos_max);
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  const Eigen::Vector2f phi = cosSin2Pi(u2);
  return {sin_theta * phi.x(), sin_theta * phi.y(), cos_theta};
}

}  // namespace wobble::render
