// scenes/cloth_drop.toml in code, for contact's tests (tests/sim/contact/collisions/body_contact_test.cpp): an n x n
// cloth 1.6 m square, released hanging edge-down (at the given velocity) above a sphere of radius 0.4 m on the floor,
// with self-contact (thickness a quarter of the particle spacing): it lands on the sphere, buckles and folds onto
// itself.
#pragma once
#include <memory>

#include "sim/bodies/cloth.h"
#include "sim/contact/colliders/plane.h"
#include "sim/contact/colliders/sphere.h"
#include "sim/system.h"

namespace wobble::testing {

inline std::unique_ptr<MassSpringSystem> clothDrop(int n, const Vec3& velocity = Vec3::Zero()) {
  ClothParams p;
  p.nx = p.ny = n;
  p.size_x = p.size_y = 1.6;
  p.center = Vec3(0.1, 1.95, 0.05);
  p.hanging = true;
  p.mass = 0.01;
  p.ks = 800;
  p.kd = 0.5;
  p.drag = 0.002;
  p.velocity = velocity;
  Body cloth = buildCloth("cloth", p);
  cloth.contact.self_contact = true;
  cloth.contact.thickness = 0.25 * 1.6 / (n - 1);
  auto system = std::make_unique<MassSpringSystem>();
  system->addBody(std::move(cloth));
  system->addCollider(
      std::make_unique<SphereCollider>("sphere", ContactParams{0, 0.4, 0.01}, Vec3(0, 0.4, 0), 0.4, Vec3::Zero()));
  system->addCollider(
      std::make_unique<PlaneCollider>("floor", ContactParams{0, 0.6, 0.01}, Vec3::Zero(), Vec3::UnitY()));
  return system;
}

}  // namespace wobble::testing
