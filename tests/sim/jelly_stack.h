// scenes/jelly_stack.toml in code, for contact's cost and tests (bench/body_contact_bench.cpp,
// tests/sim/contact/collisions/body_contact_test.cpp): two 5^3 jellies, the smaller one turned by 30 degrees and
// dropped from 2.1 m onto the other, which stands on a floor.
#pragma once
#include <memory>

#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/plane.h"
#include "sim/system.h"

namespace wobble::testing {

inline std::unique_ptr<MassSpringSystem> jellyStack() {
  auto system = std::make_unique<MassSpringSystem>();
  JellyParams base{.n = 5, .size = 1, .mass = 0.1, .ks = 3000, .kd = 2, .center = Vec3(0, 0.52, 0)};
  system->addBody(buildJelly("base", base));
  JellyParams top = base;
  top.size = 0.8;
  top.center = Vec3(0.05, 2.1, -0.05);
  top.rotation_axis = Vec3::UnitY();
  top.rotation_deg = 30;
  system->addBody(buildJelly("top", top));
  system->addCollider(
      std::make_unique<PlaneCollider>("floor", ContactParams{0.2, 0.6, 0.01}, Vec3::Zero(), Vec3::UnitY()));
  return system;
}

}  // namespace wobble::testing
