#include "sim/contact_constraints.h"

#include <algorithm>

namespace wobble {

void findContactConstraints(Colliders colliders, double t, const VecX& x, const VecX& f, const VecX& mass,
                            const VecX& inv_mass, std::vector<ContactConstraint>& out) {
  out.clear();
  thread_local std::vector<int> near;  // kept between calls: no allocation per step
  for (const auto& collider : colliders) {
    const std::size_t earlier = out.size();  // constraints from earlier colliders, in particle order
    collider->near(t, x, collider->contact().epsilon, near);
    std::size_t k = 0;
    for (const int i : near) {
      if (inv_mass[i] == 0) continue;
      while (k < earlier && out[k].particle < i) ++k;
      if (k < earlier && out[k].particle == i) continue;  // the first collider holding a particle keeps it
      const auto s = activeSupport(*collider, t, particle(x, i), particle(f, i), mass[i]);
      if (s) out.push_back({i, s->normal, s->normal.dot(s->acceleration)});
    }
    std::inplace_merge(out.begin(), out.begin() + earlier, out.end(),
                       [](const ContactConstraint& a, const ContactConstraint& b) { return a.particle < b.particle; });
  }
}

}  // namespace wobble
