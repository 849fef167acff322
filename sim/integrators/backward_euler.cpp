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
// 5.3, contact_filter.h), which is what the explicit support force does instantaneously. Their friction is taken
// out of F0 as well and held in the solve (docs/contact.md): a contact whose static friction sticks at the start is
// held (S_i = 0, its tangential change the explicit law's), a sliding one slowed by a tangential damper of Coulomb's
// force at its start speed (frictionBlocks).
// Without that, the support sized to cancel a stiff spring's push at the start would act for the whole step while the
// spring relaxes and launch the body; for the same reason a support on a particle leaving its surface within the step
// (no constraint) is taken out of F0 (ReleasedSupport). Impacts
// likewise (B&W's constraints, here for collisions within the step): when the solved step would end a particle inside
// a surface, that particle is constrained along the normal to its restitution bounce (or what keeps it out) and the
// step is solved again, so the stiff springs pass the impulse to the body inside the implicit solve and no position
// is moved behind the solve's back (ForceJacobian::impactConstraints, docs/energy.md). Contact between bodies
// (ForceJacobian::bodyContacts, docs/body-contact.md) goes into the solve as well: every point-triangle and edge-edge
// pair whose gap, linearized at the step's start, the solved step would close gets a stiff one-sided quadratic
// penalty with its Jacobian (a stencil block of the matrix), the set of pressed pairs updated after each solve (an
// active set), and Coulomb friction as a tangential damper sized from the pressed pair's normal force (lagged, as IPC
// does: Li et al. 2020, "Incremental Potential Contact"). The penalty is convex, and backward Euler is the minimizer of
// the incremental potential (Gast et al. 2015, "Optimization integrator for large time steps"), so an exact step never
// gains energy through it; the pass after the step keeps only its collision impulses and impact zones (Bridson et al.
// 2002), the guarantee that nothing passes through. An embedded surface's points (a mesh jelly's, weighted_points.h)
// meet colliders through the same penalty (ForceJacobian::colliderPairs: each point the step would end below a
// surface, against its tangent plane, its restitution's bounce a raised rest gap), their explicit supports taken out
// of F0 (ReleasedSupport): held from the step's start they made a resting mesh jelly hop. Options:
// cg_tolerance (relative residual |S (b - A dv)| / |S (b - A z)|, default in integrator.h), cg_error_fraction (below),
// cg_preconditioner (integrator.h) and cg_max_iterations of each linear solve (a solve that hits the limit is used as
// it stands, as Blender's cloth solver does; the achieved residual is in the stats); newton: after that first step,
// iterate Newton on the full nonlinear equations (contact still held at its start value) with a backtracking line
// search on the residual, until max |M^-1 residual| <= newton_tolerance * max(1, max |v1|), at most
// newton_max_iterations linear solves (the damper's x-dependence is not in the Jacobian, so convergence is linear
// rather than quadratic when dampers act; it still converges to the exact backward-Euler step). The error rule
// (cg_error_fraction = eta > 0, without newton): the solve also stops once its error is at most eta times the step's
// own. Backward Euler's local error in v is about (h^2 / 2) a' ~ |dv_n - dv_(n-1)| / 2; the last two steps' velocity
// changes estimate it, when both had this h and none of the last three steps had a contact constraint (contact impulses
// make dv jump from step to step with no smooth error to match: on a jelly resting on the elevator the estimate let the
// solve's error reach half the method's). The solve's error e = A^-1 r has |e| <= |r| / m_min, since A = M - h df/dv -
// h^2 df/dx >= M (the spring and damper blocks are positive semidefinite, force_jacobian.h) on the filter's subspace.
// So it stops at |S r| <= eta m_min |dv_n-1 - dv_n-2| / 2, or at cg_tolerance if that is looser: the solver's error
// stays a fraction of the method's, at every step size (as implicit ODE codes tie their linear solves to the local
// error test), and stiff steps, whose error is large, need fewer iterations. Throws std::invalid_argument if the
// Dynamics offers no ForceJacobian.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "sim/contact_filter.h"
#include "sim/integrators/methods.h"
#include "sim/solver/filtered_pcg.h"
#include "sim/solver/parallel.h"

