// scenes/jelly_shot.toml in code, for the momentum tests and benchmarks (tests/sim/momentum_test.cpp,
// bench/jelly_contact_bench.cpp): a free pair, no gravity and no colliders. A 1.28 kg jelly (4^3 particles of
// 0.02 kg) at 25 m/s into a 25.6 kg one (8^3 of 0.05 kg) at rest, off its centre: 32 kg m/s in all. They meet at
// about 0.03 s.
#pragma once
#include <memory>

#include "sim/bodies/jelly.h"
#include "sim/system.h"

namespace wobble::testing {

inline std::unique_ptr<MassSpringSystem> jellyShot() {
  auto system = std::make_unique<MassSpringSystem>(Vec3::Zero());
  system->addBody(buildJelly("bullet", {.n = 4,
                                        .size = 0.4,
                                        .mass = 0.02,
                                        .ks = 2000,
                                        .kd = 5,
                                        .center = Vec3(-1.5, 0.3, 0.2),
                                        .velocity = Vec3(25, 0, 0)}));
  system->addBody(buildJelly("target", {.n = 8,
                                        .size = 1.6,
                                        .mass = 0.05,
                                        .ks = 2000,
                                        .kd = 5,
                                        .center = Vec3(0, 0, 0),
                                        .rotation_axis = Vec3(0, 1, 0.3),
                                        .rotation_deg = 20}));
  return system;
}

}  // namespace wobble::testing
