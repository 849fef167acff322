// Backward Euler's step: the linearized solve, its error rule, and Newton's iteration (backward_euler.h).
#include "sim/integrators/backward_euler.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "sim/contact/constraints/filter.h"
#include "sim/integrators/methods.h"
#include "sim/solver/parallel.h"

namespace wobble {

BackwardEuler::BackwardEuler(const IntegratorOptions& o) : options_(o) {
  if (!(o.cg_tolerance > 0) || o.cg_max_iterations < 1)
    throw std::invalid_argument("backward-euler: cg_tolerance must be > 0 and cg_max_iterations >= 1");
  if (!(o.cg_error_fraction >= 0)) throw std::invalid_argument("backward-euler: cg_error_fraction must be >= 0");
  if (!(o.newton_tolerance > 0) || o.newton_max_iterations < 1 || o.line_search_halvings < 0)
    throw std::invalid_argument(
        "backward-euler: newton_tolerance must be > 0, newton_max_iterations >= 1 and line_search_halvings >= 0");
}

void BackwardEuler::step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) {
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
    excess_friction_.reserve(jacobian->mass().size());
    coulomb_.reserve(jacobian->mass().size());
    friction_product_.resize(x.size());
    diagonal_.reserve(jacobian->mass().size());
    body_net_.reserve(jacobian->bodyFirsts().size());
    body_capacity_.reserve(jacobian->bodyFirsts().size());
    body_mass_.reserve(jacobian->bodyFirsts().size());
    dv_.resize(0);  // no warm start, no error estimate
    error_.history = 0;
    pairs_.forget();  // their particles' numbers are another topology's
    const int n = static_cast<int>(jacobian->mass().size());
    error_.sums.reserve((n + particleChunk(n) - 1) / particleChunk(n));  // a sum per chunk (parallel.h)
    error_.lightest = std::numeric_limits<double>::infinity();           // the lightest free particle's mass
    momentum_.pinned = false;
    for (Eigen::Index p = 0; p < jacobian->mass().size(); ++p)
      if (jacobian->inverseMass()[p] > 0) error_.lightest = std::min(error_.lightest, jacobian->mass()[p]);
      else momentum_.pinned = true;
    ++stats_.pattern_setups;
  }
  const VecX& mass = jacobian->mass();
  momentum_.x = &x;
  momentum_.mass = &mass;
  filter_.reset(jacobian->inverseMass());
  jacobian->contactConstraints(t, x, v, contacts_, &released_);
  constrainFilter(contacts_, filter_);

  // F0 = M a0: every force, contact included, at the start state.
  ++stats_.evaluations;
  dynamics.acceleration(t, x, v, f0_);
  // A support on a particle leaving its surface would act for the whole step (contact/constraints/constraints.h): taken
  // out.
  for (const ReleasedSupport& r : released_) particle(f0_, r.particle) -= jacobian->inverseMass()[r.particle] * r.force;
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
  PairJoin first = pairs_.begin();
  matrix_.stencils().clear();
  end_x_.resize(x.size());
  forEachChunk(n_, parallel_, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) particle(end_x_, p) = particle(x, p) + h * (particle(v, p) + particle(dv_, p));
  });
  const bool body_pairs = options_.body_contact_in_solve && jacobian->bodyContacts(x, end_x_, pairs_.list(), first);
  if ((jacobian->colliderPairs(t, h, x, v, end_x_, pairs_.list()) || body_pairs) &&
      updatePairs(*jacobian, h, x, end_x_, true))
    applyPairs(h, x, v);
  solve(rhs_, dv_, absolute);
  solveImpacts(*jacobian, t, h, x, v, absolute);
  if (boundFriction(*jacobian, h, x, v, absolute)) solveImpacts(*jacobian, t, h, x, v, absolute);
  if (!pairs_.empty()) {
    ++stats_.body_contact_steps;
    stats_.body_contact_pairs_carried += long(pairs_.size());
  }

  if (options_.newton) {
    newton(*jacobian, t, h, x, v, mass);
  } else {
    // A linearized step that made up energy (a spring shortened or turned by much of its length within the step,
    // where its linearization at the start is far off): the exact step instead, by Newton's iteration on the
    // incremental potential from it (docs/energy.md). Checked where contact acted in the step: constraints on
    // colliders or pairs between bodies at its start, or an impact or a change of pairs within it, in it or in the step
    // before (a stiff body leaving a surface it bounced off), which is where the linearization fails; a step in free
    // flight pays nothing.
    if ((contactActed() || contact_before_) && madeUpEnergy(*jacobian, t, h, x, v)) {
      ++stats_.exact_steps;
      error_.history = 0;  // this step's dv is Newton's: not the smooth error's measure
      newton(*jacobian, t, h, x, v, mass, true);
    }
  }
  contact_before_ = contactActed();
  pairs_.carry(h, x, v, dv_);
  contact_work_ = 0;
  if (!pairs_.empty()) setEnd(h, x, v), contact_work_ = pairs_.work(x, end_x_);

  forEachChunk(n_, parallel_, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) {
      particle(x, p) += h * (particle(v, p) + particle(dv_, p));
      particle(v, p) += particle(dv_, p);
    }
  });
}