namespace wobble {
namespace {

class BackwardEuler final : public Integrator {
 public:
  explicit BackwardEuler(const IntegratorOptions& o) : options_(o) {
    if (!(o.cg_tolerance > 0) || o.cg_max_iterations < 1)
      throw std::invalid_argument("backward-euler: cg_tolerance must be > 0 and cg_max_iterations >= 1");
    if (!(o.cg_error_fraction >= 0)) throw std::invalid_argument("backward-euler: cg_error_fraction must be >= 0");
    if (o.newton && (!(o.newton_tolerance > 0) || o.newton_max_iterations < 1))
      throw std::invalid_argument("backward-euler: newton_tolerance must be > 0 and newton_max_iterations >= 1");
  }

  std::string_view name() const override { return "backward-euler"; }
  bool solvesBodyContact() const override { return options_.body_contact_in_solve; }
  bool linearizesItsStep() const override { return !options_.newton; }

  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override {
    const ForceJacobian* jacobian = dynamics.forceJacobian();
    if (!jacobian)
      throw std::invalid_argument(
          "backward-euler needs force Jacobians, and this Dynamics offers none (Dynamics::forceJacobian() is null)");
    if (3 * jacobian->mass().size() != x.size())
      throw std::invalid_argument("backward-euler: state size does not match the system's mass");
    ++stats_.steps;
    stats_.last_cg_iterations = 0;
    stats_.last_linear_solves = 0;
    stats_.last_residual = 0;
    stats_.last_cg_residual = 0;
    n_ = static_cast<int>(x.size() / 3);
    parallel_ = jacobian->parallel();
    if (!matrix_.fits(jacobian->jacobianPattern())) {  // a new topology: size the matrix once
      matrix_.reset(jacobian->jacobianPattern());
      contacts_.reserve(jacobian->mass().size());  // one per particle and surface it touches: most touch one
      sliding_.reserve(jacobian->mass().size());
      dv_.resize(0);  // no warm start, no error estimate
      history_ = 0;
      carried_.clear();  // their particles' numbers are another topology's
      const int n = static_cast<int>(jacobian->mass().size());
      sums_.reserve((n + particleChunk(n) - 1) / particleChunk(n));  // a sum per chunk (parallel.h)
      lightest_ = std::numeric_limits<double>::infinity();           // the lightest free particle's mass
      for (Eigen::Index p = 0; p < jacobian->mass().size(); ++p)
        if (jacobian->inverseMass()[p] > 0) lightest_ = std::min(lightest_, jacobian->mass()[p]);
      ++stats_.pattern_setups;
    }
    const VecX& mass = jacobian->mass();
    filter_.reset(jacobian->inverseMass());
    jacobian->contactConstraints(t, x, v, contacts_, &released_);
    constrainFilter(contacts_, filter_);

    // F0 = M a0: every force, contact included, at the start state.
    ++stats_.evaluations;
    dynamics.acceleration(t, x, v, f0_);
    // A support on a particle leaving its surface would act for the whole step (contact_constraints.h): taken out.
    for (const ReleasedSupport& r : released_)
      particle(f0_, r.particle) -= jacobian->inverseMass()[r.particle] * r.force;
    // Friction likewise (ContactConstraint::friction): the filter holds a sticking contact, a damper in the solve
    // slows a sliding one (frictionBlocks).
    for (const ContactConstraint& c : contacts_)
      if (c.friction != Vec3::Zero()) particle(f0_, c.particle) -= jacobian->inverseMass()[c.particle] * c.friction;
    // Linearized step at (x0, v0): A dv = h (F0 + h dF/dx v0), with dv's filtered-out part prescribed.
    assemble(*jacobian, t, x, v, h, &v, &kv_);
    rhs_.resize(x.size());
    if (dv_.size() != x.size()) dv_.setZero(x.size());  // else warm start from the last step's dv
    const double absolute = errorRuleTolerance(h);
    forEachChunk(n_, parallel_, [&](int begin, int end) {
      for (int p = begin; p < end; ++p) {
        particle(rhs_, p) = h * (mass[p] * particle(f0_, p) + h * particle(kv_, p));
        particle(dv_, p) = filter_.apply(p, particle(dv_, p));
      }
    });
    frictionBlocks(h, v);
    addPrescribedChange(contacts_, filter_, h, dv_);
    // Contact between bodies: of the pairs near the predicted end x0 + h (v0 + dv), dv the warm start (the last step's
    // velocity change), those the last step ended pressed (a resting body's every step) go active into the first
    // solve; the others join as the solves' ends press them (PairJoin: each check searches again, so a pair held
    // back costs nothing but its test). Not the explicit flight x0 + h (v0 + h a0): with stiff springs a0 is huge
    // wherever they are stretched (2e5 m/s^2 in a crumpling cloth's folds), and that flight would close the gap of a
    // hundred thousand pairs far apart.
    pairs_.clear();
    terms_.clear();
    matrix_.stencils().clear();
    rhs_saved_ = false;
    end_x_.resize(x.size());
    forEachChunk(n_, parallel_, [&](int begin, int end) {
      for (int p = begin; p < end; ++p) particle(end_x_, p) = particle(x, p) + h * (particle(v, p) + particle(dv_, p));
    });
    carried_elements_.clear();
    for (const CarriedPair& c : carried_) carried_elements_.push_back(c.element);
    PairJoin first{.only = &carried_elements_};
    const bool body_pairs = options_.body_contact_in_solve && jacobian->bodyContacts(x, end_x_, pairs_, first);
    if ((jacobian->colliderPairs(t, h, x, v, end_x_, pairs_) || body_pairs) &&
        updatePairs(*jacobian, h, x, end_x_, true))
      applyPairs(h, x, v);
    solve(rhs_, dv_, absolute);
    solveImpacts(*jacobian, t, h, x, v, absolute);
    if (!pairs_.empty()) {
      ++stats_.body_contact_steps;
      stats_.body_contact_pairs_carried += long(pairs_.size());
    }

    if (options_.newton) {
      newton(*jacobian, t, h, x, v, mass);
    } else {
      // A linearized step that made up energy (a spring shortened or turned by much of its length within the step,
      // where its linearization at the start is far off): the exact step instead, by Newton's iteration from it.
      // Checked where the step solved more than once: an impact or contact pairs changed its velocities within it,
      // which is where the linearization failed (docs/energy.md); a smooth step pays nothing.
      if (stats_.last_linear_solves > 1 && madeUpEnergy(*jacobian, t, h, x, v)) {
        ++stats_.exact_steps;
        history_ = 0;  // this step's dv is Newton's: not the smooth error's measure
        newton(*jacobian, t, h, x, v, mass, true);
      }
    }
    carryPairs(h, x, v);

    forEachChunk(n_, parallel_, [&](int begin, int end) {
      for (int p = begin; p < end; ++p) {
        particle(x, p) += h * (particle(v, p) + particle(dv_, p));
        particle(v, p) += particle(dv_, p);
      }
    });
  }

