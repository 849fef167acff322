// A cloth that falls onto itself, for contact's cost and tests (bench/body_contact_bench.cpp,
// tests/sim/body_contact_test.cpp): a side x side cloth, 2 x 2 m and 4 kg whatever the resolution, folded like a
// ribbon into `layers` stacked layers (half-circle folds, two particle spacings between layers) just above a floor,
// with self-contact (thickness a quarter of the spacing). Its bending springs are at 1% of the cloth's stiffness: a
// limp cloth, so that the folds collapse and the layers land on each other instead of springing open.
#pragma once
#include <cmath>
#include <memory>

#include "sim/bodies/cloth.h"
#include "sim/colliders/plane.h"
#include "sim/system.h"

namespace wobble::testing {

inline std::unique_ptr<MassSpringSystem> foldedCloth(int side, bool self_contact, int layers = 4) {
  const double size = 2, spacing = size / (side - 1);
  ClothParams p;
  p.nx = p.ny = side;
  p.size_x = p.size_y = size;
  p.center = Vec3::Zero();
  p.mass = 4.0 / (side * side);
  p.ks = 20 * side * side / 4.0;  // the same sheet stiffness at every resolution
  p.kd = p.ks / 1000;
  Body cloth = buildCloth("cloth", p);
  for (std::size_t k = 0; k < cloth.springs.size(); ++k)
    if (cloth.springs.type[k] == SpringType::Bending) {
      cloth.springs.ks[k] *= 0.01;
      cloth.springs.kd[k] *= 0.01;
    }
  // Fold along x: the path of length `size` runs along layer 0 to +x, half a circle up, layer 1 back to -x, ...
  const double r = spacing, arc = M_PI * r, width = (size - (layers - 1) * arc) / layers;
  for (Eigen::Index i = 0; i < cloth.x.size() / 3; ++i) {
    double s = cloth.x[3 * i] + size / 2, x = 0, y = 0;
    for (int k = 0;; ++k) {
      const double dir = k % 2 == 0 ? 1 : -1, start = k % 2 == 0 ? 0 : width;
      if (s <= width || k == layers - 1) {
        x = start + dir * s;
        y = 2 * r * k;
        break;
      }
      s -= width;
      if (s <= arc) {
        x = start + dir * (width + r * std::sin(s / r));
        y = 2 * r * k + r * (1 - std::cos(s / r));
        break;
      }
      s -= arc;
    }
    cloth.x[3 * i] = x - width / 2;
    cloth.x[3 * i + 1] = y + 0.01;
  }
  cloth.contact.self_contact = self_contact;
  cloth.contact.thickness = 0.25 * spacing;
  auto system = std::make_unique<MassSpringSystem>();
  system->addBody(std::move(cloth));
  system->addCollider(
      std::make_unique<PlaneCollider>("floor", ContactParams{0, 0.5, 0.005}, Vec3::Zero(), Vec3::UnitY()));
  return system;
}

}  // namespace wobble::testing
