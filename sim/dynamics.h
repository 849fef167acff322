// What an integrator sees of a physical system: accelerations as a function of time and flat state, and, for
// implicit integrators, an optional linearization of the forces.
#pragma once
#include <algorithm>
#include <array>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/SparseCore>

#include "sim/solver/stencil.h"
#include "sim/types.h"

namespace wobble {

class PairBlockMatrix;
class PairSchedule;

using Triplets = std::vector<Eigen::Triplet<double>>;

// A particle held by a surface at a state: its contact support force is active there. Implicit integrators turn the
// support into a velocity constraint over the step (Baraff & Witkin's filter; a particle on several surfaces at once
// gets one per surface, their normals intersected: particle_filter.h), because a support force sized to
// cancel a stiff spring's push at the start, held for a whole long step while the spring relaxes, launches the body.
struct ContactConstraint {
  int particle;
  Vec3 normal;  // unit, out of the surface
  // The particle's normal velocity changes by h times this over the step: the surface's normal acceleration for a
  // resting contact; for an impact (addImpactConstraints), the change that gives it its bounce.
  double normal_acceleration;
  // The surface's index among the system's colliders: at most one constraint per particle and surface.
  int collider = 0;
  bool impact = false;  // from addImpactConstraints (else a resting contact at the step's start)
  // Friction of a resting contact (contact/constraints/constraints.h), which an implicit step must not hold as the
  // explicit force the accelerations add: sized to cancel the springs' tangential pull at the start, held for a whole
  // long step while they relax, it drives the body (a cloth landing on a floor with friction 0.5 gained 60 000 J in a
  // step).
  Vec3 friction = Vec3::Zero();  // N: the friction force the accelerations add at the start (taken out of it)
  // Static friction holds at the start: the particle's tangential velocity changes by h times this too (it is
  // held), the explicit law's rate: the surface's tangential acceleration, less the relative tangential velocity
  // over the stick time (2 h of the system's step, contact/colliders/response.h).
  bool stick = false;
  Vec3 tangential_acceleration = Vec3::Zero();  // m/s^2, with stick
  // Sliding at the start: kinetic friction as a damper on the tangential velocity relative to the surface at the
  // step's end, -damping (I - n n^T) (v1 - u1), u1 = surface_velocity + h surface_acceleration: linear in v, so
  // exact in the step and dissipative.
  double damping = 0;  // N s/m
  // m/s: below this relative tangential speed the damper is sized as at this speed (the friction between bodies in
  // backward Euler's solve takes the same, PenaltyPairs::kStickSpeed).
  static constexpr double kStickSpeed = 1e-3;
  // Coulomb's constant force turned with the slip (it would do positive work) gives way to a damper of the same force
  // at that slip, which only takes energy out: |force| / max(|slide|, kStickSpeed); 0 while it opposes the slip.
  // backward Euler's friction on colliders and between bodies alike (BackwardEuler::boundFriction).
  static double turnedDamping(const Vec3& force, const Vec3& slide) {
    return slide.dot(force) > 0 ? force.norm() / std::max(slide.norm(), kStickSpeed) : 0;
  }
  // Coulomb's cone, which backward Euler keeps the hold and the damper within over the step (boundFriction): the
  // surface's coefficient and the support the accelerations apply at the start (in the start force).
  double mu = 0;
  double support = 0;  // N
  Vec3 surface_velocity = Vec3::Zero(), surface_acceleration = Vec3::Zero();
};

// A support that the accelerations apply at a step's start but an implicit step must not hold
// (contact/constraints/constraints.h): the particle is leaving the surface. The solver takes force (support and
// friction, N) back out of its start force.
struct ReleasedSupport {
  int particle;
  Vec3 force;
};

// Two surface elements of bodies near each other in an implicit step (contact between bodies, docs/body-contact.md): a
// point against a triangle or an edge against an edge, as a stencil of particles with weights w such that sum w_i x_i
// is the relative position (sim/contact/distance/primitives.h): four particles for surfaces over particles, up to 32
// when the elements' vertices are blends of particles (a mesh jelly's embedded surface, sim/solver/stencil.h). At the
// step's start their nearest points are along the unit normal n (from the second element to the first); the pair's
// gap g(x) = n . sum w_i x_i - thickness, linear in x over the step, is kept >= 0 by a stiff penalty inside backward
// Euler's solve (backward_euler.cpp). The same serves an embedded point against a collider (colliderPairs, below):
// the stencil is the point's 8 particles, and the surface's offset comes off the gap.
struct ContactPair {
  // Default-constructed pairs (a list resized before threads fill it) are left unwritten but for the stencil's size and
  // pointers and the fields below with initializers: without a constructor of its own, resizing a list would zero
  // every pair first, on one thread.
  ContactPair() {}
  ContactPair(const std::array<int, 4>& e, WeightedStencil s, const Vec3& n, double thickness_m, double friction_mu)
      : element(e), stencil(std::move(s)), normal(n), thickness(thickness_m), friction(friction_mu) {}

