// The diffuse-plus-coat BSDF: evaluation, mixture pdf and lobe sampling (see bsdf.h).
#include "bsdf.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wobble::render {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

float ggxD(float cos_h, float a2) {
  const float d = cos_h * cos_h * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

float smithG1(float cos_v, float a2) {
  return 2.0f * cos_v / (cos_v + std::sqrt(a2 + (1.0f - a2) * cos_v * cos_v));
}

}  // namespace

Bsdf::Bsdf(const Material& m, const Color& base, const Eigen::Vector3f& n)
    : frame_(n), base_(base), coat_(m.coat), alpha_(std::max(m.roughness, 1e-3f)) {
  const float r = (m.ior - 1.0f) / (m.ior + 1.0f);
  f0_ = r * r;
}

float Bsdf::fresnel(float c) const {
  const float m = std::clamp(1.0f - c, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0_ + (1.0f - f0_) * m2 * m2 * m;
}

float Bsdf::coatProbability(float cos_o) const {
  // At least 1/4 of the samples go to the coat when there is one: the coat mirrors the sky even where Fresnel is
  // small, and that reflection is what reads as "glossy".
  return coat_ > 0 ? std::clamp(0.25f + coat_ * fresnel(cos_o), 0.0f, 0.9f) : 0.0f;
}

BsdfLobes Bsdf::evalLobes(const Eigen::Vector3f& wo_w, const Eigen::Vector3f& wi_w) const {
  const Eigen::Vector3f wo = frame_.toLocal(wo_w), wi = frame_.toLocal(wi_w);
  if (wo.z() <= 0 || wi.z() <= 0) return {};
  BsdfLobes f{(1.0f - coat_ * fresnel(wo.z())) / kPi, 0.0f};
  if (coat_ > 0) {
    const Eigen::Vector3f h = (wo + wi).normalized();
    const float a2 = alpha_ * alpha_;
    f.specular = coat_ * fresnel(wi.dot(h)) * ggxD(h.z(), a2) * smithG1(wo.z(), a2) * smithG1(wi.z(), a2) /
                 (4.0f * wo.z() * wi.z());
  }
  return f;
}

Color Bsdf::eval(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi) const {
  const BsdfLobes f = evalLobes(wo, wi);
  return (f.diffuse * base_).array() + f.specular;
}

float Bsdf::pdf(const Eigen::Vector3f& wo_w, const Eigen::Vector3f& wi_w) const {
  const Eigen::Vector3f wo = frame_.toLocal(wo_w), wi = frame_.toLocal(wi_w);
  if (wo.z() <= 0 || wi.z() <= 0) return 0;
  const float pc = coatProbability(wo.z());
  float p = (1.0f - pc) * wi.z() / kPi;
  if (pc > 0) {
    const Eigen::Vector3f h = (wo + wi).normalized();
    p += pc * ggxD(h.z(), alpha_ * alpha_) * h.z() / (4.0f * wo.dot(h));
  }
  return p;
}

std::optional<BsdfSample> Bsdf::sample(const Eigen::Vector3f& wo_w, float u_lobe, float u1, float u2) const {
  const Eigen::Vector3f wo = frame_.toLocal(wo_w);
  if (wo.z() <= 0) return std::nullopt;
  Eigen::Vector3f wi;
  if (u_lobe < coatProbability(wo.z())) {
    // GGX half vector with density D(h) cos(h): cos^2 = (1 - u) / (1 + (a^2 - 1) u).
    const float a2 = alpha_ * alpha_;
    const float cos2 = (1.0f - u1) / (1.0f + (a2 - 1.0f) * u1);
    const float cos_h = std::sqrt(cos2), sin_h = std::sqrt(std::max(0.0f, 1.0f - cos2));
    const float phi = 2.0f * kPi * u2;
    const Eigen::Vector3f h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
    wi = 2.0f * wo.dot(h) * h - wo;
  } else {
    wi = sampleCosineHemisphere(u1, u2);
  }
  if (wi.z() <= 0) return std::nullopt;
  const Eigen::Vector3f wi_w = frame_.toWorld(wi).normalized();
  const float p = pdf(wo_w, wi_w);
  if (!(p > 0)) return std::nullopt;
  const BsdfLobes f = evalLobes(wo_w, wi_w);
  const BsdfLobes w{f.diffuse * wi.z() / p, f.specular * wi.z() / p};
  return BsdfSample{wi_w, (w.diffuse * base_).array() + w.specular, w, p};
}

}  // namespace wobble::render
