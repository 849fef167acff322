// The body materials (material_kinds.h): glossy jelly, matte diffuse and clear gelatine (render/dielectric.h).
#include "app/scene/material_kinds.h"

#include <array>

#include "app/scene/kind_table.h"
#include "app/scene/table_reader.h"
#include "render/dielectric.h"

namespace wobble {
namespace {

image::Color toColor(const Vec3& c) { return c.cast<float>(); }

render::Material makeJelly(const std::string& name, const BodyLook& look,
                           std::shared_ptr<const render::Texture> texture) {
  return render::Material::jelly(name, toColor(look.color), std::move(texture));
}

render::Material makeDiffuse(const std::string& name, const BodyLook& look,
                             std::shared_ptr<const render::Texture> texture) {
  return render::Material{name, toColor(look.color), std::move(texture)};
}

// Gelatine's keys: the interface (ior, roughness), the colour white light takes through a depth (Beer-Lambert),
// optional scattering (mean free path and albedo) and the print layer's coverage (the texture, times `color`).
void readGelatine(TableReader& r, BodyLook& look) {
  GelatineLook& g = look.gelatine;
  g.ior = r.number("ior", g.ior, Range{1, 4, true, false});
  g.roughness = r.number("roughness", g.roughness, Range::unit());
  g.absorption_color = r.vec3("absorption_color", g.absorption_color);
  if ((g.absorption_color.array() <= 0).any() || (g.absorption_color.array() > 1).any())
    r.fail("absorption_color", "each component must be in (0, 1] (linear RGB; 1 absorbs nothing)");
  g.absorption_depth = r.number("absorption_depth", g.absorption_depth, Range::positive());
  g.scatter = r.number("scatter", g.scatter, Range::nonNegative());
  g.scatter_albedo = r.vec3("scatter_albedo", g.scatter_albedo);
  if ((g.scatter_albedo.array() < 0).any() || (g.scatter_albedo.array() > 1).any())
    r.fail("scatter_albedo", "each component must be in [0, 1] (linear RGB)");
  g.print = r.number("print", look.textured ? g.print : 0.0, Range::unit());
}

render::Material makeGelatine(const std::string& name, const BodyLook& look,
                              std::shared_ptr<const render::Texture> texture) {
  const GelatineLook& g = look.gelatine;
  render::Material m =
      render::Material::gelatine(name, float(g.ior), float(g.roughness),
                                 render::absorptionFromColor(toColor(g.absorption_color), float(g.absorption_depth)),
                                 std::move(texture), float(g.print));
  m.color = toColor(look.color);
  m.scatter = g.scatter > 0 ? float(1 / g.scatter) : 0.0f;
  m.scatter_albedo = toColor(g.scatter_albedo);
  return m;
}

const std::array kKinds{
    MaterialKind{"jelly", false, nullptr, makeJelly},
    MaterialKind{"diffuse", false, nullptr, makeDiffuse},
    MaterialKind{"gelatine", true, readGelatine, makeGelatine},
};

}  // namespace

std::span<const MaterialKind> materialKinds() { return kKinds; }

std::vector<std::string> materialTypes() { return kindTypes(materialKinds()); }

const MaterialKind& materialKind(std::string_view type) { return findKind(materialKinds(), type, "material"); }

}  // namespace wobble