 private:
  // A = M - h dF/dv - h^2 dF/dx at (x, v) (the filter acts inside the CG); with w, kw = dF/dx w.
  void assemble(const ForceJacobian& jacobian, double t, const VecX& x, const VecX& v, double h, const VecX* w,
                VecX* kw) {
    ++stats_.jacobians;
    jacobian.fillJacobian(t, x, v, h * h, h, matrix_, w, kw);
    const VecX& mass = jacobian.mass();
    forEachChunk(n_, parallel_, [&](int begin, int end) {
      for (int p = begin; p < end; ++p) matrix_.self()[p] += mass[p];
    });
  }

  // Kinetic friction of the contacts sliding at the step's start (ContactConstraint::damping): the damper
  // F_p = -c P (v_p - u1), P = I - n n^T, its Jacobian h c P in the matrix (exact over the step, positive
  // semidefinite: it only takes energy out), its start force in the right-hand side. Baraff & Witkin (1998) hold
  // contacts by the filter and leave friction explicit; an explicit friction sized from the start's forces and held for
  // a 1/60 s step while the springs relax pushed a landing cloth sideways and stretched it (docs/contact.md). The
  // matrix takes h c P as h c on the particle's own weight (self: one number a particle): the filter removes the
  // normal n from the solve (S = I - n n^T, or on two surfaces the line both leave free), where P and I agree, and
  // the prescribed normal change z along n meets S (h c z) = 0 either way. Sets sliding_ and adds the forces at v to
  // rhs_ and the weights to the matrix.
  void frictionBlocks(double h, const VecX& v) {
    sliding_.clear();
    for (const ContactConstraint& c : contacts_) {
      if (c.stick || !(c.damping > 0)) continue;
      sliding_.push_back({c, true});
      particle(rhs_, c.particle) -= (h * c.damping) * tangentialSlide(c, h, v);
    }
    addFrictionWeights(h);
  }
  // matrix_.self() += h c for every sliding contact whose normal the filter removes (after an assembly).
  void addFrictionWeights(double h) {
    for (const SlidingContact& s : sliding_)
      if (s.in_matrix) matrix_.self()[s.contact.particle] += h * s.contact.damping;
  }
  // After the filter is rebuilt for impacts: a sliding contact whose normal it no longer removes (its constraint gone
  // with an impact, contact_constraints.h) leaves the matrix, where h c would damp its normal velocity too; its
  // friction stays the start's force in the right-hand side (at most Coulomb's).
  void dropFreedFriction(double h) {
    for (SlidingContact& s : sliding_)
      if (s.in_matrix && filter_.apply(s.contact.particle, s.contact.normal).squaredNorm() > 1e-12) {
        matrix_.self()[s.contact.particle] -= h * s.contact.damping;
        s.in_matrix = false;
      }
  }
  // The tangential part of the particle's velocity in v relative to the surface at the step's end, (I - n n^T)(v -
  // u1): what the sliding contact's damper acts on.
  static Vec3 tangentialSlide(const ContactConstraint& c, double h, const VecX& v) {
    const Vec3 u = particle(v, c.particle) - (c.surface_velocity + h * c.surface_acceleration);
    return u - c.normal.dot(u) * c.normal;
  }

