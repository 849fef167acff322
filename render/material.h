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
// Every surface is shaded two-sided (the normal is turned towards the viewer), so a cloth shows the same material on
// both sides and a closed jelly's inside is never seen anyway.
#pragma once
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

  Color baseColor(const Eigen::Vector2f& uv) const {
    return texture ? Color(color.cwiseProduct(texture->eval(uv))) : color;
  }
  // Averaged over a pixel's footprint (texture.h).
  Color baseColor(const Eigen::Vector2f& uv, const TextureFootprint& footprint) const {
    return texture ? Color(color.cwiseProduct(texture->evalFootprint(uv, footprint))) : color;
  }

  static Material diffuse(std::string name, const Color& color) { return {std::move(name), color, nullptr}; }
  static Material textured(std::string name, std::shared_ptr<const Texture> texture) {
    return {std::move(name), Color::Ones(), std::move(texture)};
  }
  // Glossy gelatine: the texture (or tint) shows through a clear coat with sharp highlights.
  static Material jelly(std::string name, const Color& tint, std::shared_ptr<const Texture> texture = nullptr) {
    return {std::move(name), tint, std::move(texture), 1.0f, 1.4f, 0.06f};
  }
};

// Throws std::invalid_argument naming the material when a parameter is out of range.
void checkMaterial(const Material& m);

}  // namespace wobble::render
