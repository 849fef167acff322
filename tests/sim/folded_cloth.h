// A cloth that falls onto itself, for contact's cost and tests (bench/body_contact_bench.cpp,
// tests/sim/contact/collisions/body_contact_test.cpp): a side x side cloth, 2 x 2 m and 4 kg whatever the resolution,
// folded like a ribbon into `layers` stacked layers (half-circle folds, two particle spacings between layers) just
// above a floor, with self-contact (thickness a quarter of the spacing). Its bending springs are at 1% of the cloth's
// stiffness: a limp cloth, so that the folds collapse and the layers land on each other instead of springing open. With
// layer_gap > 0 (less than 1) the layers lie that many spacings apart instead, each fold one short spring, and every
// spring's rest length is its length in this folded shape: nothing springs open at release, the stack drops onto the
// floor and its layers settle onto each other (at 256 x 256 the default folds spring open so violently that the run
// stops: docs/body-contact.md, Cost). floor_friction: the floor's Coulomb coefficient; velocity: every particle's at
// release; drag: the air's (buildCloth's by default).
#pragma once
#include <cmath>
#include <memory>

#include "sim/bodies/cloth.h"
#include "sim/contact/colliders/plane.h"
#include "sim/system.h"

namespace wobble::testing {

inline std::unique_ptr<MassSpringSystem> foldedCloth(int side, bool self_contact, int layers = 4, double layer_gap = 0,
                                                     double floor_friction = 0.5, const Vec3& velocity = Vec3::Zero(),
                                                     double drag = ClothParams{}.drag) {
  const double size = 2, spacing = size / (side - 1);
  ClothParams p;
  p.nx = p.ny = side;
  p.size_x = p.size_y = size;
  p.center = Vec3::Zero();
  p.mass = 4.0 / (side * side);
  p.ks = 20 * side * side / 4.0;  // the same sheet stiffness at every resolution
  p.kd = p.ks / 1000;
  p.velocity = velocity;
  p.drag = drag;
  Body cloth = buildCloth("cloth", p);
  for (std::size_t k = 0; k < cloth.springs.size(); ++k)
    if (cloth.springs.type[k] == SpringType::Bending) {
      cloth.springs.ks[k] *= 0.01;
      cloth.springs.kd[k] *= 0.01;
    }
  // Fold along x: the path of length `size` runs along layer 0 to +x, a fold up, layer 1 back to -x, ...; a fold is
  // half a circle of radius r, or with layer_gap one spring up `rise` and back half a spacing (each layer then a whole
  // number of spacings long, so that the fold is one of the cloth's springs).
  const bool stacked = layer_gap > 0;
  const double r = spacing, arc = stacked ? spacing : M_PI * r, rise = stacked ? layer_gap * spacing : 2 * r;
  const double shift = stacked ? spacing / 2 : 0;  // a stacked layer's particles halfway between those below
  const double width =
      stacked ? spacing * std::floor((side - layers) / double(layers)) : (size - (layers - 1) * arc) / layers;
  for (Eigen::Index i = 0; i < cloth.x.size() / 3; ++i) {
    double s = cloth.x[3 * i] + size / 2, x = 0, y = 0;
    for (int k = 0;; ++k) {
      const double dir = k % 2 == 0 ? 1 : -1, start = k % 2 == 0 ? 0 : width - shift;
      if (s <= width || k == layers - 1) {
        x = start + dir * s;
        y = rise * k;
        break;
      }
      s -= width;
      if (s <= arc) {
        x = start + dir * (width + (stacked ? -shift * s / arc : r * std::sin(s / r)));
        y = rise * k + (stacked ? rise * s / arc : r * (1 - std::cos(s / r)));
        break;
      }
      s -= arc;
    }
    cloth.x[3 * i] = x - width / 2;
    cloth.x[3 * i + 1] = y + 0.01;
  }
  if (stacked)
    for (std::size_t k = 0; k < cloth.springs.size(); ++k)
      cloth.springs.rest[k] =
          (cloth.x.segment<3>(3 * cloth.springs.a[k]) - cloth.x.segment<3>(3 * cloth.springs.b[k])).norm();
  cloth.contact.self_contact = self_contact;
  cloth.contact.thickness = 0.25 * spacing;
  auto system = std::make_unique<MassSpringSystem>();
  system->addBody(std::move(cloth));
  system->addCollider(
      std::make_unique<PlaneCollider>("floor", ContactParams{0, floor_friction, 0.005}, Vec3::Zero(), Vec3::UnitY()));
  return system;
}

}  // namespace wobble::testing
