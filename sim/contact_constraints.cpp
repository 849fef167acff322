#include "sim/contact_constraints.h"

#include <algorithm>

namespace wobble {

void findContactConstraints(Colliders colliders, double t, double h, const VecX& x, const VecX& v, const VecX& f,
                            const VecX& mass, const VecX& inv_mass, std::vector<ContactConstraint>& out) {
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
      // Not on a particle moving away fast enough to leave the band within the step (one that has just bounced): the
      // constraint would hold its normal velocity for the whole step against the springs' pull, positive work that
      // launched a stiff jelly off the floor at 1/60 s. A surface pushes only while it is pressed (Signorini's
      // condition at the velocity level); a resting particle's velocity noise stays far below the band's width.
      if (s && s->distance + h * s->normal.dot(particle(v, i) - s->velocity) < collider->contact().epsilon)
        out.push_back({i, s->normal, s->normal.dot(s->acceleration)});
    }
    std::inplace_merge(out.begin(), out.begin() + earlier, out.end(),
                       [](const ContactConstraint& a, const ContactConstraint& b) { return a.particle < b.particle; });
  }
}

bool addImpactConstraints(Colliders colliders, double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                          const VecX& v1, const VecX& inv_mass, std::vector<ContactConstraint>& out) {
  thread_local std::vector<int> near;  // kept between calls: no allocation per step
  thread_local std::vector<ContactConstraint> found;
  found.clear();
  for (const auto& collider : colliders) {
    collider->near(t + h, x1, 0, near);  // below the surface at the step's end
    for (const int i : near) {
      if (inv_mass[i] == 0) continue;
      const auto end = collider->query(t + h, particle(x1, i));
      if (!end || !(end->distance < 0)) continue;
      const Vec3 n = end->normal;
      const auto start = collider->query(t, particle(x0, i));
      const double approach = n.dot(particle(v0, i) - (start ? start->velocity : end->velocity));
      const double bounce = n.dot(end->velocity) + collider->contact().restitution * std::max(0.0, -approach);
      const double lift = n.dot(particle(v1, i)) - end->distance / h;
      found.push_back({i, n, (std::max(bounce, lift) - n.dot(particle(v0, i))) / h});
    }
  }
  if (found.empty()) return false;
  const auto by_particle = [](const ContactConstraint& a, const ContactConstraint& b) {
    return a.particle < b.particle;
  };
  std::stable_sort(found.begin(), found.end(), by_particle);  // collider order kept within a particle
  found.erase(std::unique(found.begin(), found.end(),
                          [](const ContactConstraint& a, const ContactConstraint& b) {
                            return a.particle == b.particle;
                          }),
              found.end());
  for (const ContactConstraint& c : found) {
    const auto at = std::lower_bound(out.begin(), out.end(), c, by_particle);
    if (at != out.end() && at->particle == c.particle) *at = c;
    else out.insert(at, c);
  }
  return true;
}

}  // namespace wobble
