// The stiff cloth of stiff_cloth_bench at another size, for the implicit solver's tests: side x side particles,
// ks 1e5 (kd 750, 1 kg each, 4 x 4 m), corners pinned, no colliders.
#pragma once
#include <memory>

#include "sim/bodies/cloth.h"
#include "sim/system.h"

namespace wobble::testing {

inline std::unique_ptr<MassSpringSystem> stiffCloth(int side) {
  ClothParams p;
  p.nx = p.ny = side;
  p.ks = 1e5;
  p.pinned = clothPinSet("corners", p.nx, p.ny);
  auto system = std::make_unique<MassSpringSystem>();
  system->addBody(buildCloth("cloth", p));
  return system;
}

}  // namespace wobble::testing
