#include "sim/contact/constraints/constraints.h"

#include <algorithm>

namespace wobble {
namespace {

// m/s: a relative normal velocity above this leaves the surface (round-off in a resting one stays far below).
constexpr double kLeaving = 1e-9;

bool byParticleAndCollider(const ContactConstraint& a, const ContactConstraint& b) {
  return a.particle != b.particle ? a.particle < b.particle : a.collider < b.collider;
}

// The friction of a resting contact c on a particle of mass m under the force f (as addContactForces sees it), moving
// at v, with the system's step h (stick time 2 h): what the accelerations add (taken out by the step), and what the
// step holds instead: sticking, the explicit law's tangential acceleration (the relative tangential velocity stopped
// over 2 h, plus the surface's tangential acceleration); sliding, a damper of Coulomb's force at the start's sliding
// speed (at least ContactConstraint::kStickSpeed), on the velocity relative to the surface at the step's end.
void addFriction(const SurfacePoint& s, const ContactParams& params, const Vec3& f, const Vec3& v, double m, double h,
                 ContactConstraint& c) {
  const SupportParts parts = supportParts(s, params, f, v, m, 2 * h);
  const Eigen::Matrix3d tangential = Eigen::Matrix3d::Identity() - s.normal * s.normal.transpose();
  const Vec3 slide = tangential * (v - s.velocity);
  c.friction = parts.friction;
  c.stick = parts.sticks;
  c.tangential_acceleration = tangential * s.acceleration - slide / (2 * h);
  c.damping = parts.limit / std::max(slide.norm(), ContactConstraint::kStickSpeed);
  c.mu = params.friction;
  c.support = parts.support;
  c.surface_velocity = s.velocity;
  c.surface_acceleration = s.acceleration;
}

}  // namespace

void findContactConstraints(Colliders colliders, double t, double h, const VecX& x, const VecX& v, const VecX& f,
                            const VecX& mass, const VecX& inv_mass, std::vector<ContactConstraint>& out,
                            std::vector<ReleasedSupport>* released) {
  out.clear();
  if (released) released->clear();
  thread_local std::vector<int> near;  // kept between calls: no allocation per step
  // The force as addContactForces sees it at each collider (the smooth force plus the earlier colliders' supports),
  // to size the friction it adds exactly.
  thread_local VecX running;
  if (colliders.size() > 1) running = f;
  const VecX& acting = colliders.size() > 1 ? running : f;
  for (std::size_t k = 0; k < colliders.size(); ++k) {
    const Collider& collider = *colliders[k];
    const std::size_t earlier = out.size();  // constraints from earlier colliders, in particle order
    collider.near(t, x, collider.contact().epsilon, near);
    for (const int i : near) {
      if (inv_mass[i] == 0) continue;
      const auto s = activeSupport(collider, t, particle(x, i), particle(f, i), mass[i]);
      // Not on a particle moving away fast enough to leave the band within the step (one that has just bounced): the
      // constraint would hold its normal velocity for the whole step against the springs' pull, positive work that
      // launched a stiff jelly off the floor at 1/60 s. A surface pushes only while it is pressed (Signorini's
      // condition at the velocity level); a resting particle's velocity noise stays far below the band's width.
      // The support addContactForces applies (the same as s on one collider), whose friction the step replaces.
      const auto applied =
          colliders.size() > 1 ? activeSupport(collider, t, particle(x, i), particle(running, i), mass[i]) : s;
      if (!s) {
      } else if (s->distance + h * s->normal.dot(particle(v, i) - s->velocity) < collider.contact().epsilon) {
        out.push_back({i, s->normal, s->normal.dot(s->acceleration), int(k)});
        if (applied && collider.contact().friction > 0)
          addFriction(*applied, collider.contact(), particle(acting, i), particle(v, i), mass[i], h, out.back());
      } else if (released) {
        released->push_back({i, supportForce(*s, collider.contact(), particle(f, i), particle(v, i), mass[i], 2 * h)});
      }
      if (colliders.size() > 1 && applied)  // as addContactForces: the next collider sees this one's support
        particle(running, i) +=
            supportForce(*applied, collider.contact(), particle(running, i), particle(v, i), mass[i], 2 * h);
    }
    // Stable: an earlier collider's constraint on a particle stays before this one's.
    std::inplace_merge(out.begin(), out.begin() + earlier, out.end(), byParticleAndCollider);
  }
  // A particle on several surfaces is not held by static friction: its tangential directions are few or none, and
  // which surface's friction would prescribe them is ambiguous. Its friction is each surface's damper instead.
  for (std::size_t k = 0; k + 1 < out.size(); ++k)
    if (out[k].particle == out[k + 1].particle) out[k].stick = out[k + 1].stick = false;
}

bool addImpactConstraints(Colliders colliders, double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                          const VecX& v1, const VecX& inv_mass, std::vector<ContactConstraint>& out) {
  thread_local std::vector<int> near;  // kept between calls: no allocation per step
  thread_local std::vector<ContactConstraint> found;
  found.clear();
  for (std::size_t k = 0; k < colliders.size(); ++k) {
    const Collider& collider = *colliders[k];
    collider.near(t + h, x1, 0, near);  // below the surface at the step's end
    for (const int i : near) {
      if (inv_mass[i] == 0) continue;
      const auto end = collider.query(t + h, particle(x1, i));
      if (!end || !(end->distance < 0)) continue;
      const Vec3 n = end->normal;
      const auto start = collider.query(t, particle(x0, i));
      const double approach = n.dot(particle(v0, i) - (start ? start->velocity : end->velocity));
      const double bounce = n.dot(end->velocity) + collider.contact().restitution * std::max(0.0, -approach);
      const double lift = n.dot(particle(v1, i)) - end->distance / h;
      found.push_back({i, n, (std::max(bounce, lift) - n.dot(particle(v0, i))) / h, int(k), true});
    }
  }
  if (found.empty()) return false;
  std::sort(found.begin(), found.end(), byParticleAndCollider);
  // A particle's resting constraints on surfaces it was leaving at the step's start go when it meets an impact: they
  // hold a separating normal velocity, and on a stiff jelly sliding into a wall, the floor's held together with the
  // wall's impact over-constrained the body (a ks 1e7 cube jumped 0.6 m off the floor). Those it was not leaving (a
  // particle in a groove, kept on both planes) and its impacts, this pass's and earlier passes', stay together.
  const auto by_particle = [](const ContactConstraint& a, const ContactConstraint& b) {
    return a.particle < b.particle;
  };
  out.erase(std::remove_if(out.begin(), out.end(),
                           [&](const ContactConstraint& c) {
                             if (c.impact || !std::binary_search(found.begin(), found.end(), c, by_particle))
                               return false;
                             const auto start = colliders[c.collider]->query(t, particle(x0, c.particle));
                             const Vec3 u = start ? start->velocity : Vec3::Zero();
                             return c.normal.dot(particle(v0, c.particle) - u) > kLeaving;
                           }),
            out.end());
  for (const ContactConstraint& c : found) {
    const auto at = std::lower_bound(out.begin(), out.end(), c, byParticleAndCollider);
    if (at != out.end() && at->particle == c.particle && at->collider == c.collider) *at = c;
    else out.insert(at, c);
  }
  return true;
}

}  // namespace wobble
