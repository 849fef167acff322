// Collision response shared by every collider (course-framework rules, relative to the surface's motion).
//
// Inside accelerations (a pure function of the stage state, so every integrator sees the same contact model):
//   a particle within epsilon of a surface whose net force, relative to the surface's acceleration, pushes into it
//   gets the support force Fn that cancels that push, and Coulomb friction. Static friction is what it takes to
//   cancel the tangential force and stop the tangential velocity over stick_time, -(fT + m vT / stick_time); when
//   that is within the cone mu Fn the contact sticks, otherwise it slides with kinetic friction -mu Fn vT/|vT|.
//   With stick_time = 2 h the stopping term is stable under every explicit method here (|R(-1/2)| < 1), and
//   unlike a pure kinetic law it cannot chatter around vT = 0 and creep downhill.
// At step ends only (the stored state): a particle within epsilon and approaching the surface leaves it with its
//   restitution's bounce, v_n' = u_n + e min(-(v_n - u_n), -(v0_n - u_n)) (v0: its velocity at the step's start, when
//   known): only the approach it brought into the step bounces; what the step's own forces added (the load of a
//   resting particle) is resting contact, stopped with restitution 0 (Guendelman, Bridson & Fedkiw 2003). One below
//   the surface is moved back onto it.
#pragma once
#include <memory>
#include <span>
#include <vector>

#include "sim/contact/colliders/collider.h"
#include "sim/contact/colliders/weighted_points.h"
#include "sim/dynamics.h"

namespace wobble {

using Colliders = std::span<const std::unique_ptr<Collider>>;

// The surface point at which collider supports a particle at x with mass m under net force f at time t: within
// epsilon of the surface, with f (relative to the surface's acceleration) pushing into it. Nothing otherwise.
// The one definition of an active contact, for the explicit forces here and the implicit constraints.
std::optional<SurfacePoint> activeSupport(const Collider& collider, double t, const Vec3& x, const Vec3& f, double m);

// The support and friction force on a point of mass m under net force f, moving at v, that s supports (activeSupport):
// support * s.normal + friction.
struct SupportParts {
  double support;  // N, along the normal
  Vec3 friction;   // N, tangential
  double limit;    // N: mu times the support
  bool sticks;     // static friction: the force that stops the tangential motion over stick_time is within the limit
};
SupportParts supportParts(const SurfacePoint& s, const ContactParams& c, const Vec3& f, const Vec3& v, double m,
                          double stick_time);
Vec3 supportForce(const SurfacePoint& s, const ContactParams& c, const Vec3& f, const Vec3& v, double m,
                  double stick_time);

void addContactForces(Colliders colliders, double t, const VecX& x, const VecX& v, const VecX& mass,
                      const VecX& inv_mass, double stick_time, VecX& f);

// v_start: the velocities at the step's start (nullptr: unknown, every approach bounces).
void resolveCollisions(Colliders colliders, double t, VecX& x, VecX& v, const VecX& inv_mass,
                       const VecX* v_start = nullptr);

// The same for points riding on particles (contact/colliders/weighted_points.h: a mesh jelly's surface): each point
// meets the colliders as a particle of the point's mass would, at its own position and velocity, and the force, impulse
// or move is handed to its particles by its weights. Points in order, each seeing what the earlier ones did to their
// shared particles. added (when given): appended with each force handed to a particle (an implicit step takes them out
// again and holds the points by its own penalty: ForceJacobian::colliderPairs).
void addContactForces(Colliders colliders, const WeightedPoints& points, double t, const VecX& x, const VecX& v,
                      const VecX& inv_mass, double stick_time, VecX& f, std::vector<ReleasedSupport>* added = nullptr);
void resolveCollisions(Colliders colliders, const WeightedPoints& points, double t, VecX& x, VecX& v,
                       const VecX& inv_mass, const VecX* v_start = nullptr);

// Each cell's box in one state (WeightedPoints::cellBounds), computed when a collider first needs it: a plane never
// does. Cleared by its owner whenever the state changes.
class CellBoxes {
 public:
  void clear() { ready_ = false; }
  const std::vector<Eigen::AlignedBox3d>& of(const WeightedPoints& points, const VecX& x) {
    if (!ready_) points.cellBounds(x, boxes_);
    ready_ = true;
    return boxes_;
  }

 private:
  std::vector<Eigen::AlignedBox3d> boxes_;
  bool ready_ = false;
};

// The points whose blend of x collider.near(t, ., margin) keeps, in index order, into out, and their positions into
// at (particle(at, j) is point out[j]'s; at grows to fit and is never shrunk, so a step allocates nothing); cells
// holds the boxes of x's cells. Only the points of the cells the collider may be near are blended and asked: for a
// half-space (Collider::halfSpace), those whose blend of the particles' distances to the plane is within the margin
// (the distance is affine: the blend of the distances is the point's distance, to round-off), after the cells
// whose nearest particle is; for any other collider, the points of the cells whose box it may be near
// (Collider::mayBeNear). Every other point lies where near() keeps nothing, so the list is the one near() gives on
// every point's blend, at the cost of the few points by the collider. The tests are widened by round-off slack.
void nearPoints(const Collider& collider, double t, const WeightedPoints& points, const VecX& x, CellBoxes& cells,
                double margin, std::vector<int>& out, VecX& at);

}  // namespace wobble
