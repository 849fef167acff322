// Sky radiance and sun / area light sampling with shadow rays (see lights.h).
#include "render/lights.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "render/sampling.h"

namespace wobble::render {

Color Sky::eval(const Eigen::Vector3f& d) const {
  const float e = d.dot(up) / up.norm();
  // sqrt: a fast change near the horizon, as in a real clear sky, then a slow one towards the zenith.
  if (e >= 0) return horizon + std::sqrt(e) * (zenith - horizon);
  return horizon + std::sqrt(std::min(1.0f, -4.0f * e)) * (ground - horizon);
}

namespace {

// 1 - cos(radius) without the cancellation of 1 - cosf near 1 (the real sun's 0.27 degrees).
float oneMinusCos(float radius_deg) {
  const float s = std::sin(0.5f * radius_deg * std::numbers::pi_v<float> / 180.0f);
  return 2.0f * s * s;
}

float sunPdf(const SunLight& sun) {
  return 1.0f / (2.0f * std::numbers::pi_v<float> * oneMinusCos(sun.angular_radius_deg));
}

}  // namespace

SunCone::SunCone(const SunLight& light) : sun(&light), axis(light.direction.normalized()) {
  const Frame frame(axis);
  s = frame.s;
  t = frame.t;
  if (light.angular_radius_deg > 0) {
    cos_max = 1.0f - oneMinusCos(light.angular_radius_deg);
    pdf = sunPdf(light);
  }
}

LightSample sampleSun(const SunCone& cone, const Eigen::Vector3f& p, const Eigen::Vector3f& ng, float u1, float u2) {
  LightSample s;
  if (cone.pdf > 0) {
    const Eigen::Vector3f local = sampleUniformCone(u1, u2, cone.cos_max);
    s.wi = (local.x() * cone.s + local.y() * cone.t + local.z() * cone.axis).normalized();
  } else {
    s.wi = cone.axis;
  }
  if (s.wi.dot(ng) <= 0) return s;
  s.shadow.origin = p;
  s.shadow.direction = s.wi;
  // Uniform cone sampling of a disc of constant radiance: radiance / pdf = irradiance at normal incidence.
  s.value = cone.sun->irradiance;
  s.pdf = cone.pdf;
  return s;
}

LightSample sampleRect(const RectLight& light, const Eigen::Vector3f& p, const Eigen::Vector3f& ng, float u1,
                       float u2) {
  LightSample s;
  const Eigen::Vector3f area_normal = light.edge_u.cross(light.edge_v);
  const float area = area_normal.norm();
  const Eigen::Vector3f q = light.corner + u1 * light.edge_u + u2 * light.edge_v;
  const Eigen::Vector3f d = q - p;
  const float dist2 = d.squaredNorm();
  if (!(dist2 > 0) || !(area > 0)) return s;
  const float dist = std::sqrt(dist2);
  s.wi = d / dist;
  const float cos_light = -s.wi.dot(area_normal) / area;
  if (cos_light <= 0 || s.wi.dot(ng) <= 0) return s;
  s.shadow.origin = p;
  s.shadow.direction = s.wi;
  s.shadow.tfar = dist * (1.0f - 1e-4f);
  s.pdf = dist2 / (cos_light * area);  // area sampling: pdf = 1 / area, converted to solid angle
  s.value = light.radiance / s.pdf;
  return s;
}

LightHit sunInDirection(const SunCone& sun, const Eigen::Vector3f& d) {
  if (!(sun.pdf > 0) || d.dot(sun.axis) < sun.cos_max) return {};
  return {sun.sun->irradiance * sun.pdf, sun.pdf};
}

LightHit rectAlongRay(const RectLight& light, const Eigen::Vector3f& origin, const Eigen::Vector3f& d, float tmax) {
  const Eigen::Vector3f n = light.edge_u.cross(light.edge_v);
  const float denom = d.dot(n);
  if (!(denom < 0)) return {};  // parallel, or seen from behind: it emits on the side of n only
  const float t = (light.corner - origin).dot(n) / denom;
  if (!(t > 0 && t < tmax)) return {};
  const Eigen::Vector3f q = origin + t * d - light.corner;
  const float n2 = n.squaredNorm();
  const float s = q.cross(light.edge_v).dot(n) / n2, r = light.edge_u.cross(q).dot(n) / n2;
  if (s < 0 || s > 1 || r < 0 || r > 1) return {};
  const float cos_light = -denom / std::sqrt(n2);
  return {light.radiance, t * t / (cos_light * std::sqrt(n2))};
}

SkyDistribution::SkyDistribution(const Sky& sky) : up_(sky.up.normalized()) {
  const Frame frame(up_);
  a_ = frame.s;
  b_ = frame.t;
  cdf_[0] = 0;
  for (int i = 0; i < kBins; ++i) {
    const float z = -1.0f + 2.0f * (static_cast<float>(i) + 0.5f) / kBins;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    weight_[i] = std::max(0.0f, luminance(sky.eval(z * up_ + r * a_)));
    cdf_[i + 1] = cdf_[i] + weight_[i];
  }
  total_ = cdf_[kBins];
}

Eigen::Vector3f SkyDistribution::sample(float u1, float u2, float& pdf) const {
  const float target = u1 * total_;
  // The last bin whose cdf start is <= target, skipping empty bins (their start equals the next one's).
  const int bin = std::clamp(int(std::upper_bound(cdf_ + 1, cdf_ + kBins + 1, target) - (cdf_ + 1)), 0, kBins - 1);
  const float within = weight_[bin] > 0 ? std::clamp((target - cdf_[bin]) / weight_[bin], 0.0f, 1.0f) : 0.5f;
  const float z = std::clamp(-1.0f + 2.0f * (static_cast<float>(bin) + within) / kBins, -1.0f, 1.0f);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const Eigen::Vector2f phi = cosSin2Pi(u2);
  // Density in z is weight / total per bin of width 2 / kBins; dw = dz dphi.
  pdf = weight_[bin] / total_ * (kBins / 2.0f) / (2.0f * std::numbers::pi_v<float>);
  return z * up_ + r * (phi.x() * a_ + phi.y() * b_);
}

float SkyDistribution::pdf(const Eigen::Vector3f& d) const {
  if (empty()) return 0;
  const int bin = std::clamp(int((d.dot(up_) + 1.0f) * (kBins / 2.0f)), 0, kBins - 1);
  return weight_[bin] / total_ * (kBins / 2.0f) / (2.0f * std::numbers::pi_v<float>);
}

Background::Background(const Lights& lights)
    : sky_(lights.sky), sky_distribution_(lights.sky), environment_(lights.environment) {
  sky_.up.normalize();
}

Eigen::Vector3f Background::sample(float u1, float u2, float& pdf) const {
  return environment_ ? environment_->sample(u1, u2, pdf) : sky_distribution_.sample(u1, u2, pdf);
}

float Background::pdf(const Eigen::Vector3f& d) const {
  return environment_ ? environment_->pdf(d) : sky_distribution_.pdf(d);
}

void checkLights(const Lights& lights) {
  for (std::size_t i = 0; i < lights.suns.size(); ++i) {
    const SunLight& s = lights.suns[i];
    if (!s.direction.allFinite() || s.direction.norm() == 0 || !s.irradiance.allFinite() ||
        s.irradiance.minCoeff() < 0 || !(s.angular_radius_deg >= 0 && s.angular_radius_deg < 90))
      throw std::invalid_argument("sun " + std::to_string(i) +
                                  ": needs a non-zero direction, non-negative irradiance and a radius in [0, 90) deg");
  }
  for (std::size_t i = 0; i < lights.rects.size(); ++i) {
    const RectLight& r = lights.rects[i];
    if (!r.corner.allFinite() || !(r.edge_u.cross(r.edge_v).norm() > 0) || !r.radiance.allFinite() ||
        r.radiance.minCoeff() < 0)
      throw std::invalid_argument("area light " + std::to_string(i) +
                                  ": needs non-parallel edges and non-negative radiance");
  }
  const Sky& k = lights.sky;
  if (!k.zenith.allFinite() || !k.horizon.allFinite() || !k.ground.allFinite() || k.zenith.minCoeff() < 0 ||
      k.horizon.minCoeff() < 0 || k.ground.minCoeff() < 0 || !(k.up.norm() > 0))
    throw std::invalid_argument("sky: needs non-negative colours and a non-zero up vector");
}

}  // namespace wobble::render
