// A column of small jellies dropped onto a floor, each shifted a little from the one below, alternately along x and z:
// the pile of issue 53 that never came to rest under backward Euler (docs/body-contact.md, "Rest"). For
// tests/sim/contact/collisions/body_rest_test.cpp.
#pragma once
#include <memory>
#include <string>

#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/plane.h"
#include "sim/system.h"

namespace wobble::testing {

struct ColumnParams {
  int count = 3;
  // Soft enough for RK4 at 1/60 s (the stiffest mode's h omega about 2.4, below RK4's 2.8), stiff enough to carry
  // the jellies above it without flattening.
  JellyParams jelly{.n = 3, .size = 0.5, .mass = 0.05, .ks = 100, .kd = 0.5};
  double gap = 0.1;       // m between one jelly's top and the next one's bottom at the start
  double offset = 0.06;   // of the size: each jelly's shift from the one below
  double friction = 0.3;  // between bodies (each body's `friction`)
  ContactParams floor{0.2, 0.6, 0.01};
};

inline std::unique_ptr<MassSpringSystem> jellyColumn(const ColumnParams& p) {
  auto system = std::make_unique<MassSpringSystem>();
  const double s = p.jelly.size;
  for (int k = 0; k < p.count; ++k) {
    JellyParams j = p.jelly;
    const double shift = p.offset * s * ((k + 1) / 2);
    j.center = Vec3(k % 2 ? shift : shift * 0.5, 0.5 * s + 0.05 + k * (s + p.gap), k % 2 ? -shift * 0.5 : shift);
    Body b = buildJelly("jelly" + std::to_string(k), j);
    b.contact.friction = p.friction;
    system->addBody(std::move(b));
  }
  system->addCollider(std::make_unique<PlaneCollider>("floor", p.floor, Vec3::Zero(), Vec3::UnitY()));
  return system;
}

}  // namespace wobble::testing
