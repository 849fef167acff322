// What an integrator sees of a physical system: accelerations as a function of time and flat state, and, for
// implicit integrators, an optional linearization of the forces.
#pragma once
#include <vector>

#include <Eigen/SparseCore>

#include "types.h"

namespace wobble {

using Triplets = std::vector<Eigen::Triplet<double>>;

// A particle held by a surface at a state: its contact support force is active there. Implicit integrators turn the
// support into a velocity constraint over the step (Baraff & Witkin's filter), because a support force sized to
// cancel a stiff spring's push at the start, held for a whole long step while the spring relaxes, launches the body.
struct ContactConstraint {
  int particle;
  Vec3 normal;                 // unit, out of the surface
  double normal_acceleration;  // of the surface along the normal: the particle's normal velocity changes by h times it
};

// Optional capability of a Dynamics, for implicit integrators: the lumped (diagonal) mass and the smooth forces with
// their Jacobians. Smooth means every force except contact (support and friction): those are not differentiable,
// so implicit methods take them explicitly, from Dynamics::acceleration at the step's start state.
class ForceJacobian {
 public:
  // Mass per particle, and inverse mass, which is 0 for a pinned particle (implicit solvers filter those out).
  virtual const VecX& mass() const = 0;
  virtual const VecX& inverseMass() const = 0;
  // f = the smooth forces at (t, x, v), 3 per particle (resized).
  virtual void smoothForce(double t, const VecX& x, const VecX& v, VecX& f) const = 0;
  // Appends the entries of dF/dx and dF/dv of the smooth forces at (t, x, v): 3n x 3n, symmetric and negative
  // semidefinite (so M - h dF/dv - h^2 dF/dx is positive definite); duplicate entries are meant to be summed.
  virtual void addForceJacobians(double t, const VecX& x, const VecX& v, Triplets& dfdx, Triplets& dfdv) const = 0;
  // Replaces out by the particles whose contact support is active at (t, x, v), at most one per particle. The default
  // is none: contact, if any, then stays an explicit force in the accelerations.
  virtual void contactConstraints(double t, const VecX& x, const VecX& v, std::vector<ContactConstraint>& out) const {
    (void)t, (void)x, (void)v;
    out.clear();
  }

 protected:
  ~ForceJacobian() = default;
};

class Dynamics {
 public:
  virtual ~Dynamics() = default;
  // a = M^-1 f(t, x, v). Must be a pure function of its arguments: integrators call it at trial states.
  virtual void acceleration(double t, const VecX& x, const VecX& v, VecX& a) const = 0;
  // What implicit integrators need beyond accelerations; nullptr when the system offers no Jacobians.
  virtual const ForceJacobian* forceJacobian() const { return nullptr; }
};

}  // namespace wobble