  // Whether the step's end x + h (v + dv), v + dv has more energy than the start gives it (ForceJacobian::
  // energyMadeUp).
  bool madeUpEnergy(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v) {
    setEnd(h, x, v);
    return jacobian.energyMadeUp(t, h, x, v, end_x_, end_v_) > 0;
  }
  // The step's end for the solved dv: end_v_ = v + dv, end_x_ = x + h end_v_.
  void setEnd(double h, const VecX& x, const VecX& v) {
    end_x_.resize(x.size());
    end_v_.resize(x.size());
    forEachChunk(n_, parallel_, [&](int begin, int end) {
      for (int p = begin; p < end; ++p) {
        particle(end_v_, p) = particle(v, p) + particle(dv_, p);
        particle(end_x_, p) = particle(x, p) + h * particle(end_v_, p);
      }
    });
  }

  // Impacts (contact_constraints.h): while the solved step ends a particle inside a surface, constrain it along the
  // normal to its bounce and solve again (warm-started), so the springs share its impulse with the body within the
  // step; likewise while it ends two bodies' surface elements within their thickness (ForceJacobian::bodyContacts:
  // the pairs' penalty, addPairs). At most kImpactPasses more solves (what still ends inside is lifted by the step
  // end's projection, what still ends too near is the post-step pass's). Between bodies, a check that changes the
  // activity of fewer than kSettledShare of the step's pairs (new pressed pairs included) and finds no impact ends the
  // step with the last solve, the first check included (docs/body-contact.md, "Cost"): on a landing cloth the checks
  // past the first few flipped tens of pairs among tens of thousands, and on a cloth lying collapsed on itself the
  // first check a few tens among 95 000, each at the price of a solve; what they leave is the post-step pass's.
  void solveImpacts(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v, double absolute) {
    for (int pass = 0; pass < (pairs_.empty() ? kImpactPasses : kBodyPasses); ++pass) {
      setEnd(h, x, v);
      const bool impacts = jacobian.impactConstraints(t, h, x, v, end_x_, end_v_, contacts_);
      const bool found = jacobian.colliderPairs(t, h, x, v, end_x_, pairs_);
      PairJoin pressed{.pressed = true, .recovery = kRecovery, .slack = kActiveSlack};
      const std::size_t changes =
          ((options_.body_contact_in_solve && jacobian.bodyContacts(x, end_x_, pairs_, pressed)) || found ||
           !pairs_.empty())
              ? updatePairs(jacobian, h, x, end_x_, false)
              : 0;
      // Of the pairs within reach, handed over or not (the solve's are a few of them: PairJoin).
      const bool settled = double(changes) < kSettledShare * double(pairs_.size() + pressed.held_back);
      if (!impacts && (changes == 0 || settled)) return;
      const bool pairs = changes > 0;
      history_ = 0;  // this step's dv carries impulses: not the smooth error's measure
      if (impacts) {
        ++stats_.impact_solves;
        filter_.reset(jacobian.inverseMass());  // afresh: an impact replaces a resting contact's constraint
        constrainFilter(contacts_, filter_);
        dropFreedFriction(h);
        for (const ContactConstraint& c : contacts_)
          particle(dv_, c.particle) = filter_.apply(c.particle, particle(dv_, c.particle));
        addPrescribedChange(contacts_, filter_, h, dv_);
      }
      if (pairs) {
        ++stats_.body_contact_solves;
        ++stats_.body_contact_active_set_solves;
        applyPairs(h, x, v);
      }
      solve(rhs_, dv_, absolute);
    }
  }

