// A small jelly thrown onto a cloth, for contact's tests (tests/sim/contact/): a 3^3 jelly 0.4 m wide at 4 m/s straight
// down from 1.6 m onto a 16 x 16 cloth 2 m square, pinned at its corners, with self-contact: the cloth's pairs with
// itself and the pairs of the two bodies.
#pragma once
#include <memory>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/system.h"

namespace wobble::testing {

inline std::unique_ptr<MassSpringSystem> jellyOnCloth() {
  auto system = std::make_unique<MassSpringSystem>();
  ClothParams p;
  p.nx = p.ny = 16;
  p.size_x = p.size_y = 2;
  p.ks = 5000;
  p.kd = 10;
  p.mass = 0.05;
  p.pinned = clothPinSet("corners", 16, 16);
  Body cloth = buildCloth("cloth", p);
  cloth.contact.self_contact = true;
  system->addBody(std::move(cloth));
  JellyParams jelly{.n = 3, .size = 0.4, .mass = 0.1, .ks = 2000, .kd = 5, .center = Vec3(0.05, 1.6, 0.03)};
  jelly.velocity = Vec3(0, -4, 0);
  system->addBody(buildJelly("jelly", jelly));
  return system;
}

}  // namespace wobble::testing
