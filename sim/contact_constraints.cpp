#include "contact_constraints.h"

namespace wobble {

void findContactConstraints(Colliders colliders, double t, const VecX& x, const VecX& f, const VecX& mass,
                            const VecX& inv_mass, std::vector<ContactConstraint>& out) {
  out.clear();
  const Eigen::Index n = mass.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    if (inv_mass[i] == 0) continue;
    for (const auto& collider : colliders) {
      const auto s = activeSupport(*collider, t, particle(x, i), particle(f, i), mass[i]);
      if (!s) continue;
      out.push_back({static_cast<int>(i), s->normal, s->normal.dot(s->acceleration)});
      break;
    }
  }
}

}  // namespace wobble