  // Contact between bodies inside the solve: each pair (ContactPair), with gap g(x) = n . sum w_i x_i - thickness
  // linear in x over the step, has the one-sided penalty energy k min(0, g - g_rest)^2 / 2: convex, so backward Euler
  // solved exactly with it never gains energy (docs/body-contact.md). The force at the step's end F_i = -k (g(x1) -
  // g_rest) w_i n while the pair is pressed (active), its Jacobian -k w_i w_j n n^T: exact over the step, the system
  // gains h^2 k u u^T (u: the w_i n) as a stencil block, the right-hand side h (F(x0) + h dF/dx v0) = -h k (g(x0) -
  // g_rest + h n . sum w_i v0_i) w_i n. Which pairs are pressed is found by solving: active while the solved end has
  // g(x1) < g_rest (an active set, from the last step's and updated after each solve; a pair pulled would be an
  // attraction the one-sided energy does not have, and a source of energy: only within kActiveSlack of the rest gap
  // does a pair keep its activity against the solved end). The stiffness k = kPenalty m / h^2 (m = 1 / sum w_i^2 / m_i,
  // the pair's effective mass). g_rest is 0, or for a pair already within the thickness all but kRecovery of its
  // overlap (a tenth a step, as Bridson 2002's repulsion): a pair that entered the thickness outside the solve is not
  // pushed out at once with the energy of its whole overlap. Sets terms_ for new pairs and each pair's activity at the
  // solved end x1 (first: the step's first pairs, active as the last step left them); returns how many changed.
  std::size_t updatePairs(const ForceJacobian& jacobian, double h, const VecX& x0, const VecX& x1, bool first) {
    const VecX& inverse_mass = jacobian.inverseMass();
    // On threads in fixed chunks of pairs (each pair's term its own; the counts summed per chunk, in order).
    const std::size_t known = terms_.size();
    terms_.resize(pairs_.size());
    std::size_t changed = countOverPairs(pairs_.size() - known, [&](std::size_t j) {
      const std::size_t k = known + j;
      const ContactPair& c = pairs_[k];
      const double weight = c.stencil.inverseMass(inverse_mass);
      const double stiffness = weight > 0 ? kPenalty / (weight * h * h) : 0;
      PairTerm term{stiffness, 0, penaltyRestGap(c.gap(x0), kRecovery), false};
      if (c.collider) term.rest = std::max(term.rest, c.gap(x0) + c.rise);
      if (first) {  // the last step's active set, and its friction, start this step's
        const auto it = std::lower_bound(carried_.begin(), carried_.end(), CarriedPair{c.element, 0});
        if (it != carried_.end() && it->element == c.element && stiffness > 0) {
          term.active = true;
          term.damping = it->damping;
        }
      }
      terms_[k] = term;
      return term.active;
    });
    if (first) return changed;
    changed += countOverPairs(pairs_.size(), [&](std::size_t k) {
      const double past = pairs_[k].gap(x1) - terms_[k].rest;  // < 0: pressed
      const bool active = terms_[k].stiffness > 0 && past < 0;
      if (active == terms_[k].active || std::abs(past) < kActiveSlack * pairs_[k].thickness) return false;
      terms_[k].active = active;
      return true;
    });
    return changed;
  }
  // How many of the pairs 0 .. n - 1 fn(pair) returns true for, each pair once, on threads.
  template <class Fn>
  std::size_t countOverPairs(std::size_t n, Fn&& fn) {
    return sumOverChunks(int(n), parallel_, pair_counts_, [&](int begin, int end) {
      std::size_t count = 0;
      for (int k = begin; k < end; ++k) count += fn(std::size_t(k)) ? 1 : 0;
      return count;
    });
  }

