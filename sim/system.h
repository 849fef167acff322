// The mass-spring system of a scene: every body's particles joined in one flat state, the springs, gravity, air
// drag and the colliders the scene names. It is the Dynamics that integrators step.
#pragma once
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sim/body.h"
#include "sim/contact/colliders/collider.h"
#include "sim/contact/colliders/weighted_points.h"
#include "sim/contact/params.h"
#include "sim/dynamics.h"
#include "sim/solver/pair_schedule.h"

namespace wobble {

// The energy checks' margins (docs/energy.md): the run's (Simulation) is at least the energy of lifting every free
// particle by kEnergyGainLift (m |g|, |g| at least 1 m/s^2); a step's (energyMadeUp) kStepEnergyMargin of the larger
// of that and the step start's |energy|: the linearized backward-Euler steps of the shipped scenes at 1/60 s rise by
// at most 0.7% of |energy|, but where an impact stops part of a body within the step (cloth_drop's landing: 7%;
// docs/energy.md).
inline constexpr double kEnergyGainLift = 0.01;  // m: the colliders' default contact band
inline constexpr double kStepEnergyMargin = 0.01;

struct BodySlot {
  Body body;      // as built (initial state, surface), body-local indices
  int first = 0;  // index of its first particle in the system
};

class MassSpringSystem final : public Dynamics, public ForceJacobian {
 public:
  explicit MassSpringSystem(Vec3 gravity = Vec3(0, -9.8, 0)) : gravity_(gravity) {}

  void addBody(Body body);
  void addCollider(std::unique_ptr<Collider> collider) { colliders_.push_back(std::move(collider)); }
  // The step size the system will be integrated with: static friction stops sticking contacts over 2 h
  // (see contact/colliders/response.h). Simulation sets it; a constant during each step, so accelerations stay pure.
  void setStepSize(double h) { stick_time_ = 2 * h; }
  double stepSize() const { return stick_time_ / 2; }
  // The caps of contact between bodies (sim/contact/collisions/body_collisions.h).
  void setContactSettings(const collision::Settings& s) { contact_settings_ = s; }
  const collision::Settings& contactSettings() const { return contact_settings_; }

  void acceleration(double t, const VecX& x, const VecX& v, VecX& a) const override;
  const ForceJacobian* forceJacobian() const override { return this; }
  // Total force, contact forces included.
  void force(double t, const VecX& x, const VecX& v, VecX& f) const;
  // Gravity, air drag, springs and dampers: every force but contact (ForceJacobian).
  void smoothForce(double t, const VecX& x, const VecX& v, VecX& f) const override;
  // Spring, damper and drag Jacobians (force_jacobian.h); gravity is constant, contact is left out.
  const PairSchedule& jacobianPattern() const override { return schedule_; }
  void fillJacobian(double t, const VecX& x, const VecX& v, double cx, double cv, PairBlockMatrix& a, const VecX* w,
                    VecX* kw) const override;
  bool parallel() const override { return runsInParallel(particleCount()); }
  const std::vector<int>& bodyFirsts() const override { return body_firsts_; }
  // The same Jacobians as triplets of dF/dx and dF/dv (duplicates summed): for analysis and tests.
  void addForceJacobians(double t, const VecX& x, const VecX& v, Triplets& dfdx, Triplets& dfdv) const;
  // The particles whose contact support is active (contact/constraints/constraints.h).
  void contactConstraints(double t, const VecX& x, const VecX& v, std::vector<ContactConstraint>& out,
                          std::vector<ReleasedSupport>* released = nullptr) const override;
  // The particles a candidate implicit step ends inside a collider (contact/constraints/constraints.h,
  // addImpactConstraints).
  bool impactConstraints(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1, const VecX& v1,
                         std::vector<ContactConstraint>& out) const override;
  // The embedded points a candidate implicit step ends within a collider's band, as penalty pairs (ForceJacobian).
  bool colliderPairs(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                     std::vector<ContactPair>& out) const override;
  // Restitution and penetration correction, applied to the stored state at the end of each step. Every integrator
  // meets colliders with an embedded surface here and in the contact forces (contact/colliders/weighted_points.h);
  // backward Euler's constraints hold particles only, so an embedded surface's impacts are resolved here after its
  // solve. v_start: the velocities at the step's start, whose approach alone bounces (resting contact does not;
  // contact/colliders/response.h); nullptr: every approach at the end bounces.
  void resolveCollisions(double t, VecX& x, VecX& v, const VecX* v_start = nullptr) const;

