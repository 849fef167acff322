// Lights: what illuminates the scene. Lights are sampled explicitly at every shading point (next-event estimation)
// and are invisible to rays; rays that escape the scene see only the sky. So no light is ever counted twice.
//
//   SunLight   direction (towards the sun, any length), irradiance (linear RGB W/m^2 on a surface facing the sun),
//              angular_radius_deg (the sun's apparent radius; the real sun is 0.27; larger gives softer shadows,
//              0 gives hard ones)
//   RectLight  a one-sided rectangular area light: corner, edge_u, edge_v (the rectangle is corner + s edge_u +
//              t edge_v for s, t in [0, 1]; it emits on the side of edge_u x edge_v), radiance (linear RGB)
//   Sky        environment radiance by elevation: zenith straight up, horizon at the horizon, ground below it
//              (smoothly blended); up is the world's up axis. Black everywhere turns the sky off.
#pragma once
#include <vector>

#include <Eigen/Core>

#include "color.h"

namespace wobble::render {

class Scene;

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
};

// One light sample seen from point p (already offset off its surface) whose face-forwarded geometric normal is ng.
// value = incident radiance * cos(at the light) / pdf, with visibility included: the receiver multiplies by its
// BSDF and its own cosine. value is zero when the light is below the surface, behind, or occluded.
struct LightSample {
  Eigen::Vector3f wi = Eigen::Vector3f::UnitY();  // unit, towards the light
  Color value = Color::Zero();
};

LightSample sampleSun(const Scene& scene, const SunLight& sun, const Eigen::Vector3f& p, const Eigen::Vector3f& ng,
                      float u1, float u2);
LightSample sampleRect(const Scene& scene, const RectLight& light, const Eigen::Vector3f& p,
                       const Eigen::Vector3f& ng, float u1, float u2);

// Throws std::invalid_argument on a zero direction, negative power or degenerate rectangle.
void checkLights(const Lights& lights);

}  // namespace wobble::render