  std::array<int, 4> element;  // the pair's surface vertices in the pass that found it: its identity there
  WeightedStencil stencil;
  Vec3 normal;
  double thickness;  // m
  double friction;   // Coulomb coefficient
  // An embedded point against a collider (ForceJacobian::colliderPairs): the surface's offset along the normal (its
  // tangent plane at the step's end: the gap is the point's height above it), and the least rise of the gap over the
  // step that the point's restitution asks (h times the normal velocity it leaves with); both 0 between bodies.
  bool collider = false;
  double surface = 0, rise = 0;
  Vec3 relative(const VecX& y) const { return stencil.sum(y); }  // sum w_i y_i
  double gap(const VecX& x) const { return normal.dot(relative(x)) - surface - thickness; }
};

// The rest gap of backward Euler's penalty on a pair whose gap at the step's start is start_gap: 0, or for a pair
// already within the thickness all but `recovery` of its overlap (backward_euler.cpp, updatePairs).
inline double penaltyRestGap(double start_gap, double recovery) { return std::min(0.0, start_gap) * (1 - recovery); }

// The band around a pair's rest gap within which backward Euler's active set leaves its activity as it is: slack times
// the pair's distance at the step's start (thickness + start_gap), at most slack times the thickness. Scaled by the
// distance left, not the thickness alone: a band of a quarter of the thickness around the rest gap of a pair nearly
// touching reaches past contact, so the solve could never press it and would leave it to the pass after the step,
// whose impulses on the touching particles alone feed a resting stack energy every step (docs/body-contact.md, "Rest").
inline double activeSlack(double slack, double start_gap, double thickness) {
  return slack * std::clamp(thickness + start_gap, 0.0, thickness);
}

// Which of the pairs within reach a search for an implicit solve hands over (ForceJacobian::bodyContacts). A pair
// the solve does not press contributes nothing to it, and every check after a solve searches again: so backward
// Euler takes into a step's first solve only the pairs the last step left pressed, and after a solve only the pairs
// its end presses, instead of every pair within reach to be checked at each solve's end (docs/body-contact.md).
struct PairJoin {
  // Set: only the pairs of these elements (ContactPair::element, ascending).
  const std::vector<std::array<int, 4>>* only = nullptr;
  // Else, when pressed: only the pairs whose gap at the end lies below their rest gap (penaltyRestGap) by more than
  // their activeSlack (backward Euler's active set).
  bool pressed = false;
  double recovery = 0, slack = 0;
  // Out: how many pairs within reach, not in the list yet, the search held back (what the list would hold more had
  // every one been handed over: the solver's stop rule counts them).
  std::size_t held_back = 0;