  // Work done on the bodies by moving colliders over a step from (x0, v0) at t to (x1, v1) at t + h (after contact
  // resolution): over the particles within epsilon of a collider at either end (an embedded point's: its cell's
  // particles), each one's contact impulse (its momentum change less the impulse of gravity, drag and its springs at
  // the step's midpoint) times the velocity of the nearest surface it touched (a static one's is 0). A body pressed
  // between a moving and a static surface counts the moving one's push. 0 when no moving surface is touched.
  double colliderWork(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1, const VecX& v1) const;

  // Kinetic + gravitational + elastic energy.
  double energy(const VecX& x, const VecX& v) const;
  // ForceJacobian: the rise of energy() over the step less colliderWork(), less kStepEnergyMargin of the larger of
  // the start's |energy()| and liftEnergy().
  double energyMadeUp(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                      const VecX& v1) const override;
  // ForceJacobian: the springs' elastic and gravity's energy at x1.
  double stepPotential(double h, const VecX& x1, const VecX& v1) const override;
  // The energy of lifting every free (not pinned) particle by kEnergyGainLift, with |g| at least 1 m/s^2: the energy
  // checks' absolute margin.
  double liftEnergy() const;

  int particleCount() const { return static_cast<int>(mass_.size()); }
  const VecX& initialPositions() const { return x0_; }
  const VecX& initialVelocities() const { return v0_; }
  const VecX& mass() const override { return mass_; }
  const VecX& inverseMass() const override { return inv_mass_; }
  // In the order of jacobianPattern() (pair_schedule.h), not the order the bodies listed them.
  const Springs& springs() const { return springs_; }
  // How many times the spring schedule was built: once per addBody, never per step.
  int scheduleBuilds() const { return schedule_builds_; }
  const std::vector<BodySlot>& bodies() const { return bodies_; }
  const std::vector<std::unique_ptr<Collider>>& colliders() const { return colliders_; }
  // The points of embedded surfaces that meet colliders in place of their lattice's particles: every model vertex a
  // mesh jelly's triangles use, once.
  const WeightedPoints& embeddedPoints() const { return points_; }
  const Vec3& gravity() const { return gravity_; }

 private:
  Vec3 gravity_;
  double stick_time_ = 2e-3;
  collision::Settings contact_settings_;
  std::vector<BodySlot> bodies_;
  std::vector<int> body_firsts_;  // bodies_' firsts (bodyFirsts)
  std::vector<std::unique_ptr<Collider>> colliders_;
  VecX x0_, v0_, mass_, inv_mass_, drag_;
  // inv_mass_ as colliders see particles: 0 also for a lattice particle under an embedded surface, which meets
  // colliders through points_ alone (so that the visible surface, not the lattice's corners, rests on a floor).
  VecX collider_inv_mass_;
  // Whether any particle meets colliders (collider_inv_mass_ not all 0): a mesh jelly alone meets them through its
  // points only, and the particle loops, which would skip every particle, are not run at all.
  bool particles_meet_colliders_ = false;
  std::span<const std::unique_ptr<Collider>> particleColliders() const {
    if (particles_meet_colliders_) return colliders_;
    return {};
  }
  WeightedPoints points_;
  Springs springs_;
  PairSchedule schedule_;
  int schedule_builds_ = 0;
};

}  // namespace wobble
