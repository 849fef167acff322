// The cloth-on-a-sphere fixture of several tests: an n x n cloth of stiffness ks with its corners pinned, 5 mm above
// the top of a unit sphere at the origin (friction 0.5, contact epsilon 1 cm), so that it lands within a few steps;
// without self-contact unless asked (a scene's cloth has it by default).
#pragma once
#include <memory>

#include "sim/bodies/cloth.h"
#include "sim/contact/colliders/sphere.h"
#include "sim/system.h"

namespace wobble::testing {

inline std::unique_ptr<MassSpringSystem> clothOnSphere(int n, double ks = ClothParams{}.ks, bool self_contact = false) {
  ClothParams p;
  p.nx = p.ny = n;
  p.ks = ks;
  p.center = Vec3(0, 1.005, 0);
  p.pinned = clothPinSet("corners", p.nx, p.ny);
  auto system = std::make_unique<MassSpringSystem>();
  Body cloth = buildCloth("cloth", p);
  cloth.contact.self_contact = self_contact;
  system->addBody(std::move(cloth));
  system->addCollider(
      std::make_unique<SphereCollider>("sphere", ContactParams{0, 0.5, 0.01}, Vec3::Zero(), 1.0, Vec3::Zero()));
  return system;
}

}  // namespace wobble::testing
