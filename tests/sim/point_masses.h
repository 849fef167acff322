// Small hand-made bodies for tests: single particles and springs, where analytic answers exist.
#pragma once
#include "sim/body.h"
#include "sim/simulation.h"
#include "sim/system.h"

namespace wobble::testing {

// A body of free particles (no springs, no surface) at the given positions, all with velocity v and mass m.
inline Body particles(std::vector<Vec3> xs, Vec3 v = Vec3::Zero(), double m = 1) {
  Body b;
  b.name = "points";
  b.kind = "points";
  const int n = static_cast<int>(xs.size());
  b.x.resize(3 * n);
  b.v.resize(3 * n);
  for (int i = 0; i < n; ++i) {
    particle(b.x, i) = xs[i];
    particle(b.v, i) = v;
  }
  b.mass = VecX::Constant(n, m);
  b.pinned.assign(n, false);
  return b;
}

// Particle 0 pinned at the origin, particle 1 at (rest + stretch, 0, 0) moving with velocity v, joined by a spring.
inline Body anchoredSpring(double rest, double stretch, double v, double ks, double kd, double m = 1) {
  Body b = particles({Vec3::Zero(), Vec3(rest + stretch, 0, 0)}, Vec3::Zero(), m);
  particle(b.v, 1) = Vec3(v, 0, 0);
  b.pinned[0] = true;
  b.springs.add(0, 1, rest, ks, kd, SpringType::Structural);
  return b;
}

}  // namespace wobble::testing
