// Backward (implicit) Euler for mass-spring systems, after Baraff & Witkin 1998, "Large Steps in Cloth Simulation".
// The step solves M dv = h F(x0 + h (v0 + dv), v0 + dv), x1 = x0 + h (v0 + dv). By default with one Newton step
// linearized at the start state:
//   (M - h dF/dv - h^2 dF/dx) dv = h (F0 + h dF/dx v0),
// solved by Baraff & Witkin's modified conjugate gradients, preconditioned by 3x3 block-Jacobi plus, on large systems
// that need many iterations, an aggregation coarse level (filtered_pcg.h, coarse_correction.h), warm-started from the
// previous step's dv. The
// matrix has the Jacobians' fixed pattern (one 3x3 block per particle and per spring): sized once per topology, its
// values refilled in place every step; every loop runs over particle chunks or the pattern's schedule, so the result is
// the same bytes whatever the thread count. First order; A-stable and L-stable (unconditionally stable on linear
// springs, strongly damps the fast modes: amplitude factor 1/sqrt(1 + (omega h)^2) per step on an undamped oscillator).
// Contact forces are explicit: they enter through F0 = M a(t, x0, v0) and are held fixed over the step; the Jacobians
// (ForceJacobian, from the Dynamics) cover springs, dampers and drag. Constraints use B&W's filter S = blockdiag(S_i)
// inside the CG (particle_filter.h), solving S (A dv - b) = 0 with (I - S) dv = z: a pinned particle (inverse mass 0)
// has S_i = 0, dv_i = 0; a particle whose contact support is active at the start (ForceJacobian::contactConstraints)
// has S_i = I - n n^T and its normal dv prescribed (the surface's normal acceleration times h; on two surfaces at
// once S_i = d d^T, d the line both leave free, on three S_i = 0, every normal component prescribed: B&W section
// 5.3, contact/constraints/filter.h), which is what the explicit support force does instantaneously. Their friction is
// taken out of F0 as well and held in the solve (docs/contact.md): a contact whose static friction sticks at the start
// is held (S_i = 0, its tangential change the explicit law's), a sliding one slowed by a tangential damper of Coulomb's
// force at its start speed (frictionBlocks); after the solve, a hold or damper whose impulse exceeds mu times the
// normal impulse gives way to Coulomb's force and the step is solved again (boundFriction: Bridson, Fedkiw & Anderson
// 2002, "Robust treatment of collisions, contact and friction for cloth animation", section 7.2). Without that, the
// support sized to cancel a stiff spring's push at the start would act for the whole step while the spring relaxes and
// launch the body; for the same reason a support on a particle leaving its surface within the step (no constraint) is
// taken out of F0 (ReleasedSupport). Impacts likewise (B&W's constraints, here for collisions within the step): when
// the solved step would end a particle inside a surface, that particle is constrained along the normal to its
// restitution bounce (or what keeps it out) and the step is solved again, so the stiff springs pass the impulse to the
// body inside the implicit solve and no position is moved behind the solve's back (ForceJacobian::impactConstraints,
// docs/energy.md). Contact between bodies (ForceJacobian::bodyContacts, docs/body-contact.md) goes into the solve as
// well: every point-triangle and edge-edge pair whose gap, linearized at the step's start, the solved step would close
// gets a stiff one-sided quadratic penalty with its Jacobian (a stencil block of the matrix), the set of pressed pairs
// updated after each solve (an active set), and Coulomb friction as a tangential damper sized from the pressed pair's
// normal force (lagged, as IPC does: Li et al. 2020, "Incremental Potential Contact"). The penalty is convex, and
// backward Euler is the minimizer of the incremental potential (Gast et al. 2015, "Optimization integrator for large
// time steps"), so an exact step never gains energy through it; the pass after the step keeps only its collision
// impulses and impact zones (Bridson et al. 2002), the guarantee that nothing passes through. An embedded surface's
// points (a mesh jelly's, contact/colliders/weighted_points.h) meet colliders through the same penalty
// (ForceJacobian::colliderPairs: each point the step would end below a surface, against its tangent plane, its
// restitution's bounce a raised rest gap), their explicit supports taken out of F0 (ReleasedSupport): held from the
// step's start they made a resting mesh jelly hop. Options: cg_tolerance (relative residual |S (b - A dv)| / |S (b - A
// z)|, default in integrator.h), cg_error_fraction (below), cg_preconditioner (integrator.h) and cg_max_iterations of
// each linear solve (a solve that hits the limit is used as it stands, as Blender's cloth solver does; the achieved
// residual is in the stats); newton: after that first step, iterate Newton on the full nonlinear equations (contact
// still held at its start value) with a backtracking line search on the step's incremental potential, of which the step
// is the minimizer (Gast et al. 2015; as IPC's Newton iteration, Li et al. 2020: a Newton step that would raise it is
// not taken, so the iteration cannot make energy the potential does not have; line_search = residual: on the residual's
// norm; after each Newton step the pairs its end presses are searched for and the active set updated, as after a
// linearized solve), until max |M^-1 residual| <= newton_tolerance * max(1, max |v1|), at most newton_max_iterations
// linear solves (the damper's x-dependence is not in the Jacobian, so convergence is linear rather than quadratic when
// dampers act; it still converges to the exact backward-Euler step). The error rule (cg_error_fraction = eta > 0,
// without newton): the solve also stops once its error is at most eta times the step's own. Backward Euler's local
// error in v is about (h^2 / 2) a' ~ |dv_n - dv_(n-1)| / 2, estimated from the last two steps' velocity changes without
// an extra solve.
#pragma once
#include <cmath>
#include <vector>

