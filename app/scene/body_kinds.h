// The body kinds a scene may name (`type` in [bodies.NAME]), one entry each: the keys it reads and its default look.
// Every body is drawn as its surface mesh and framed by its particles, so that is all a kind needs. Adding a kind: a
// builder in sim/bodies/, an entry in body_kinds.cpp, its keys in scenes/README.md.
#pragma once
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sim/body.h"

namespace wobble {

class TableReader;
struct SceneFile;

struct BodyKind {
  std::string_view type;      // the scene's `type` value
  Vec3 color;                 // default `color` when untextured (a textured body defaults to white)
  std::string_view material;  // default `material` (material_kinds.h)
  bool self_contact;          // default `self_contact` for a body alone in its scene: whether it collides with itself
  bool self_contact_among;    // ... for a body among others (another body can press it until it folds)
  bool closed;                // its surface is closed (has an inside), as gelatine needs
  // Reads the kind's own keys and builds the body, charging its size to the scene's budget first (scene_budget.h).
  Body (*read)(TableReader& r, const std::string& name, SceneFile& scene);
};

std::span<const BodyKind> bodyKinds();
std::vector<std::string> bodyTypes();  // the `type` values, in table order
// Throws std::out_of_range for a type not in the table (the reader has checked it).
const BodyKind& bodyKind(std::string_view type);
// The contact keys every kind has (`thickness`, `friction`, `self_contact`), into body.contact; the thickness must be
// below the body's shortest spring (its default is the smaller of 0.02 m and a quarter of that spring). bodies: how
// many the scene has (self_contact's default follows it).
void readBodyContact(TableReader& r, const BodyKind& kind, int bodies, Body& body);

}  // namespace wobble
