// The body materials a scene may name (`material` in [bodies.NAME]), one entry each: the keys it reads and the
// renderer's material it makes. The look reader (render_config.cpp), the renderer's scene (render_scene.cpp) and
// `wobble blend` go through this table and never ask which material a body has. Adding a material: its model in
// render/ (a Material field or kind), an entry in material_kinds.cpp, its keys in scenes/README.md (a section
// "### `material = "NAME"`"), its mapping in app/blender/make_blend.py (ARCHITECTURE.md, "add a material").
#pragma once
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "app/scene/render_config.h"
#include "render/material.h"
#include "render/texture.h"

namespace wobble {

class TableReader;

struct MaterialKind {
  std::string_view type;  // the scene's `material` value
  bool closed_only;       // needs a closed surface (it has an inside): not for a cloth
  // Reads the material's own keys into look (nullptr: none).
  void (*read)(TableReader& r, BodyLook& look);
  // The renderer's material of a body with this look and its texture (or none).
  render::Material (*make)(const std::string& name, const BodyLook& look,
                           std::shared_ptr<const render::Texture> texture);
};

std::span<const MaterialKind> materialKinds();
std::vector<std::string> materialTypes();  // the `material` values, in table order
// Throws std::out_of_range for a material not in the table (the reader has checked it).
const MaterialKind& materialKind(std::string_view type);

}  // namespace wobble