#include "sim/integrators/backward_euler_pairs.h"
#include "sim/integrators/integrator.h"
#include "sim/solver/filtered_pcg.h"

namespace wobble {

// The step and its solves are in backward_euler.cpp; its contact (the constraints' friction, the impacts' and the
// pairs' further solves) in backward_euler_contact.cpp; the pairs' penalty in backward_euler_pairs.h.
class BackwardEuler final : public Integrator {
 public:
  explicit BackwardEuler(const IntegratorOptions& o);

  std::string_view name() const override { return "backward-euler"; }
  bool solvesBodyContact() const override { return options_.body_contact_in_solve; }
  bool linearizesItsStep() const override { return !options_.newton; }
  double contactWork() const override { return contact_work_; }

  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override;

 private:
  // The step (backward_euler.cpp).
  // A = M - h dF/dv - h^2 dF/dx at (x, v) (the filter acts inside the CG); with w, kw = dF/dx w.
  void assemble(const ForceJacobian& jacobian, double t, const VecX& x, const VecX& v, double h, const VecX* w,
                VecX* kw);
  // The error rule's bound on |S r| for this step (0: none), from the last two steps' dv (dv_ and previous_dv),
  // which it then shifts: previous_dv = dv_. Before dv_ is filtered and warm-started.
  double errorRuleTolerance(double h);
  // Whether h is the step of the error rule's history (within round-off: dv scales with h).
  bool sameStep(double h) const { return std::abs(h - error_.history_h) <= 1e-9 * h; }
  // Solves S (A y - b) = 0 from y (its filtered-out part kept); absolute: the error rule's bound on |S r| (0: none).
  void solve(const VecX& b, VecX& y, double absolute = 0);
  // A solve stopped at a tolerance leaves a residual r = S (b - A y) whose net force and torque are momentum made
  // from nothing: the exact solve's internal forces (springs, dampers, the pairs' penalty and friction between bodies)
  // are translation-invariant (A 1 = M 1) and, up to the h^2 geometric stiffness, rotation-invariant, and move none.
  // Removed by the correction on the rigid modes: y_p += delta + omega x (x_p - c), M delta = sum r_p,
  // I omega = sum (x_p - c) x r_p (M, c, I: the system's mass, centre of mass and inertia at the step's start), with
  // P^T A P taken as M and I (Galerkin on the rigid modes: exact for the linear momentum, to the geometric stiffness's
  // share for the angular). Where bodies touch in the solve (a step with contact pairs: its impulses are what a
  // residual's net force turns into momentum; a body in flight leaves a net force of 1e-9 of its momentum) and no
  // collider or pin acts (no particle held or constrained, no embedded point pressed on a collider): there momentum is
  // the bodies' own to keep, and a shift of the free particles alone would stretch their springs to the held ones,
  // which P^T A P = M does not see. docs/body-contact.md, "Momentum".
  void keepMomentum(VecX& y);
  // r = S (M dv - h (Fs(x0 + h (v0 + dv), v0 + dv) + Fc)); returns max |M^-1 r|. Leaves the trial state in the
  // Newton scratch's x1, v1.
  double residual(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v, const VecX& dv,
                  const VecX& mass, VecX& r);
  // The step's incremental potential at dv (backward_euler.cpp), for the trial state the last residual() left; NaN
  // where the Dynamics does not offer its share (ForceJacobian::stepPotential).
  double potential(const ForceJacobian& jacobian, double h, const VecX& dv, const VecX& mass);
  // Newton on the nonlinear backward-Euler equations from the linearized step in dv_, with a backtracking line search
  // on the incremental potential (options_.line_search). until_energy_kept: stop as soon as the iterate no longer
  // makes up energy (madeUpEnergy), before convergence.
  void newton(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v, const VecX& mass,
              bool until_energy_kept = false);
  // Whether the step's end x + h (v + dv), v + dv has more energy than the start gives it (ForceJacobian::
  // energyMadeUp).
  bool madeUpEnergy(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v);
  // The step's end for the solved dv: end_v_ = v + dv, end_x_ = x + h end_v_.
  void setEnd(double h, const VecX& x, const VecX& v);

