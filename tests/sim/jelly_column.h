// A column of small jellies dropped onto a floor, each shifted a little from the one below, alternately along x and z:
// the pile of issue 53 that never came to rest under backward Euler (docs/body-contact.md, "Rest"). For
// tests/sim/contact/collisions/body_rest_test.cpp.
#pragma once
#include <memory>
#include <string>
#include <vector>

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

// The column's jellies, bottom first, before they join a system.
inline std::vector<Body> columnJellies(const ColumnParams& p) {
  std::vector<Body> jellies;
  const double s = p.jelly.size;
  for (int k = 0; k < p.count; ++k) {
    JellyParams j = p.jelly;
    const double shift = p.offset * s * ((k + 1) / 2);
    j.center = Vec3(k % 2 ? shift : shift * 0.5, 0.5 * s + 0.05 + k * (s + p.gap), k % 2 ? -shift * 0.5 : shift);
    Body b = buildJelly("jelly" + std::to_string(k), j);
    b.contact.friction = p.friction;
    jellies.push_back(std::move(b));
  }
  return jellies;
}

inline void addFloor(MassSpringSystem& system, const ColumnParams& p) {
  system.addCollider(std::make_unique<PlaneCollider>("floor", p.floor, Vec3::Zero(), Vec3::UnitY()));
}

inline std::unique_ptr<MassSpringSystem> jellyColumn(const ColumnParams& p) {
  auto system = std::make_unique<MassSpringSystem>();
  for (Body& b : columnJellies(p)) system->addBody(std::move(b));
  addFloor(*system, p);
  return system;
}

// Jelly b's particle (i, j, k) of an n^3 lattice (index i + n (j + n k)) in the column of count jellies glued into
// one n x (count n) x n lattice (fusedColumn): layer b n + j.
inline int fusedParticle(int b, int n, int count, int i, int j, int k) { return i + n * (b * n + j + count * n * k); }

// The same jellies glued into one body (an oracle for the stack: the column's own modes, with no contact): their
// particles (state and masses) and springs, and across each gap between one jelly's top layer and the next one's
// bottom layer the lattice's springs too (structural, shear and bending, rest length their initial distance) where the
// stack has contact. An n x (count n) x n lattice, layer b n + j the jelly b's layer j; its surface, the jellies'.
inline Body fusedColumn(const std::vector<Body>& jellies, int n) {
  const int count = static_cast<int>(jellies.size()), per = n * n * n;
  Body fused = particleBody("column", "jelly", count * per, jellies.front().mass[0]);
  fused.contact = jellies.front().contact;
  for (int b = 0; b < count; ++b) {
    const Body& jelly = jellies[b];
    std::vector<int> to(per);  // the jelly's particle -> the column's
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) to[i + n * (j + n * k)] = fusedParticle(b, n, count, i, j, k);
    for (int q = 0; q < per; ++q) {
      particle(fused.x, to[q]) = particle(jelly.x, q);
      particle(fused.v, to[q]) = particle(jelly.v, q);
      fused.mass[to[q]] = jelly.mass[q];
    }
    const int base = static_cast<int>(fused.surface.vertexCount());
    for (int vtx : jelly.surface.particle) fused.surface.particle.push_back(to[vtx]);
    fused.surface.uv.insert(fused.surface.uv.end(), jelly.surface.uv.begin(), jelly.surface.uv.end());
    for (auto t : jelly.surface.triangles) fused.surface.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  const Springs& springs = jellies.front().springs;
  addLatticeSprings({n, count * n, n}, jellyOffsets(), fused.x, springs.ks[0], springs.kd[0], fused.springs);
  return fused;
}

}  // namespace wobble::testing
