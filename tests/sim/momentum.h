// Total linear momentum sum m_i v_i of a system's particles, for the contact tests' conservation checks.
#pragma once
#include "sim/system.h"

namespace wobble::testing {

inline Vec3 momentum(const MassSpringSystem& system, const VecX& v) {
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < system.particleCount(); ++i) p += system.mass()[i] * particle(v, i);
  return p;
}

}  // namespace wobble::testing