  // Contact (backward_euler_contact.cpp).
  // Kinetic friction of the contacts sliding at the step's start; sets sliding_, adds their forces at v to rhs_ and
  // their weights to the matrix.
  void frictionBlocks(double h, const VecX& v);
  // matrix_.self() += h c for every sliding contact whose normal the filter removes (after an assembly).
  void addFrictionWeights(double h);
  // A sliding contact's damper (ContactConstraint::damping) into sliding_, its weight into the matrix and its force at
  // v into rhs_.
  void addSliding(const ContactConstraint& c, double h, const VecX& v, bool bounded = false);
  // After a solve: the holds and dampers whose friction impulse is over Coulomb's cone given way to Coulomb's force
  // and the step solved again (backward_euler_contact.cpp); returns whether it solved.
  bool boundFriction(const ForceJacobian& jacobian, double h, const VecX& x, const VecX& v, double absolute);
  // After the filter is rebuilt for impacts: a sliding contact whose normal it no longer removes leaves the matrix.
  void dropFreedFriction(double h);
  // The tangential part of the particle's velocity in v relative to the surface at the step's end, (I - n n^T)(v -
  // u1): what the sliding contact's damper acts on.
  static Vec3 tangentialSlide(const ContactConstraint& c, double h, const VecX& v);
  // The pairs' terms (PenaltyPairs::update) for the solved end x1.
  std::size_t updatePairs(const ForceJacobian& jacobian, double h, const VecX& x0, const VecX& x1, bool first);
  // At the solved end end_x_: the pairs it presses searched for (colliders' and between bodies) and the active set
  // updated (updatePairs); returns how many pairs changed, settled: fewer than kSettledShare of those within reach.
  std::size_t pressPairs(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v,
                         bool& settled);
  // The active pairs' terms into the matrix and the right-hand side (PenaltyPairs::apply).
  void applyPairs(double h, const VecX& x, const VecX& v);
  // The further solves while the solved step ends a particle inside a surface or changes which pairs are pressed.
  void solveImpacts(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v, double absolute);
  // Whether contact acted in the step so far: constraints on colliders or pairs between bodies, or a further solve
  // (an impact, a change of pairs).
  bool contactActed() const {
    return stats_.last_linear_solves > 1 || !contacts_.empty() || !released_.empty() || !pairs_.empty();
  }

