// scenes/jelly_stack.toml in code, for contact's cost and tests (bench/body_contact_bench.cpp,
// tests/sim/contact/collisions/body_contact_test.cpp): two 5^3 jellies, the smaller one turned by 30 degrees and
// dropped from 2.1 m onto the other, which stands on a floor. self_contact: each jelly's (the scene's default: on).
#pragma once
#include <initializer_list>
#include <memory>
#include <utility>

#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/plane.h"
#include "sim/system.h"

namespace wobble::testing {

// Adds a jelly per (name, params), each with that self-contact.
inline void addJellies(MassSpringSystem& system, std::initializer_list<std::pair<const char*, JellyParams>> jellies,
                       bool self_contact) {
  for (const auto& [name, params] : jellies) {
    Body body = buildJelly(name, params);
    body.contact.self_contact = self_contact;
    system.addBody(std::move(body));
  }
}

inline std::unique_ptr<MassSpringSystem> jellyStack(bool self_contact = false) {
  auto system = std::make_unique<MassSpringSystem>();
  JellyParams base{.n = 5, .size = 1, .mass = 0.1, .ks = 3000, .kd = 2, .center = Vec3(0, 0.52, 0)};
  JellyParams top = base;
  top.size = 0.8;
  top.center = Vec3(0.05, 2.1, -0.05);
  top.rotation_axis = Vec3::UnitY();
  top.rotation_deg = 30;
  addJellies(*system, {{"base", base}, {"top", top}}, self_contact);
  system->addCollider(
      std::make_unique<PlaneCollider>("floor", ContactParams{0.2, 0.6, 0.01}, Vec3::Zero(), Vec3::UnitY()));
  return system;
}

}  // namespace wobble::testing
