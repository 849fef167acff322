#include "app/scene/body_kinds.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "app/scene/kind_table.h"
#include "app/scene/model_file.h"
#include "app/scene/scene_budget.h"
#include "app/scene/scene_file.h"
#include "app/scene/table_reader.h"
#include "io/text_table.h"
#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/bodies/mesh_jelly.h"
#include "sim/simulation.h"

namespace wobble {
namespace {

// A start faster than the blow-up rule allows would be reported as a blow-up at step 1, advising a smaller dt.
void checkSpeed(TableReader& r, const Vec3& velocity) {
  if (velocity.squaredNorm() > kBlowUpSpeedSquared)
    r.fail("velocity", "a speed of " + std::to_string(std::lround(velocity.norm())) +
                           " m/s is above the blow-up threshold of 1000 m/s (|v|^2 > 1e6, sim/simulation.h)");
}

// A jelly of the user's model (`mesh`): the model is read and checked before the lattice is charged to the budget.
Body readMeshJelly(TableReader& r, const std::string& name, SceneFile& scene) {
  const ModelMesh model = readModelKey(r, true);
  MeshJellyParams p;
  // (cells + 1)^3 particles at most: bounded like the cube jelly's n.
  p.cells = r.integer("cells", p.cells, Range{1, std::floor(std::cbrt(double(kMaxBodyParticles))) - 1});
  reserveBody(r, scene, "cells", p.cells, [&model](int cells) {
    return meshJellySize(cells, std::int64_t(model.points.size()), std::int64_t(model.triangles.size()));
  });
  p.placement = readPlacement(r, JellyParams{}.center, model);
  p.mass = r.number("mass", p.mass, Range::positive());
  p.ks = r.number("ks", p.ks, Range::nonNegative());
  p.kd = r.number("kd", p.kd, Range::nonNegative());
  p.velocity = r.vec3("velocity", p.velocity);
  checkSpeed(r, p.velocity);
  return buildMeshJelly(name, model, p);
}

Body readJelly(TableReader& r, const std::string& name, SceneFile& scene) {
  if (r.node("mesh")) return readMeshJelly(r, name, scene);
  JellyParams p;
  // n^3 particles: the cube root of the most one body may have bounds n before anything is multiplied.
  p.n = r.integer("n", p.n, Range{2, std::floor(std::cbrt(double(kMaxBodyParticles)))});
  reserveBody(r, scene, "n", p.n, [](int n) { return jellySize(n); });
  p.size = r.number("size", p.size, Range::positive());
  p.mass = r.number("mass", p.mass, Range::positive());
  p.ks = r.number("ks", p.ks, Range::nonNegative());
  p.kd = r.number("kd", p.kd, Range::nonNegative());
  p.center = r.vec3("center", p.center);
  p.rotation_axis = r.vec3("rotation_axis", p.rotation_axis);
  p.rotation_deg = r.number("rotation_deg", p.rotation_deg);
  p.velocity = r.vec3("velocity", p.velocity);
  checkSpeed(r, p.velocity);
  if (p.rotation_deg != 0 && p.rotation_axis.norm() == 0) r.fail("rotation_axis", "must not be zero");
  return buildJelly(name, p);
}

void readPins(TableReader& r, ClothParams& p) {
  const toml::node* node = r.node("pinned");
  if (!node) return;
  const toml::array* list = node->as_array();
  if (!list) r.fail("pinned", "must be an array of particle indices and/or \"corners\", \"top-edge\"");
  for (const toml::node& item : *list) {
    if (const auto* index = item.as_integer()) {
      if (index->get() < 0 || index->get() >= p.nx * p.ny)
        r.fail("pinned", "index " + std::to_string(index->get()) + " must be in [0, " +
                             std::to_string(p.nx * p.ny - 1) + "] (i + nx * j)");
      p.pinned.push_back(static_cast<int>(index->get()));
    } else if (const auto* set = item.as_string()) {
      try {
        const auto ids = clothPinSet(set->get(), p.nx, p.ny);
        p.pinned.insert(p.pinned.end(), ids.begin(), ids.end());
      } catch (const std::invalid_argument& e) {
        r.fail("pinned", e.what());
      }
    } else {
      r.fail("pinned", "items must be particle indices or \"corners\", \"top-edge\"");
    }
  }
}

Body readCloth(TableReader& r, const std::string& name, SceneFile& scene) {
  ClothParams p;
  // nx ny particles; bounding each by the most one body may have over 2 keeps 64-bit counts from overflowing.
  const Range side{2, double(kMaxBodyParticles / 2)};
  p.nx = r.integer("nx", p.nx, side);
  p.ny = r.integer("ny", p.ny, side);
  reserveBody(r, scene, "ny", p.ny, [nx = p.nx](int ny) { return clothSize(nx, ny); });
  const auto size = r.pair("size", {p.size_x, p.size_y}, Range::positive());
  p.size_x = size[0];
  p.size_y = size[1];
  p.center = r.vec3("center", p.center);
  p.hanging = r.boolean("hanging", p.hanging);
  p.mass = r.number("mass", p.mass, Range::positive());
  p.ks = r.number("ks", p.ks, Range::nonNegative());
  p.kd = r.number("kd", p.kd, Range::nonNegative());
  p.drag = r.number("drag", p.drag, Range::nonNegative());
  p.velocity = r.vec3("velocity", p.velocity);
  checkSpeed(r, p.velocity);
  readPins(r, p);
  return buildCloth(name, p);
}

// Untextured: a jelly red (deeper than the OBJ material's: the glossy coat whitens it) or the OBJ's cloth blue.
const std::array kKinds{
    BodyKind{"jelly", Vec3(0.8, 0.12, 0.15), "jelly", false, true, true, readJelly},
    BodyKind{"cloth", Vec3(0.25, 0.4, 0.8), "diffuse", true, true, false, readCloth},
};

}  // namespace

std::span<const BodyKind> bodyKinds() { return kKinds; }

std::vector<std::string> bodyTypes() { return kindTypes(bodyKinds()); }

const BodyKind& bodyKind(std::string_view type) { return findKind(bodyKinds(), type, "body"); }

void readBodyContact(TableReader& r, const BodyKind& kind, int bodies, Body& body) {
  const auto& rest = body.springs.rest;
  const double shortest =
      rest.empty() ? std::numeric_limits<double>::infinity() : *std::min_element(rest.begin(), rest.end());
  SurfaceContact& c = body.contact;
  c.thickness = r.number("thickness", std::min(c.thickness, 0.25 * shortest), Range::positive());
  if (c.thickness >= shortest)
    r.fail("thickness", "must be > 0 and below the body's shortest spring, " + io::formatNumber(shortest) +
                            " m (a thicker contact layer would hold a surface's own neighbours apart)");
  c.friction = r.number("friction", c.friction, Range::nonNegative());
  // A jelly alone folds only at very large strain; pressed by another body into a narrow place it folds through itself
  // (docs/body-contact.md, "Self-contact"), and the pass runs for the bodies' sake anyway.
  c.self_contact = r.boolean("self_contact", bodies > 1 ? kind.self_contact_among : kind.self_contact);
}

}  // namespace wobble