  // Armijo's sufficient decrease: a Newton step is taken once it lowers the potential by this share of its slope's
  // prediction (Nocedal & Wright's usual 1e-4).
  static constexpr double kArmijo = 1e-4;
  // The relative rounding of the potential's sums over particles and springs (far above double's 1e-16: a million
  // terms of either sign), which a line search's comparison forgives.
  static constexpr double kPotentialRounding = 1e-10;
  static constexpr int kImpactPasses = 4;
  static constexpr int kBodyPasses = 8;  // ... when bodies touch
  // A later check that changes the activity of fewer than this share of the step's pairs ends the step (solveImpacts;
  // measured in docs/performance.md).
  static constexpr double kSettledShare = 0.003;

  struct SlidingContact {
    ContactConstraint contact;
    bool in_matrix;        // its damper is in the matrix (dropFreedFriction)
    bool bounded = false;  // boundFriction's, in place of Coulomb's force turned against the slip: kept as it is
  };
  // The error rule's history (errorRuleTolerance).
  struct ErrorRule {
    VecX previous_dv;  // the step before's dv
    int history = 0;   // steps (at most 2) whose dv is in dv_ and previous_dv, all with step history_h
    double history_h = 0;
    double lightest = 0;  // the lightest free particle's mass (m_min)
    std::vector<double> sums;
  };
  // Newton's iterates and residuals (newton, residual).
  struct NewtonScratch {
    VecX fs, fc, r, x1, v1, delta, trial, trial_r;
    VecX v_rest, f_rest, f_damped, f_delta;  // the dampers' forces along the line search's direction
  };
  // The rigid-mode correction's inputs (keepMomentum).
  struct MomentumCorrection {
    using Sums = Eigen::Matrix<double, 16, 1>;
    const VecX* x = nullptr;  // the step's start positions
    const VecX* mass = nullptr;
    bool pinned = false;     // some particle has inverse mass 0
    std::vector<Sums> sums;  // per chunk
  };

  IntegratorOptions options_;
  PairBlockMatrix matrix_;
  ParticleFilter filter_;
  FilteredPcg pcg_;
  int n_ = 0;
  bool parallel_ = false;
  bool two_level_ = false;  // cg_preconditioner auto: the next solve's choice
  std::vector<ContactConstraint> contacts_;
  std::vector<ReleasedSupport> released_;
  // The contacts sliding at the step's start (frictionBlocks), and those boundFriction gave a damper.
  std::vector<SlidingContact> sliding_;
  // A contact whose friction boundFriction bounded by Coulomb's constant force (in rhs_ and f0_), or by a damper once
  // that force turned against the slip.
  struct CoulombFriction {
    ContactConstraint contact;
    Vec3 force;  // N
    bool damped = false;
  };
  std::vector<CoulombFriction> coulomb_;
  // Friction beyond Coulomb's cone, as boundFriction finds it in a pass: a hold (contacts_[index]), a damper
  // (sliding_[index]) or a pair's damper (pairs_'s pair index) whose friction impulse exceeds mu times the normal one,
  // and Coulomb's force that would take its place.
  struct ExcessFriction {
    enum Kind { Hold, Damper, Pair };
    int index;
    Kind kind;
    Vec3 force;  // N
  };
  std::vector<ExcessFriction> excess_friction_;
  std::vector<Sym3> diagonal_;  // the matrix's diagonal blocks, for boundFriction's measure of an excess
  VecX friction_product_;       // boundFriction's A dv
  // boundFriction's per body: its holds' and dampers' friction impulses, their cones' bounds, its free mass.
  std::vector<Vec3> body_net_;
  std::vector<double> body_capacity_, body_mass_;
  PenaltyPairs pairs_;  // this step's contact pairs and the last step's pressed ones
  VecX f0_, kv_, rhs_, dv_;
  VecX end_x_, end_v_;  // the candidate step's end state, for impacts
  ErrorRule error_;
  NewtonScratch newton_;
  MomentumCorrection momentum_;
  bool contact_before_ = false;  // contact acted in the last step (the energy check's trigger, step)
  double contact_work_ = 0;      // J: the pairs' penalty's work over the last step (contactWork)
};

}  // namespace wobble
