// Lights: what illuminates the scene. At every shading point each sun and area light is sampled explicitly
// (next-event estimation) and the path continues in a BSDF-sampled direction that may find the same light again; the
// two estimates are combined by multiple importance sampling (power heuristic, path_tracer.h), so no light is counted
// twice and each is found by whichever strategy suits it (the sun's disc by light sampling on a matte floor, by BSDF
// sampling in a sharp glossy highlight). Camera rays do not see suns or area lights, only the sky.
//
//   SunLight   direction (towards the sun, any length), irradiance (linear RGB W/m^2 on a surface facing the sun),
//              angular_radius_deg (the sun's apparent radius; the real sun is 0.27; larger gives softer shadows,
//              0 gives hard ones)
//   RectLight  a one-sided rectangular area light: corner, edge_u, edge_v (the rectangle is corner + s edge_u +
//              t edge_v for s, t in [0, 1]; it emits on the side of edge_u x edge_v), radiance (linear RGB)
//   Sky        environment radiance by elevation: zenith straight up, horizon at the horizon, ground below it
//              (smoothly blended); up is the world's up axis. Black everywhere turns the sky off.
//              SkyDistribution samples its directions in proportion to luminance (a table over elevation, uniform in
//              azimuth), for next-event estimation of the sky.
//   environment an equirectangular image of the light from every direction (environment.h); when set it replaces
//              the sky as the Background that rays leaving the scene find and that next-event estimation samples.
#pragma once
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "render/color.h"
#include "render/environment.h"
#include "render/ray.h"

namespace wobble::render {

struct SunLight {
  Eigen::Vector3f direction{0.4f, 1.0f, 0.3f};
  Color irradiance{3.0f, 2.9f, 2.7f};
  float angular_radius_deg = 2.0f;
};

struct RectLight {
  Eigen::Vector3f corner{-1, 5, -1}, edge_u{0, 0, 2}, edge_v{2, 0, 0};
  Color radiance{5, 5, 5};
};

struct Sky {
  Color zenith{0.30f, 0.50f, 0.95f};
  Color horizon{0.85f, 0.90f, 1.00f};
  Color ground{0.25f, 0.23f, 0.20f};
  Eigen::Vector3f up{0, 1, 0};

  Color eval(const Eigen::Vector3f& direction) const;
  static Sky black() { return {Color::Zero(), Color::Zero(), Color::Zero()}; }
};

struct Lights {
  std::vector<SunLight> suns;
  std::vector<RectLight> rects;
  Sky sky;
  std::shared_ptr<const EnvironmentMap> environment;  // none: the sky
};

// One light sample seen from point p (already offset off its surface) whose face-forwarded geometric normal is ng.
// value = incident radiance / pdf (solid angle) if nothing blocks shadow: the receiver traces shadow (the path
// tracer's unoccluded, as pbrt's Unoccluded) and multiplies by its BSDF and its own cosine. value is zero when the
// light is below the surface or behind; then no shadow ray is needed. pdf is the solid-angle density of wi (for the
// MIS weight); 0 for a sun of radius 0, which BSDF sampling can never hit.
struct LightSample {
  Eigen::Vector3f wi = Eigen::Vector3f::UnitY();  // unit, towards the light
  Color value = Color::Zero();
  float pdf = 0;
  Ray shadow;  // from p towards the light, ending just before it
};

// A sun prepared for sampling: its unit axis, frame and cone, computed once per frame instead of per sample.
struct SunCone {
  explicit SunCone(const SunLight& sun);
  const SunLight* sun;
  Eigen::Vector3f axis, s, t;  // orthonormal
  float cos_max = 1, pdf = 0;  // pdf 0: a point sun (radius 0)
};

LightSample sampleSun(const SunCone& cone, const Eigen::Vector3f& p, const Eigen::Vector3f& ng, float u1, float u2);
inline LightSample sampleSun(const SunLight& sun, const Eigen::Vector3f& p, const Eigen::Vector3f& ng, float u1,
                             float u2) {
  return sampleSun(SunCone(sun), p, ng, u1, u2);
}
LightSample sampleRect(const RectLight& light, const Eigen::Vector3f& p, const Eigen::Vector3f& ng, float u1, float u2);

// What a ray leaving a surface in direction d finds of a light (no visibility test: the caller traces the ray).
// radiance is zero, and pdf (the light-sampling density of d, solid angle) 0, when it misses the light.
struct LightHit {
  Color radiance = Color::Zero();
  float pdf = 0;
};
// A sun of radius > 0 is a disc of constant radiance irradiance / (2 pi (1 - cos radius)), uniform-cone sampled.
LightHit sunInDirection(const SunCone& sun, const Eigen::Vector3f& d);
// The rectangle's front face, hit at a distance below tmax along (origin, d).
LightHit rectAlongRay(const RectLight& light, const Eigen::Vector3f& origin, const Eigen::Vector3f& d, float tmax);

// Directions drawn in proportion to the sky's luminance: a piecewise-constant density over elevation (kBins bins
// of sin(elevation) = d.up, each of equal solid angle), uniform in azimuth.
class SkyDistribution {
 public:
  static constexpr int kBins = 128;
  explicit SkyDistribution(const Sky& sky);

  bool empty() const { return total_ <= 0; }  // a black sky: nothing to sample
  // Direction for (u1, u2) in [0, 1)^2 and its solid-angle density.
  Eigen::Vector3f sample(float u1, float u2, float& pdf) const;
  float pdf(const Eigen::Vector3f& d) const;

 private:
  Eigen::Vector3f up_, a_, b_;  // orthonormal, up_ along the sky's up
  float total_ = 0;
  float weight_[kBins];  // luminance per bin
  float cdf_[kBins + 1];
};

// What a ray leaving the scene finds, and its sampling for next-event estimation: the environment map when the
// lights have one, else the sky. The path tracer asks this alone, never which of the two it is.
class Background {
 public:
  explicit Background(const Lights& lights);

  Color eval(const Eigen::Vector3f& d) const { return environment_ ? environment_->eval(d) : sky_.eval(d); }
  bool empty() const { return environment_ ? environment_->empty() : sky_distribution_.empty(); }
  // A unit direction for (u1, u2) in [0, 1)^2 drawn in proportion to luminance, and its solid-angle density.
  Eigen::Vector3f sample(float u1, float u2, float& pdf) const;
  float pdf(const Eigen::Vector3f& d) const;

 private:
  Sky sky_;  // with a unit up vector
  SkyDistribution sky_distribution_;
  std::shared_ptr<const EnvironmentMap> environment_;
};

// Throws std::invalid_argument on a zero direction, negative power or degenerate rectangle.
void checkLights(const Lights& lights);

}  // namespace wobble::render