void BackwardEuler::assemble(const ForceJacobian& jacobian, double t, const VecX& x, const VecX& v, double h,
                             const VecX* w, VecX* kw) {
  ++stats_.jacobians;
  jacobian.fillJacobian(t, x, v, h * h, h, matrix_, w, kw);
  const VecX& mass = jacobian.mass();
  forEachChunk(n_, parallel_, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) matrix_.self()[p] += mass[p];
  });
}

double BackwardEuler::errorRuleTolerance(double h) {
  if (!(options_.cg_error_fraction > 0) || options_.newton) return 0;  // the rule is off: no history to keep
  double tolerance = 0;
  if (error_.history >= 2 && sameStep(h) && std::isfinite(error_.lightest)) {
    const double change = sumOverChunks(n_, parallel_, error_.sums, [&](int begin, int end) {
      double sum = 0;
      for (int p = begin; p < end; ++p) sum += (particle(dv_, p) - particle(error_.previous_dv, p)).squaredNorm();
      return sum;
    });
    tolerance = options_.cg_error_fraction * error_.lightest * 0.5 * std::sqrt(change);
  }
  if (!sameStep(h)) error_.history = 0;
  error_.history_h = h;
  error_.history = std::min(error_.history + 1, 2);
  if (!contacts_.empty())
    error_.history = 0;  // this step's dv carries contact impulses: not the smooth error's measure
  error_.previous_dv = dv_;
  return tolerance;
}

