#include "sim/contact.h"

#include <cmath>
#include <vector>

namespace wobble {
namespace {

std::vector<int>& nearScratch() {
  thread_local std::vector<int> near;  // kept between calls: no allocation per step
  return near;
}

}  // namespace

std::optional<SurfacePoint> activeSupport(const Collider& collider, double t, const Vec3& x, const Vec3& f, double m) {
  auto s = collider.query(t, x);
  if (!s || std::abs(s->distance) >= collider.contact().epsilon) return std::nullopt;
  if (s->normal.dot(f - m * s->acceleration) >= 0) return std::nullopt;
  return s;
}

void addContactForces(Colliders colliders, double t, const VecX& x, const VecX& v, const VecX& mass,
                      const VecX& inv_mass, double stick_time, VecX& f) {
  // Collider by collider over the particles near it: each particle still meets the colliders in order.
  std::vector<int>& near = nearScratch();
  for (const auto& collider : colliders) {
    collider->near(t, x, collider->contact().epsilon, near);
    for (const int i : near) {
      if (inv_mass[i] == 0) continue;
      const auto s = activeSupport(*collider, t, particle(x, i), particle(f, i), mass[i]);
      if (!s) continue;
      // Net force relative to the surface's frame; its normal part pushes into the surface (activeSupport).
      const Vec3 g = particle(f, i) - mass[i] * s->acceleration;
      const double push = s->normal.dot(g), support = -push;
      const ContactParams& c = collider->contact();
      const Vec3 vr = particle(v, i) - s->velocity;
      const Vec3 vt = vr - s->normal.dot(vr) * s->normal;
      const Vec3 gt = g - push * s->normal;
      const double limit = c.friction * support;
      Vec3 friction = -(gt + (mass[i] / stick_time) * vt);
      if (friction.norm() > limit) {
        const double speed = vt.norm();
        const Vec3 direction = speed > 0 ? Vec3(vt / speed) : gt.normalized();
        friction = -limit * direction;
      }
      particle(f, i) += support * s->normal + friction;
    }
  }
}

void resolveCollisions(Colliders colliders, double t, VecX& x, VecX& v, const VecX& inv_mass) {
  std::vector<int>& near = nearScratch();
  for (const auto& collider : colliders) {
    const ContactParams& c = collider->contact();
    collider->near(t, x, c.epsilon, near);
    for (const int i : near) {
      if (inv_mass[i] == 0) continue;
      const auto s = collider->query(t, particle(x, i));
      if (!s || s->distance >= c.epsilon) continue;
      const double vn = s->normal.dot(particle(v, i) - s->velocity);
      if (vn < 0) particle(v, i) -= (1 + c.restitution) * vn * s->normal;
      if (s->distance < 0) particle(x, i) -= s->distance * s->normal;
    }
  }
}

}  // namespace wobble
