// Material: what a surface looks like. One model covers every surface in wobble's scenes:
//   a Lambertian base whose colour is `color` times the texture (if any), under an optional clear dielectric coat
//   (GGX microfacet reflection weighted by Schlick's Fresnel) that gives the glossy "jelly" look. Light reflected
//   by the coat is taken from the base, so the surface never reflects more than arrives.
//
// Parameters:
//   name        for error messages
//   color       linear RGB multiplier of the base (the whole base colour when there is no texture), in [0, 1]
//   texture     optional base colour texture (linear RGB), looked up with the surface's UV
//   coat        coat weight in [0, 1]; 0 = plain diffuse (colliders), 1 = full coat (jelly)
//   ior         coat index of refraction (> 1); 1.33 water, 1.4 gelatine, 1.5 glass
//   roughness   coat GGX alpha (> 0); 0.02 is a near mirror, 0.3 a satin sheen
// Gelatine (dielectric = true; render/dielectric.h): a clear body light enters, is tinted in and leaves.
//   ior             index of refraction inside / outside, in (1, 4]; 1.33 water, 1.4 gelatine
//   roughness       GGX alpha of the interface in [0, 1]; 0 = smooth (a perfect mirror and refraction)
//   absorption      sigma_a per channel (1/m, >= 0): Beer-Lambert transmittance exp(-sigma_a d) inside
//   scatter         scattering coefficient sigma_s (1/m, >= 0; 0 = clear): a random walk through the body
//   scatter_albedo  the throughput kept at each scattering event, per channel, in [0, 1]
//   print           coverage in [0, 1] of a thin diffuse printed layer on the surface, coloured color x texture
//                   (the cat skin): a hit shows the print with this probability, else the clear interface (a mix)
// A gelatine material needs a closed surface (the inside is where a ray has entered and not yet left).
// Every surface is shaded two-sided (the normal is turned towards the viewer), so a cloth shows the same material on
// both sides and a closed jelly's inside is never seen anyway.
#pragma once
#include <cmath>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "render/color.h"
#include "render/texture.h"

namespace wobble::render {

struct Material {
  std::string name;
  Color color{0.8f, 0.8f, 0.8f};
  std::shared_ptr<const Texture> texture;
  float coat = 0;
  float ior = 1.5f;
  float roughness = 0.1f;
  bool dielectric = false;
  Color absorption = Color::Zero();
  float scatter = 0;
  Color scatter_albedo = Color::Ones();
  float print = 0;

  Color baseColor(const Eigen::Vector2f& uv) const {
    return texture ? Color(color.cwiseProduct(texture->eval(uv))) : color;
  }
  // Averaged over a pixel's footprint (texture.h).
  Color baseColor(const Eigen::Vector2f& uv, const TextureFootprint& footprint) const {
    return texture ? Color(color.cwiseProduct(texture->evalFootprint(uv, footprint))) : color;
  }
  // Inside the body: Beer-Lambert transmittance over a distance t, and the distance to the next scattering event
  // for a uniform u in [0, 1) (draw u only where scatter > 0).
  Color transmittance(float t) const { return (-absorption * t).array().exp().matrix(); }
  float freeFlight(float u) const { return -std::log1p(-u) / scatter; }

  static Material diffuse(std::string name, const Color& color) { return {std::move(name), color, nullptr}; }
  static Material textured(std::string name, std::shared_ptr<const Texture> texture) {
    return {std::move(name), Color::Ones(), std::move(texture)};
  }
  // Glossy gelatine: the texture (or tint) shows through a clear coat with sharp highlights.
  static Material jelly(std::string name, const Color& tint, std::shared_ptr<const Texture> texture = nullptr) {
    return {std::move(name), tint, std::move(texture), 1.0f, 1.4f, 0.06f};
  }
  // Clear gelatine with a printed skin: color and texture colour the print only; absorption tints the inside.
  static Material gelatine(std::string name, float ior, float roughness, const Color& absorption,
                           std::shared_ptr<const Texture> texture = nullptr, float print = 0) {
    Material m{std::move(name), Color::Ones(), std::move(texture), 0.0f, ior, roughness};
    m.dielectric = true;
    m.absorption = absorption;
    m.print = print;
    return m;
  }
};

// Throws std::invalid_argument naming the material when a parameter is out of range.
void checkMaterial(const Material& m);

}  // namespace wobble::render
