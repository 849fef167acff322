#include "system.h"

#include "contact.h"

namespace wobble {
namespace {

void appendTo(VecX& v, const VecX& tail) {
  const Eigen::Index n = v.size();
  v.conservativeResize(n + tail.size());
  v.tail(tail.size()) = tail;
}

}  // namespace

void MassSpringSystem::addBody(Body body) {
  const int first = particleCount(), count = body.particleCount();
  appendTo(x0_, body.x);
  appendTo(v0_, body.v);
  appendTo(mass_, body.mass);
  VecX inv_mass = body.mass.cwiseInverse(), drag = VecX::Constant(count, body.drag);
  for (int i = 0; i < count; ++i)
    if (body.pinned[i]) {
      inv_mass[i] = 0;
      particle(v0_, first + i).setZero();
    }
  appendTo(inv_mass_, inv_mass);
  appendTo(drag_, drag);
  springs_.append(body.springs, first);
  bodies_.push_back({std::move(body), first});
}

void MassSpringSystem::force(double t, const VecX& x, const VecX& v, VecX& f) const {
  const int n = particleCount();
  f.resize(3 * n);
  for (int i = 0; i < n; ++i) particle(f, i) = mass_[i] * gravity_ - drag_[i] * particle(v, i);
  addSpringForces(springs_, x, v, f);
  addContactForces(colliders_, t, x, v, mass_, inv_mass_, f);
}

void MassSpringSystem::acceleration(double t, const VecX& x, const VecX& v, VecX& a) const {
  force(t, x, v, a);
  const int n = particleCount();
  for (int i = 0; i < n; ++i) particle(a, i) *= inv_mass_[i];
}

void MassSpringSystem::resolveCollisions(double t, VecX& x, VecX& v) const {
  wobble::resolveCollisions(colliders_, t, x, v, inv_mass_);
}

double MassSpringSystem::energy(const VecX& x, const VecX& v) const {
  double e = springEnergy(springs_, x);
  for (int i = 0; i < particleCount(); ++i)
    e += mass_[i] * (0.5 * particle(v, i).squaredNorm() - gravity_.dot(particle(x, i)));
  return e;
}

}  // namespace wobble