void BackwardEuler::solve(const VecX& b, VecX& y, double absolute) {
  const bool two_level = options_.cg_preconditioner == CgPreconditioner::Auto
                             ? two_level_
                             : options_.cg_preconditioner == CgPreconditioner::TwoLevel;
  const PcgResult r = pcg_.solve(matrix_, filter_, b, y, options_.cg_tolerance, options_.cg_max_iterations, parallel_,
                                 two_level, absolute);
  // Why it stopped (run.json's linear_solver.stops): the error rule's bound looser than cg_tolerance, the
  // iteration cap, or cg_tolerance itself.
  if (r.relative_residual <= options_.cg_tolerance) {
    ++stats_.tolerance_stops;
  } else if (r.by_absolute && r.iterations < options_.cg_max_iterations) {
    ++stats_.error_rule_stops;
    stats_.max_cg_residual_error_rule = std::max(stats_.max_cg_residual_error_rule, r.relative_residual);
  } else {
    ++stats_.iteration_cap_stops;
    stats_.max_cg_residual_cap = std::max(stats_.max_cg_residual_cap, r.relative_residual);
  }
  keepMomentum(y);
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

void BackwardEuler::keepMomentum(VecX& y) {
  if (!momentum_.x || pairs_.empty() || momentum_.pinned || filter_.anyConstrained() || pairs_.pressesCollider())
    return;
  const VecX& r = pcg_.residual();
  const VecX& x = *momentum_.x;
  const VecX& mass = *momentum_.mass;
  using Sums = MomentumCorrection::Sums;  // M, sum m x, sum r, sum x x r, sum m x x^T (xx yy zz xy xz yz)
  const Sums s = sumOverChunks(n_, parallel_, momentum_.sums, [&](int begin, int end) {
    Sums sum = Sums::Zero();
    for (int p = begin; p < end; ++p) {
      if (filter_.kind(p) != ParticleFilter::Free) continue;
      const double m = mass[p];
      const Vec3 xp = particle(x, p), rp = particle(r, p);
      sum[0] += m;
      sum.segment<3>(1) += m * xp;
      sum.segment<3>(4) += rp;
      sum.segment<3>(7) += xp.cross(rp);
      sum.segment<3>(10) += m * xp.cwiseProduct(xp);
      sum[13] += m * xp.x() * xp.y();
      sum[14] += m * xp.x() * xp.z();
      sum[15] += m * xp.y() * xp.z();
    }
    return sum;
  });
  if (!(s[0] > 0)) return;
  const Vec3 c = s.segment<3>(1) / s[0];
  const Vec3 delta = s.segment<3>(4) / s[0];
  const Vec3 torque = s.segment<3>(7) - c.cross(s.segment<3>(4));
  Eigen::Matrix3d second;  // sum m (x - c)(x - c)^T
  second << s[10], s[13], s[14], s[13], s[11], s[15], s[14], s[15], s[12];
  second -= s[0] * c * c.transpose();
  const Eigen::Matrix3d inertia = second.trace() * Eigen::Matrix3d::Identity() - second;
  const Vec3 omega = inertia.completeOrthogonalDecomposition().solve(torque);  // 0 about a line of particles
  forEachChunk(n_, parallel_, [&](int begin, int end) {
    for (int p = begin; p < end; ++p)
      if (filter_.kind(p) == ParticleFilter::Free) particle(y, p) += delta + omega.cross(particle(x, p) - c);
  });
}

double BackwardEuler::residual(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v,
                               const VecX& dv, const VecX& mass, VecX& r) {
  newton_.v1 = v + dv;
  newton_.x1 = x + h * newton_.v1;
  ++stats_.evaluations;
  jacobian.smoothForce(t + h, newton_.x1, newton_.v1, newton_.fs);
  pairs_.addForces(newton_.x1, newton_.v1, newton_.fs);
  for (const SlidingContact& s : sliding_)  // their friction (frictionBlocks)
    if (s.in_matrix)
      particle(newton_.fs, s.contact.particle) -= s.contact.damping * tangentialSlide(s.contact, h, newton_.v1);
  r.resize(x.size());
  double worst = 0;
  for (int p = 0; p < n_; ++p) {
    const Vec3 rp =
        filter_.apply(p, mass[p] * particle(dv, p) - h * (particle(newton_.fs, p) + particle(newton_.fc, p)));
    particle(r, p) = rp;
    worst = std::max(worst, rp.cwiseAbs().maxCoeff() / mass[p]);
  }
  return worst;
}

// Phi(dv) = dv^T M dv / 2 - h Fc . dv + U(x1) + h D(v1), x1 = x + h (v + dv), v1 = v + dv: with M dv = h F(x1, v1)
// the step, its gradient is the residual's M dv - h F, the step its minimizer. U: the springs' and gravity's energy
// and the active pairs' penalty; D: the dissipation of the sliding contacts' and the pairs' friction (each a damper
// linear in v1: D = c |P u|^2 / 2 has gradient c P u). The springs' dampers and the drag are the line search's
// (newton): their directions move with x1.
double BackwardEuler::potential(const ForceJacobian& jacobian, double h, const VecX& dv, const VecX& mass) {
  double phi = jacobian.stepPotential(h, newton_.x1, newton_.v1) + pairs_.potential(h, newton_.x1, newton_.v1);
  for (const SlidingContact& s : sliding_)
    if (s.in_matrix) phi += 0.5 * h * s.contact.damping * tangentialSlide(s.contact, h, newton_.v1).squaredNorm();
  for (int p = 0; p < n_; ++p)
    phi += particle(dv, p).dot(0.5 * mass[p] * particle(dv, p) - h * particle(newton_.fc, p));
  return phi;
}

void BackwardEuler::newton(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v,
                           const VecX& mass, bool until_energy_kept) {
  // The contact forces in F0, held fixed: Fc = F0 - Fs(x0, v0) (f0_ holds accelerations).
  ++stats_.evaluations;
  jacobian.smoothForce(t, x, v, newton_.fs);  // without the pairs' forces: those are in the residual's Fs
  newton_.fc.resize(x.size());
  for (int p = 0; p < n_; ++p)
    particle(newton_.fc, p) = filter_.apply(p, mass[p] * particle(f0_, p) - particle(newton_.fs, p));
  double norm = residual(jacobian, t, h, x, v, dv_, mass, newton_.r);
  // The line search's merit: the incremental potential where the system offers its share (else NaN: the residual).
  double phi = options_.line_search == LineSearch::Potential ? potential(jacobian, h, dv_, mass)
                                                             : std::numeric_limits<double>::quiet_NaN();
  int pair_rounds = 0;
  while (norm > options_.newton_tolerance * std::max(1.0, newton_.v1.lpNorm<Eigen::Infinity>()) &&
         stats_.last_linear_solves < options_.newton_max_iterations) {
    assemble(jacobian, t + h, newton_.x1, newton_.v1, h, nullptr, nullptr);
    addFrictionWeights(h);
    newton_.delta.setZero(x.size());
    rhs_ = -newton_.r;
    solve(rhs_, newton_.delta);
    // Backtracking: halve the Newton step until it lowers the incremental potential by Armijo's share of its slope
    // (Gast et al. 2015; the matrix is positive definite, so the step descends), or, without the potential, the
    // residual's norm. No step that raises the potential is taken: the iteration ends at the last iterate instead.
    // The residual's search takes its last halving as it stands.
    const double slope = newton_.r.dot(newton_.delta);  // dPhi/dalpha at 0
    const bool on_potential = std::isfinite(phi) && slope < 0;
    // The dampers' and the drag's dissipation along the line, with the springs' directions held at the iterate (as
    // IPC holds its friction's: Li et al. 2020): the force Fd(w) = Fs(x1, w) - Fs(x1, 0) is linear in w, so D(v1 +
    // alpha delta) - D(v1) = -alpha delta . Fd(v1) - alpha^2 delta . Fd(delta) / 2, and Phi's slope at the iterate
    // is the residual's.
    double damped = 0, damped_delta = 0;  // delta . Fd(v1), delta . Fd(delta)
    if (on_potential) {
      stats_.evaluations += 3;
      newton_.v_rest.setZero(x.size());
      jacobian.smoothForce(t + h, newton_.x1, newton_.v_rest, newton_.f_rest);
      jacobian.smoothForce(t + h, newton_.x1, newton_.v1, newton_.f_damped);
      jacobian.smoothForce(t + h, newton_.x1, newton_.delta, newton_.f_delta);
      for (int p = 0; p < n_; ++p) {
        const Vec3 rest = particle(newton_.f_rest, p), d = particle(newton_.delta, p);
        damped += d.dot(particle(newton_.f_damped, p) - rest);
        damped_delta += d.dot(particle(newton_.f_delta, p) - rest);
      }
    }
    bool moved = false;
    double alpha = 1;
    for (int k = 0; k <= options_.line_search_halvings; ++k, alpha /= 2) {
      newton_.trial = dv_ + alpha * newton_.delta;
      const double trial_norm = residual(jacobian, t, h, x, v, newton_.trial, mass, newton_.trial_r);
      const double trial_phi = on_potential ? potential(jacobian, h, newton_.trial, mass) : phi;
      const double dissipated = -h * alpha * (damped + 0.5 * alpha * damped_delta);
      const bool last = k == options_.line_search_halvings;
      // (Near convergence the decrease is below the potential's rounding, which the comparison forgives.)
      const double rounding = kPotentialRounding * std::max(std::abs(phi), std::abs(trial_phi));
      if (on_potential ? trial_phi + dissipated - phi <= kArmijo * alpha * slope + rounding
                       : trial_norm < norm || last) {
        dv_.swap(newton_.trial);
        newton_.r.swap(newton_.trial_r);
        norm = trial_norm;
        // The next iteration's merit starts from here (its dampers' share held at its own iterate).
        phi = on_potential || !std::isfinite(phi) ? trial_phi : potential(jacobian, h, dv_, mass);
        moved = true;
        break;
      }
    }
    if (!moved) {
      ++stats_.line_search_stops;
      residual(jacobian, t, h, x, v, dv_, mass, newton_.r);  // the scratch's x1, v1 back at the iterate
      break;
    }
    // The active set at the iterate's end: Newton moves the end away from the linearized solves', and a pair it
    // presses that the set does not hold would be left to the pass after the step, whose impulses on the surface
    // alone make energy (docs/energy.md). A change means another potential: its residual and merit afresh.
    bool settled = true;
    if (pair_rounds < kBodyPasses && (setEnd(h, x, v), pressPairs(jacobian, t, h, x, v, settled)) > 0) {
      ++pair_rounds;
      ++stats_.newton_pair_updates;
      applyPairs(h, x, v);
      norm = residual(jacobian, t, h, x, v, dv_, mass, newton_.r);
      if (std::isfinite(phi)) phi = potential(jacobian, h, dv_, mass);
      if (!settled) continue;
    }
    if (until_energy_kept && !madeUpEnergy(jacobian, t, h, x, v)) break;
  }
  stats_.last_residual = norm;
}

bool BackwardEuler::madeUpEnergy(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v) {
  setEnd(h, x, v);
  return jacobian.energyMadeUp(t, h, x, v, end_x_, end_v_) > 0;
}

void BackwardEuler::setEnd(double h, const VecX& x, const VecX& v) {
  end_x_.resize(x.size());
  end_v_.resize(x.size());
  forEachChunk(n_, parallel_, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) {
      particle(end_v_, p) = particle(v, p) + particle(dv_, p);
      particle(end_x_, p) = particle(x, p) + h * particle(end_v_, p);
    }
  });
}

std::unique_ptr<Integrator> makeBackwardEuler(const IntegratorOptions& options) {
  return std::make_unique<BackwardEuler>(options);
}

}  // namespace wobble
