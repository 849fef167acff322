// Sky radiance and sun / area light sampling with shadow rays (see lights.h).
#include "lights.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "sampling.h"
#include "scene.h"

namespace wobble::render {

Color Sky::eval(const Eigen::Vector3f& d) const {
  const float e = d.dot(up.normalized());
  // sqrt: a fast change near the horizon, as in a real clear sky, then a slow one towards the zenith.
  if (e >= 0) return horizon + std::sqrt(e) * (zenith - horizon);
  return horizon + std::sqrt(std::min(1.0f, -4.0f * e)) * (ground - horizon);
}

LightSample sampleSun(const Scene& scene, const SunLight& sun, const Eigen::Vector3f& p, const Eigen::Vector3f& ng,
                      float u1, float u2) {
  LightSample s;
  const Eigen::Vector3f axis = sun.direction.normalized();
  if (sun.angular_radius_deg > 0) {
    const float cos_max = std::cos(sun.angular_radius_deg * std::numbers::pi_v<float> / 180.0f);
    s.wi = Frame(axis).toWorld(sampleUniformCone(u1, u2, cos_max)).normalized();
  } else {
    s.wi = axis;
  }
  if (s.wi.dot(ng) <= 0) return s;
  Ray shadow;
  shadow.origin = p;
  shadow.direction = s.wi;
  if (scene.occluded(shadow)) return s;
  // Uniform cone sampling of a disc of constant radiance: radiance / pdf = irradiance at normal incidence.
  s.value = sun.irradiance;
  return s;
}

LightSample sampleRect(const Scene& scene, const RectLight& light, const Eigen::Vector3f& p,
                       const Eigen::Vector3f& ng, float u1, float u2) {
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
  Ray shadow;
  shadow.origin = p;
  shadow.direction = s.wi;
  shadow.tfar = dist * (1.0f - 1e-4f);
  if (scene.occluded(shadow)) return s;
  s.value = light.radiance * (cos_light * area / dist2);  // area sampling: pdf = 1 / area, converted to solid angle
  return s;
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
