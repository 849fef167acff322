// Bsdf: the reflection model of a Material at one surface point (see material.h), in a shading frame, for one
// outgoing direction wo (towards the viewer), which is fixed at construction.
//   f(wo, wi) = (1 - coat F(n.wo)) base / pi  +  coat F(n.wo) D(h) G(wo, wi) / (4 |n.wo| |n.wi|)
// with D the GGX distribution, G Smith's separable shadowing term and F Schlick's Fresnel with F0 from the ior. The
// coat's Fresnel is taken at the macro normal, the same share the base loses, so the surface never reflects more
// than arrives (GGX with Smith shadowing reflects at most all of it); at the microfacet's angle, F(wi.h), the coat
// returned up to 0.13% more than the base gave up (tests/render/bsdf_test.cpp).
// Sampling picks the coat lobe (GGX half vectors drawn with density D(h) cos(h)) with a probability that grows with
// the Fresnel term, otherwise the cosine-weighted diffuse lobe; the pdf is the mixture of both, so the estimate is
// unbiased whichever lobe was picked. A surface without coat (coat = 0) is plain Lambertian and takes a short path.
// Directions point away from the surface, in world space.
#pragma once
#include <optional>

#include "render/material.h"
#include "render/sampling.h"

namespace wobble::render {

// f split by lobe: f = diffuse * base + specular (the coat is colourless). The denoiser filters the two parts apart,
// the diffuse one divided by the base colour, so texture detail is not blurred (path_tracer.h).
struct BsdfLobes {
  float diffuse = 0, specular = 0;
};

struct BsdfSample {
  Eigen::Vector3f wi;  // world space, unit
  Color weight;        // f(wo, wi) |n.wi| / pdf(wi)
  BsdfLobes lobes;     // the same weight by lobe: weight = lobes.diffuse * base + lobes.specular
  float pdf = 0;       // pdf(wi), for multiple importance sampling
};

class Bsdf {
 public:
  // n: unit shading normal on the side of wo.
  Bsdf(const Material& material, const Color& base, const Eigen::Vector3f& n, const Eigen::Vector3f& wo);

  Color eval(const Eigen::Vector3f& wi) const;  // f, without the cosine
  BsdfLobes evalLobes(const Eigen::Vector3f& wi) const;
  float pdf(const Eigen::Vector3f& wi) const;  // solid-angle density of sample()
  std::optional<BsdfSample> sample(float u_lobe, float u1, float u2) const;
  const Color& base() const { return base_; }

 private:
  float fresnel(float cos_theta) const;
  BsdfLobes evalLocal(const Eigen::Vector3f& wi) const;
  float pdfLocal(const Eigen::Vector3f& wi) const;

  Frame frame_;
  Color base_;
  Eigen::Vector3f wo_;  // local
  float coat_, f0_, alpha_;
  float coat_probability_ = 0;  // of sampling the coat lobe
  float diffuse_weight_ = 0;    // (1 - coat F(n.wo)) / pi
  float coat_fresnel_ = 0;      // coat F(n.wo)
};

}  // namespace wobble::render