  // The right-hand side and stencils of the active pairs (with friction: their dampers too), from rhs_base_.
  void applyPairs(double h, const VecX& x, const VecX& v) {
    history_ = 0;  // this step's dv carries contact: not the smooth error's measure
    if (!rhs_saved_) rhs_base_ = rhs_;
    rhs_saved_ = true;
    rhs_ = rhs_base_;
    matrix_.stencils().clear();
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      const ContactPair& c = pairs_[k];
      const PairTerm& term = terms_[k];
      if (!term.active) continue;
      ++stats_.body_contact_pairs;
      Sym3 block = (h * h * term.stiffness) * Sym3::outer(c.normal);
      Vec3 force = -h * term.stiffness * (c.gap(x) - term.rest + h * c.normal.dot(c.relative(v))) * c.normal;
      if (term.damping > 0) {
        const Eigen::Matrix3d tangential = Eigen::Matrix3d::Identity() - c.normal * c.normal.transpose();
        block += Sym3::fromDense((h * term.damping) * tangential);
        force -= h * term.damping * (tangential * c.relative(v));
      }
      matrix_.stencils().push_back({c.stencil, block});
      c.stencil.spread(force, rhs_);
    }
  }

  // Keeps the active pairs for the next step (updatePairs), each with its Coulomb friction: a pair pressed at the
  // step's end (normal force k (g_rest - g(x1))) gets for the next step a tangential damper F_i = -c w_i P sum w_j v_j
  // (P = I - n n^T) of coefficient c = mu |normal force| / max(|P sum w_j v1_j|, kStickSpeed): Coulomb's force on the
  // sliding speed just found, and below kStickSpeed a damper strong enough to hold the pair (static friction as a
  // creep slower than kStickSpeed). Linear in v, so exact in the step and dissipative. Lagged by a step, as IPC lags
  // its friction (Li et al. 2020): a solve of its own, with every pair's stencil in it, would cost a step as much
  // again.
  void carryPairs(double h, const VecX& x, const VecX& v) {
    carried_.clear();
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      const ContactPair& c = pairs_[k];
      const PairTerm& term = terms_[k];
      if (!term.active) continue;
      double damping = 0;
      if (c.friction > 0) {
        Vec3 x1 = Vec3::Zero(), v1 = Vec3::Zero();
        const WeightedStencil& s = c.stencil;
        for (int i = 0; i < s.size; ++i) {
          const Vec3 vi = particle(v, s.particle[i]) + particle(dv_, s.particle[i]);
          v1 += s.w[i] * vi;
          x1 += s.w[i] * (particle(x, s.particle[i]) + h * vi);
        }
        const double pressed = term.stiffness * std::max(0.0, term.rest + c.surface + c.thickness - c.normal.dot(x1));
        const double slide = (v1 - c.normal.dot(v1) * c.normal).norm();
        damping = c.friction * pressed / std::max(slide, kStickSpeed);
      }
      carried_.push_back({c.element, damping});
    }
    std::sort(carried_.begin(), carried_.end());
  }

