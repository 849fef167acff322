#include "sim/contact/node_motion.h"

#include <span>

namespace wobble::collision {

void NodeMotion::applyImpulse(const SurfaceNodes& nodes, const VecX& inv_mass, const Stencil& s,
                              const std::array<double, 4>& w, const Vec3& dv, double h) {
  const WeightedStencil e = nodes.expand(s, w);
  const double denom = e.inverseMass(inv_mass);
  if (denom <= 0) return;
  std::array<int, WeightedStencil::kCapacity> moved;
  int count = 0;
  for (int i = 0; i < e.size; ++i) {
    const int p = e.particle[i];
    const double share = e.w[i] * inv_mass[p] / denom;
    if (share == 0) continue;
    particle(vbar, p) += share * dv;
    particle(xe, p) = particle(xs, p) + h * particle(vbar, p);
    changed[p] = 1;
    moved[count++] = p;
  }
  refreshNodes(nodes, std::span<const int>(moved.data(), count));
}

}  // namespace wobble::collision
