// Dielectric: the refracting interface and the medium inside a gelatine body (material.h, Material::dielectric).
//
// Interface. Smooth (roughness 0): a perfect mirror and a perfect refraction, chosen with the exact unpolarised
// Fresnel reflectance of a dielectric (Born and Wolf; fresnelDielectric below) as probability, so each sample's
// weight is exactly 1 and no energy is gained or lost. Rough (roughness > 0): the GGX microfacet BSDF of a rough
// dielectric (Walter, Marschner, Li and Torrance 2007, "Microfacet Models for Refraction through Rough Surfaces"),
// reflection and transmission, with Smith's separable shadowing; microfacet normals are drawn with density
// D(m) |m.n| (Walter's eq. 37 sampling) and the lobe by the Fresnel term at the microfacet. Its f, pdf and sample
// follow pbrt-v4's DielectricBxDF. The n^2 scaling of radiance as it crosses the boundary is left out: it cancels on
// leaving a closed body, and keeping both sides at their own scale keeps the white furnace at 1.
//
// Medium. Inside a body light is absorbed by distance (Beer-Lambert: transmittance exp(-sigma_a d), with sigma_a
// from the colour white light takes through a stated depth) and, when `scatter` > 0, scattered: free paths are drawn
// exponentially with the scattering coefficient, and at each collision the path turns to a uniformly random
// direction (an isotropic phase function) with its throughput times the scattering albedo: a random walk through a
// homogeneous medium (pbrt-v4's "analog" tracking for a grey scattering coefficient, absorption applied as a weight).
//
// Directions point away from the surface. The frame's normal is the body's outward normal.
#pragma once
#include <optional>

#include <Eigen/Core>

#include "render/color.h"
#include "render/hit.h"
#include "render/ray.h"
#include "render/sampling.h"

namespace wobble::render {

// Fresnel reflectance of unpolarised light at an interface with relative index eta = n_transmitted / n_incident,
// for an incident direction with cosine cos_i (>= 0) to the normal on its side. 1 beyond the critical angle.
float fresnelDielectric(float cos_i, float eta);

// sigma_a (1/m) such that white light keeps `color` after `depth` metres: -ln(color) / depth, per channel.
Color absorptionFromColor(const Color& color, float depth);

struct DielectricSample {
  Eigen::Vector3f wi;  // world, unit
  float weight = 1;    // f |n.wi| / pdf (colourless)
  float pdf = 0;       // solid angle; 0 for a smooth interface (a delta: no light sample can find it)
  bool transmitted = false;
};

class DielectricBsdf {
 public:
  // outward: the body's unit outward normal at the point; wo: towards where the path came from; ior: inside / outside.
  DielectricBsdf(float ior, float roughness, const Eigen::Vector3f& outward, const Eigen::Vector3f& wo);

  bool smooth() const { return alpha_ == 0; }
  std::optional<DielectricSample> sample(float u_lobe, float u1, float u2) const;
  float eval(const Eigen::Vector3f& wi) const;  // f, no cosine (0 when smooth)
  float pdf(const Eigen::Vector3f& wi) const;   // solid angle (0 when smooth)

 private:
  Frame frame_;
  Eigen::Vector3f wo_;  // local; z along the outward normal
  float ior_, alpha_;
};

// A ray crossing a body's interface at a hit, as the path tracer (Path::crossInterface) and the caustic photons
// (tracePhoton) both cross it: the frame its BSDF is built in, and the ray a sampled direction leaves along.
struct InterfaceCrossing {
  InterfaceCrossing(const SurfaceHit& hit, const Eigen::Vector3f& direction);
  DielectricBsdf bsdf(float ior, float roughness) const { return DielectricBsdf(ior, roughness, n, wo); }
  // The ray along a sampled direction, from just off the side it leaves by, at the hit's time; none when the shading
  // normal sent the sample to the wrong side (a transmission staying on the ray's side, or a reflection crossing).
  std::optional<Ray> leave(const SurfaceHit& hit, const DielectricSample& s) const;

  Eigen::Vector3f wo;       // towards where the ray came from
  Eigen::Vector3f outward;  // the body's outward geometric normal
  Eigen::Vector3f n;        // the shading normal, turned to the outward side
  bool entering;            // the ray arrives from outside
};

}  // namespace wobble::render