  // f += the pairs' penalty and friction forces at (x1, v1) (Newton's residual).
  void addPairForces(const VecX& x1, const VecX& v1, VecX& f) const {
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      const ContactPair& c = pairs_[k];
      const Vec3 n = c.normal;
      if (!terms_[k].active) continue;
      Vec3 force = -terms_[k].stiffness * (c.gap(x1) - terms_[k].rest) * n;
      const Vec3 u = c.relative(v1);
      force -= terms_[k].damping * (u - n.dot(u) * n);
      c.stencil.spread(force, f);
    }
  }

  // The error rule's bound on |S r| for this step (0: none), from the last two steps' dv (dv_ and previous_dv_), which
  // it then shifts: previous_dv_ = dv_. Before dv_ is filtered and warm-started.
  double errorRuleTolerance(double h) {
    if (!(options_.cg_error_fraction > 0) || options_.newton) return 0;  // the rule is off: no history to keep
    double tolerance = 0;
    if (history_ >= 2 && sameStep(h) && std::isfinite(lightest_)) {
      const double change = sumOverChunks(n_, parallel_, sums_, [&](int begin, int end) {
        double sum = 0;
        for (int p = begin; p < end; ++p) sum += (particle(dv_, p) - particle(previous_dv_, p)).squaredNorm();
        return sum;
      });
      tolerance = options_.cg_error_fraction * lightest_ * 0.5 * std::sqrt(change);
    }
    if (!sameStep(h)) history_ = 0;
    history_h_ = h;
    history_ = std::min(history_ + 1, 2);
    if (!contacts_.empty()) history_ = 0;  // this step's dv carries contact impulses: not the smooth error's measure
    previous_dv_ = dv_;
    return tolerance;
  }

  // Whether h is the step of the error rule's history (within round-off: dv scales with h).
  bool sameStep(double h) const { return std::abs(h - history_h_) <= 1e-9 * h; }

  // Solves S (A y - b) = 0 from y (its filtered-out part kept); absolute: the error rule's bound on |S r| (0: none).
  void solve(const VecX& b, VecX& y, double absolute = 0) {
    const bool two_level = options_.cg_preconditioner == CgPreconditioner::Auto
                               ? two_level_
                               : options_.cg_preconditioner == CgPreconditioner::TwoLevel;
    const PcgResult r = pcg_.solve(matrix_, filter_, b, y, options_.cg_tolerance, options_.cg_max_iterations, parallel_,
                                   two_level, absolute);
    if (r.by_absolute && r.relative_residual > options_.cg_tolerance) ++stats_.error_rule_stops;
    // Auto: the coarse level pays when block-Jacobi needs many iterations, and is overhead when few are needed.
    if (options_.cg_preconditioner == CgPreconditioner::Auto &&
        (two_level ? r.iterations < kTwoLevelIterations / 4
                   : r.iterations > kTwoLevelIterations && n_ >= kTwoLevelParticles))
      two_level_ = !two_level;
    ++stats_.last_linear_solves;
    ++stats_.linear_solves;
    stats_.last_cg_iterations += r.iterations;
    stats_.cg_iterations += r.iterations;
    stats_.last_cg_residual = std::max(stats_.last_cg_residual, r.relative_residual);
    stats_.max_cg_residual = std::max(stats_.max_cg_residual, r.relative_residual);
  }

  // r = S (M dv - h (Fs(x0 + h (v0 + dv), v0 + dv) + Fc)); returns max |M^-1 r|. Leaves the trial state in x1_, v1_.
  double residual(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v, const VecX& dv,
                  const VecX& mass, VecX& r) {
    v1_ = v + dv;
    x1_ = x + h * v1_;
    ++stats_.evaluations;
    jacobian.smoothForce(t + h, x1_, v1_, fs_);
    addPairForces(x1_, v1_, fs_);
    for (const SlidingContact& s : sliding_)  // their friction (frictionBlocks)
      if (s.in_matrix) particle(fs_, s.contact.particle) -= s.contact.damping * tangentialSlide(s.contact, h, v1_);
    r.resize(x.size());
    double worst = 0;
    for (int p = 0; p < n_; ++p) {
      const Vec3 rp = filter_.apply(p, mass[p] * particle(dv, p) - h * (particle(fs_, p) + particle(fc_, p)));
      particle(r, p) = rp;
      worst = std::max(worst, rp.cwiseAbs().maxCoeff() / mass[p]);
    }
    return worst;
  }

  // Newton on the nonlinear backward-Euler equations from the linearized step in dv_, with backtracking.
  // until_energy_kept: stop as soon as the iterate no longer makes up energy (madeUpEnergy), before convergence.
  void newton(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v, const VecX& mass,
              bool until_energy_kept = false) {
    // The contact forces in F0, held fixed: Fc = F0 - Fs(x0, v0) (f0_ holds accelerations).
    ++stats_.evaluations;
    jacobian.smoothForce(t, x, v, fs_);  // without the pairs' forces: those are in the residual's Fs
    fc_.resize(x.size());
    for (int p = 0; p < n_; ++p) particle(fc_, p) = filter_.apply(p, mass[p] * particle(f0_, p) - particle(fs_, p));
    double norm = residual(jacobian, t, h, x, v, dv_, mass, r_);
    while (norm > options_.newton_tolerance * std::max(1.0, v1_.lpNorm<Eigen::Infinity>()) &&
           stats_.last_linear_solves < options_.newton_max_iterations) {
      assemble(jacobian, t + h, x1_, v1_, h, nullptr, nullptr);
      addFrictionWeights(h);
      delta_.setZero(x.size());
      rhs_ = -r_;
      solve(rhs_, delta_);
      // Backtrack on the residual norm: halve the Newton step until it decreases (at most 10 halvings).
      double alpha = 1;
      for (int k = 0; k < 10; ++k, alpha /= 2) {
        trial_ = dv_ + alpha * delta_;
        const double trial_norm = residual(jacobian, t, h, x, v, trial_, mass, trial_r_);
        if (trial_norm < norm || k == 9) {
          dv_.swap(trial_);
          r_.swap(trial_r_);
          norm = trial_norm;
          break;
        }
      }
      if (until_energy_kept && !madeUpEnergy(jacobian, t, h, x, v)) break;
    }
    stats_.last_residual = norm;
  }

  IntegratorOptions options_;
  PairBlockMatrix matrix_;
  ParticleFilter filter_;
  std::vector<ReleasedSupport> released_;
  FilteredPcg pcg_;
  std::vector<ContactConstraint> contacts_;
  int n_ = 0;
  bool parallel_ = false;
  bool two_level_ = false;  // cg_preconditioner auto: the next solve's choice
  static constexpr int kImpactPasses = 4;
  static constexpr int kBodyPasses = 8;  // ... when bodies touch
  // A later check that changes the activity of fewer than this share of the step's pairs ends the step (solveImpacts;
  // measured in docs/performance.md).
  static constexpr double kSettledShare = 0.003;
  // The share of a pair's overlap of the thickness that its penalty removes in a step (updatePairs).
  static constexpr double kRecovery = 0.1;
  // The penalty's h^2 k over the pair's effective mass (addPairs); measured in docs/body-contact.md.
  static constexpr double kPenalty = 100;
  // A pair whose solved end is within this share of the thickness of its penalty's rest gap keeps its activity:
  // without it, the last solves of a step flip a few hundred pairs by a fiftieth of the thickness each (measured on a
  // crumpled 100 x 100 cloth: 8 solves a step instead of 2); what is left inside the thickness is the pass's.
  static constexpr double kActiveSlack = 0.25;
  // m/s: below this sliding speed friction between bodies holds (carryPairs).
  static constexpr double kStickSpeed = 1e-3;
  struct PairTerm {
    double stiffness;  // N/m of the penalty (0: a pair of pinned particles)
    double damping;    // N s/m of friction (carried from the step before: carryPairs)
    double rest;       // m: the gap the penalty holds (updatePairs)
    bool active;       // pressed at the last solved end
  };
  struct CarriedPair {
    std::array<int, 4> element;  // ContactPair::element
    double damping;
    bool operator<(const CarriedPair& o) const { return element < o.element; }
  };
  struct SlidingContact {
    ContactConstraint contact;
    bool in_matrix;  // its damper is in the matrix (dropFreedFriction)
  };
  std::vector<SlidingContact> sliding_;               // the contacts sliding at the step's start (frictionBlocks)
  std::vector<CarriedPair> carried_;                  // the last step's active pairs, sorted
  std::vector<std::array<int, 4>> carried_elements_;  // their elements (the step's first search: PairJoin::only)
  std::vector<ContactPair> pairs_;                    // this step's contact between bodies, in the order found
  std::vector<PairTerm> terms_;                       // the same order
  VecX rhs_base_;  // the right-hand side without them (saved at the first pair of a step)
  bool rhs_saved_ = false;
  VecX f0_, kv_, rhs_, dv_;
  VecX end_x_, end_v_;  // the candidate step's end state, for impacts
  VecX previous_dv_;    // the step before's dv, for the error rule
  int history_ = 0;     // steps (at most 2) whose dv is in dv_ and previous_dv_, all with step history_h_
  double history_h_ = 0;
  double lightest_ = 0;  // the lightest free particle's mass (m_min)
  std::vector<double> sums_;
  std::vector<std::size_t> pair_counts_;                  // countOverPairs' per chunk
  VecX fs_, fc_, r_, x1_, v1_, delta_, trial_, trial_r_;  // Newton only
};

}  // namespace
std::unique_ptr<Integrator> makeBackwardEuler(const IntegratorOptions& options) {
  return std::make_unique<BackwardEuler>(options);
}
}  // namespace wobble
