// The collider kinds a scene may name (`type` in [colliders.NAME]), one entry each: the keys it reads, its default
// look and the shape it is drawn as. The reader (scene.cpp), the look (render_config.cpp), the renderer's scene
// (render_scene.cpp) and `wobble blend` go through this table and never ask which kind a collider is; the camera
// frames colliders by Collider::bounds. Adding a kind: a collider in sim/contact/colliders/, an entry in
// collider_kinds.cpp, its keys in scenes/README.md.
#pragma once
#include <array>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "app/scene/render_config.h"
#include "sim/contact/colliders/collider.h"

namespace wobble {

class TableReader;

// What a collider looks like at a time, in the scene's units (double); render_scene.cpp makes the renderer's shapes.
struct DrawnQuad {  // a finite square: a plane's `size` around its `point`
  Vec3 center, normal;
  double size, tile;  // side; texture tile (texture_scale)
};
struct DrawnSphere {
  Vec3 center;
  double radius;
};
struct DrawnBox {  // axis-aligned
  Vec3 center, size;
};
struct DrawnMesh {  // a mesh collider's triangles (flat-shaded), moved by `center` from where they were read
  Vec3 center;
  const std::vector<Vec3>* points;  // owned by the collider
  const std::vector<std::array<int, 3>>* triangles;
};
using DrawnShape = std::variant<DrawnQuad, DrawnSphere, DrawnBox, DrawnMesh>;

struct ColliderKind {
  std::string_view type;  // the scene's `type` value
  Vec3 color;             // default look: `color` and `texture`
  std::string_view texture;
  bool moves;  // drawn again at every frame
  // Reads the kind's own keys (the contact keys are read already); may set look keys it owns (a plane's `size`).
  std::unique_ptr<Collider> (*read)(TableReader& r, const std::string& name, const ContactParams& contact,
                                    ColliderLook& look);
  // Reads look keys of this kind alone, after `color` and `texture` (nullptr: none).
  void (*read_look)(TableReader& r, ColliderLook& look);
  // The shape drawn at time t; `collider` is one this entry's read made.
  DrawnShape (*drawn)(const Collider& collider, const ColliderLook& look, double t);
};

std::span<const ColliderKind> colliderKinds();
std::vector<std::string> colliderTypes();  // the `type` values, in table order
// Throws std::out_of_range for a type not in the table (the reader has checked it).
const ColliderKind& colliderKind(std::string_view type);

}  // namespace wobble