  // Whether a pair within reach is handed over: its element, its gap at the start and at the end, its thickness.
  bool hands(const std::array<int, 4>& element, double start_gap, double end_gap, double thickness) const {
    if (only) return std::binary_search(only->begin(), only->end(), element);
    return !pressed || end_gap < penaltyRestGap(start_gap, recovery) - activeSlack(slack, start_gap, thickness);
  }
};

// Optional capability of a Dynamics, for implicit integrators: the lumped (diagonal) mass and the smooth forces with
// their Jacobians. Smooth means every force except contact (support and friction): those are not differentiable,
// so implicit methods take them explicitly, from Dynamics::acceleration at the step's start state.
// The Jacobians have a fixed pattern: the smooth forces couple particles only in the pairs of jacobianPattern()
// (springs), each pair e = (a, b) with one symmetric block, dFa/dxa = dFb/dxb = -dFa/dxb = -dFb/dxa (likewise for v),
// plus each particle's own terms (drag). Implicit solvers size their matrices once per pattern and refill them.
class ForceJacobian {
 public:
  // Mass per particle, and inverse mass, which is 0 for a pinned particle (implicit solvers filter those out).
  virtual const VecX& mass() const = 0;
  virtual const VecX& inverseMass() const = 0;
  // f = the smooth forces at (t, x, v), 3 per particle (resized).
  virtual void smoothForce(double t, const VecX& x, const VecX& v, VecX& f) const = 0;
  // The pairs the Jacobians couple, fixed per topology (the same object for as long as the topology stands).
  virtual const PairSchedule& jacobianPattern() const = 0;
  // Refills a (reset to jacobianPattern()) with -(cx dF/dx + cv dF/dv) at (t, x, v): symmetric and positive
  // semidefinite for cx, cv >= 0, so M plus it is positive definite. With w, also sets kw = dF/dx w.
  virtual void fillJacobian(double t, const VecX& x, const VecX& v, double cx, double cv, PairBlockMatrix& a,
                            const VecX* w = nullptr, VecX* kw = nullptr) const = 0;
  // Whether solvers should run their loops on threads for this system (parallel.h); the result is the same bytes.
  virtual bool parallel() const { return false; }
  // The first particle of each body, ascending from 0: a body's particles run to the next one's first. The default:
  // the whole system is one body.
  virtual const std::vector<int>& bodyFirsts() const {
    static const std::vector<int> kOne{0};
    return kOne;
  }
  // Replaces out by the particles whose contact support is active at (t, x, v), one per particle and surface; and
  // released (when given) by the supports the accelerations apply to particles leaving their surface, and those of
  // embedded points, which colliderPairs holds instead (each handed to its particles by the point's weights). The
  // default is none: contact, if any, then stays an explicit force in the accelerations.
  virtual void contactConstraints(double t, const VecX& x, const VecX& v, std::vector<ContactConstraint>& out,
                                  std::vector<ReleasedSupport>* released = nullptr) const {
    (void)t, (void)x, (void)v;
    out.clear();
    if (released) released->clear();
  }
  // Impacts of a candidate step from (x0, v0) at t to (x1, v1) at t + h: adds to out (kept in particle order) a
  // constraint for every particle the step ends inside a surface, with the normal velocity change that keeps it out
  // and gives it its bounce (contact/constraints/constraints.h). Returns whether out changed; the solver then solves
  // again. The default finds none.
  virtual bool impactConstraints(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1, const VecX& v1,
                                 std::vector<ContactConstraint>& out) const {
    (void)t, (void)h, (void)x0, (void)v0, (void)x1, (void)v1, (void)out;
    return false;
  }
  // Contact between bodies for a candidate step from x0 to x1: appends to out the pairs of surface elements not yet in
  // it whose gap (ContactPair) would end the step below 0 (those within reach), as far as join lets them, each with
  // its normal and weights from x0 (so a pair found again is the same pair). Returns whether out grew; the solver then
  // solves again with the pairs' penalty (the default: none).
  virtual bool bodyContacts(const VecX& x0, const VecX& x1, std::vector<ContactPair>& out, PairJoin& join) const {
    (void)x0, (void)x1, (void)out, (void)join;
    return false;
  }
  // Contact of embedded points (contact/colliders/weighted_points.h) with colliders for a candidate step from x0 at t
  // to x1 at t + h: appends to out, as pairs for the same penalty, every point not yet in it that x1 ends within a
  // surface's contact band (epsilon) or below it (element {-1 - collider, point, 0, 0}, apart from the pairs between
  // bodies), with its restitution's rise from its approach speed at (x0, v0). Returns whether out grew (the default:
  // none). Their explicit supports are released (contactConstraints).
  virtual bool colliderPairs(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                             std::vector<ContactPair>& out) const {
    (void)t, (void)h, (void)x0, (void)v0, (void)x1, (void)out;
    return false;
  }
  // The energy a candidate step from (x0, v0) at t to (x1, v1) at t + h makes up: the total energy's rise (kinetic,
  // gravitational, elastic) less the work moving colliders did, less a margin for the step's rounding and estimates.
  // Above 0, the step gained energy nothing gave it (backward Euler, having linearized it, then solves it exactly).
  // The default: none known.
  virtual double energyMadeUp(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                              const VecX& v1) const {
    (void)t, (void)h, (void)x0, (void)v0, (void)x1, (void)v1;
    return 0;
  }
  // The smooth forces' share of backward Euler's incremental potential at a candidate end (x1, v1) of a step of size h
  // (Gast et al. 2015, "Optimization integrator for large time steps") that is a function of x1 alone: the elastic and
  // gravitational energy at x1, whose gradient is minus the smooth force at (x1, 0). The dampers' and drag's share,
  // linear in v1 with the springs' directions held, the integrator takes from smoothForce at v1 and at 0 (h and v1
  // are for a system that has more to add). Backward Euler's Newton iteration backtracks on the whole
  // (backward_euler.h). NaN, the default: not offered (the line search then backtracks on the residual).
  virtual double stepPotential(double h, const VecX& x1, const VecX& v1) const {
    (void)h, (void)x1, (void)v1;
    return std::numeric_limits<double>::quiet_NaN();
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
