// The smooth and rough (GGX) dielectric interface, and Beer-Lambert absorption from a colour (see dielectric.h).
#include "render/dielectric.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/microfacet.h"
#include "render/path_tracer.h"

namespace wobble::render {

namespace {

// Fresnel at a microfacet with cosine c to wo (either side): eta is inside / outside, z outward.
float frDielectric(float c, float ior) { return c >= 0 ? fresnelDielectric(c, ior) : fresnelDielectric(-c, 1 / ior); }

// Refraction of w (pointing away) about the normal n: false at total internal reflection. eta: inside / outside.
bool refract(const Eigen::Vector3f& w, Eigen::Vector3f n, float eta, float& etap, Eigen::Vector3f& t) {
  float cos_i = n.dot(w);
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
    n = -n;
  }
  const float sin2_t = std::max(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return false;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  t = -w / eta + (cos_i / eta - cos_t) * n;
  etap = eta;
  return true;
}

}  // namespace

float fresnelDielectric(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return 1.0f;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  const float r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
}

Color absorptionFromColor(const Color& color, float depth) {
  return (-color.array().max(1e-6f).log() / depth).matrix();
}

DielectricBsdf::DielectricBsdf(float ior, float roughness, const Eigen::Vector3f& outward, const Eigen::Vector3f& wo)
    : frame_(outward), wo_(frame_.toLocal(wo)), ior_(ior), alpha_(roughness > 0 ? std::max(roughness, 1e-3f) : 0) {}

std::optional<DielectricSample> DielectricBsdf::sample(float u_lobe, float u1, float u2) const {
  if (wo_.z() == 0) return std::nullopt;
  if (smooth()) {
    const float eta = wo_.z() > 0 ? ior_ : 1 / ior_;
    const float f = fresnelDielectric(std::abs(wo_.z()), eta);
    DielectricSample s;
    if (u_lobe < f) {
      s.wi = frame_.toWorld(Eigen::Vector3f(-wo_.x(), -wo_.y(), wo_.z()));
    } else {
      float etap;
      Eigen::Vector3f t;
      if (!refract(wo_, Eigen::Vector3f::UnitZ(), ior_, etap, t)) return std::nullopt;  // f = 1 there: not reached
      s.wi = frame_.toWorld(t).normalized();
      s.transmitted = true;
    }
    return s;
  }
  // Microfacet normal with density D(m) cos(m): cos^2 = (1 - u) / (1 + (a^2 - 1) u).
  const float a2 = alpha_ * alpha_;
  const float cos2 = (1.0f - u1) / (1.0f + (a2 - 1.0f) * u1);
  const float cos_m = std::sqrt(cos2), sin_m = std::sqrt(std::max(0.0f, 1.0f - cos2));
  const Eigen::Vector2f phi = cosSin2Pi(u2);
  const Eigen::Vector3f m(sin_m * phi.x(), sin_m * phi.y(), cos_m);
  if (m.dot(wo_) * wo_.z() <= 0) return std::nullopt;  // a microfacet facing away from wo: f = 0 there
  const float r = frDielectric(wo_.dot(m), ior_);
  Eigen::Vector3f wi;
  DielectricSample s;
  if (u_lobe < r) {
    wi = 2.0f * wo_.dot(m) * m - wo_;
    if (wi.z() * wo_.z() <= 0) return std::nullopt;
  } else {
    float etap;
    if (!refract(wo_, m, ior_, etap, wi) || wi.z() * wo_.z() >= 0) return std::nullopt;
    s.transmitted = true;
  }
  wi.normalize();
  s.wi = frame_.toWorld(wi);
  s.pdf = pdf(s.wi);
  if (!(s.pdf > 0)) return std::nullopt;
  s.weight = eval(s.wi) * std::abs(wi.z()) / s.pdf;
  if (!std::isfinite(s.weight)) return std::nullopt;
  return s;
}

namespace {

// The microfacet normal between wo and wi (local, z outward), faced to +z, and the relative index etap of the
// transmission (1 for a reflection); false where none exists or it faces away from either direction.
bool halfVector(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi, float ior, Eigen::Vector3f& wm, float& etap) {
  const float cos_o = wo.z(), cos_i = wi.z();
  if (cos_o == 0 || cos_i == 0) return false;
  const bool reflect = cos_o * cos_i > 0;
  etap = reflect ? 1.0f : (cos_o > 0 ? ior : 1 / ior);
  wm = wi * etap + wo;
  if (wm.squaredNorm() == 0) return false;
  wm.normalize();
  if (wm.z() < 0) wm = -wm;
  return wm.z() > 0 && wm.dot(wi) * cos_i >= 0 && wm.dot(wo) * cos_o >= 0;
}

}  // namespace

float DielectricBsdf::eval(const Eigen::Vector3f& wi_world) const {
  if (smooth()) return 0;
  const Eigen::Vector3f wi = frame_.toLocal(wi_world);
  Eigen::Vector3f wm;
  float etap;
  if (!halfVector(wo_, wi, ior_, wm, etap)) return 0;
  const float a2 = alpha_ * alpha_;
  const float d = ggxD(wm.z(), a2), g = smithG1(wo_.z(), a2) * smithG1(wi.z(), a2);
  const float f = frDielectric(wo_.dot(wm), ior_);
  if (etap == 1) return d * g * f / std::abs(4.0f * wi.z() * wo_.z());
  const float denom = wi.dot(wm) + wo_.dot(wm) / etap;
  return d * (1 - f) * g * std::abs(wi.dot(wm) * wo_.dot(wm) / (wi.z() * wo_.z() * denom * denom));
}

float DielectricBsdf::pdf(const Eigen::Vector3f& wi_world) const {
  if (smooth()) return 0;
  const Eigen::Vector3f wi = frame_.toLocal(wi_world);
  Eigen::Vector3f wm;
  float etap;
  if (!halfVector(wo_, wi, ior_, wm, etap)) return 0;
  const float pdf_m = ggxD(wm.z(), alpha_ * alpha_) * wm.z();
  const float r = frDielectric(wo_.dot(wm), ior_);
  if (etap == 1) return pdf_m / (4.0f * std::abs(wo_.dot(wm))) * r;
  const float denom = wi.dot(wm) + wo_.dot(wm) / etap;
  return pdf_m * std::abs(wi.dot(wm)) / (denom * denom) * (1 - r);
}

InterfaceCrossing::InterfaceCrossing(const SurfaceHit& hit, const Eigen::Vector3f& direction)
    : wo(-direction),
      outward(hit.ng),
      n(hit.ns.dot(hit.ng) >= 0 ? hit.ns : Eigen::Vector3f(-hit.ns)),
      entering(hit.ng.dot(wo) > 0) {}

std::optional<Ray> InterfaceCrossing::leave(const SurfaceHit& hit, const DielectricSample& s) const {
  const bool outside = s.wi.dot(outward) > 0;
  if (s.transmitted == (outside == entering)) return std::nullopt;
  return Ray{offsetFromSurface(hit.p, outside ? outward : Eigen::Vector3f(-outward)), s.wi, 0,
             std::numeric_limits<float>::infinity(), hit.time};
}

}  // namespace wobble::render
