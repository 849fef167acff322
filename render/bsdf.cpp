// The diffuse-plus-coat BSDF: evaluation, mixture pdf and lobe sampling (see bsdf.h).
#include "render/bsdf.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "render/microfacet.h"

namespace wobble::render {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

}  // namespace

Bsdf::Bsdf(const Material& m, const Color& base, const Eigen::Vector3f& n, const Eigen::Vector3f& wo)
    : frame_(n), base_(base), wo_(frame_.toLocal(wo)), coat_(m.coat), alpha_(std::max(m.roughness, 1e-3f)) {
  const float r = (m.ior - 1.0f) / (m.ior + 1.0f);
  f0_ = r * r;
  if (wo_.z() > 0) {
    const float f = fresnel(wo_.z());
    // At least 1/4 of the samples go to the coat when there is one: the coat mirrors the sky even where Fresnel is
    // small, and that reflection is what reads as "glossy".
    coat_probability_ = coat_ > 0 ? std::clamp(0.25f + coat_ * f, 0.0f, 0.9f) : 0.0f;
    diffuse_weight_ = (1.0f - coat_ * f) / kPi;
    coat_fresnel_ = coat_ * f;
  }
}

float Bsdf::fresnel(float c) const {
  const float m = std::clamp(1.0f - c, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0_ + (1.0f - f0_) * m2 * m2 * m;
}

BsdfLobes Bsdf::evalLocal(const Eigen::Vector3f& wi) const {
  if (wo_.z() <= 0 || wi.z() <= 0) return {};
  BsdfLobes f{diffuse_weight_, 0.0f};
  if (coat_ > 0) {
    const Eigen::Vector3f h = (wo_ + wi).normalized();
    const float a2 = alpha_ * alpha_;
    f.specular =
        coat_fresnel_ * ggxD(h.z(), a2) * smithG1(wo_.z(), a2) * smithG1(wi.z(), a2) / (4.0f * wo_.z() * wi.z());
  }
  return f;
}

float Bsdf::pdfLocal(const Eigen::Vector3f& wi) const {
  if (wo_.z() <= 0 || wi.z() <= 0) return 0;
  float p = (1.0f - coat_probability_) * wi.z() / kPi;
  if (coat_probability_ > 0) {
    const Eigen::Vector3f h = (wo_ + wi).normalized();
    p += coat_probability_ * ggxD(h.z(), alpha_ * alpha_) * h.z() / (4.0f * wo_.dot(h));
  }
  return p;
}

BsdfLobes Bsdf::evalLobes(const Eigen::Vector3f& wi) const { return evalLocal(frame_.toLocal(wi)); }

Color Bsdf::eval(const Eigen::Vector3f& wi) const {
  const BsdfLobes f = evalLobes(wi);
  return (f.diffuse * base_).array() + f.specular;
}

float Bsdf::pdf(const Eigen::Vector3f& wi) const { return pdfLocal(frame_.toLocal(wi)); }

std::optional<BsdfSample> Bsdf::sample(float u_lobe, float u1, float u2) const {
  if (wo_.z() <= 0) return std::nullopt;
  Eigen::Vector3f wi;
  if (u_lobe < coat_probability_) {
    // GGX half vector with density D(h) cos(h): cos^2 = (1 - u) / (1 + (a^2 - 1) u).
    const float a2 = alpha_ * alpha_;
    const float cos2 = (1.0f - u1) / (1.0f + (a2 - 1.0f) * u1);
    const float cos_h = std::sqrt(cos2), sin_h = std::sqrt(std::max(0.0f, 1.0f - cos2));
    const Eigen::Vector2f phi = cosSin2Pi(u2);
    const Eigen::Vector3f h(sin_h * phi.x(), sin_h * phi.y(), cos_h);
    wi = 2.0f * wo_.dot(h) * h - wo_;
  } else {
    wi = sampleCosineHemisphere(u1, u2);
  }
  if (wi.z() <= 0) return std::nullopt;
  wi.normalize();
  const Eigen::Vector3f wi_world = frame_.toWorld(wi);
  if (coat_ == 0) {  // Lambertian: f cos / pdf = base exactly
    const float p = wi.z() / kPi;
    if (!(p > 0)) return std::nullopt;
    return BsdfSample{wi_world, base_ * (diffuse_weight_ * kPi), {diffuse_weight_ * kPi, 0.0f}, p};
  }
  const float p = pdfLocal(wi);
  if (!(p > 0)) return std::nullopt;
  const BsdfLobes f = evalLocal(wi);
  const BsdfLobes w{f.diffuse * wi.z() / p, f.specular * wi.z() / p};
  return BsdfSample{wi_world, (w.diffuse * base_).array() + w.specular, w, p};
}

}  // namespace wobble::render
