#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "sim/contact/collisions/stage_penalty.h"

namespace wobble {
namespace {

// A Dynamics with contact between bodies for an implicit solve: every call passed on to the system's, and the pairs of
// surface elements a candidate step ends within reach (ForceJacobian::bodyContacts) from the pass between bodies. The
// system knows nothing of the pass: Simulation joins them here. It forwards every method of ForceJacobian (dynamics.h):
// one added there must be forwarded here too, or an integrator would see its default.
class WithBodyContact final : public Dynamics, public ForceJacobian {
 public:
  WithBodyContact(const Dynamics& dynamics, collision::BodyCollisions& pass, const collision::StagePenalty* stages)
      : dynamics_(dynamics), jacobian_(*dynamics.forceJacobian()), pass_(pass), stages_(stages) {}

  void acceleration(double t, const VecX& x, const VecX& v, VecX& a) const override {
    dynamics_.acceleration(t, x, v, a);
    if (stages_ && !stages_->empty()) stages_->addAccelerations(x, v, jacobian_.inverseMass(), a);
  }
  const ForceJacobian* forceJacobian() const override { return this; }

  const VecX& mass() const override { return jacobian_.mass(); }
  const VecX& inverseMass() const override { return jacobian_.inverseMass(); }
  void smoothForce(double t, const VecX& x, const VecX& v, VecX& f) const override {
    jacobian_.smoothForce(t, x, v, f);
  }
  const PairSchedule& jacobianPattern() const override { return jacobian_.jacobianPattern(); }
  void fillJacobian(double t, const VecX& x, const VecX& v, double cx, double cv, PairBlockMatrix& a, const VecX* w,
                    VecX* kw) const override {
    jacobian_.fillJacobian(t, x, v, cx, cv, a, w, kw);
  }
  bool parallel() const override { return jacobian_.parallel(); }
  const std::vector<int>& bodyFirsts() const override { return jacobian_.bodyFirsts(); }
  void contactConstraints(double t, const VecX& x, const VecX& v, std::vector<ContactConstraint>& out,
                          std::vector<ReleasedSupport>* released) const override {
    jacobian_.contactConstraints(t, x, v, out, released);
  }
  bool impactConstraints(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1, const VecX& v1,
                         std::vector<ContactConstraint>& out) const override {
    return jacobian_.impactConstraints(t, h, x0, v0, x1, v1, out);
  }
  bool bodyContacts(const VecX& x0, const VecX& x1, std::vector<ContactPair>& out, PairJoin& join) const override {
    return pass_.nearPairs(x0, x1, out, join);
  }
  bool colliderPairs(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                     std::vector<ContactPair>& out) const override {
    return jacobian_.colliderPairs(t, h, x0, v0, x1, out);
  }
  double energyMadeUp(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                      const VecX& v1) const override {
    return jacobian_.energyMadeUp(t, h, x0, v0, x1, v1);
  }
  double stepPotential(double h, const VecX& x1, const VecX& v1) const override {
    return jacobian_.stepPotential(h, x1, v1);
  }

 private:
  const Dynamics& dynamics_;
  const ForceJacobian& jacobian_;
  collision::BodyCollisions& pass_;
  const collision::StagePenalty* stages_;  // an explicit integrator's pairs within reach (null: none)
};

// The traits of an integrator of the table; nullptr for one from outside it (as tests make), which has none.
const IntegratorTraits* tableTraits(std::string_view name) {
  const auto names = integratorNames();
  return std::find(names.begin(), names.end(), name) != names.end() ? &integratorTraits(name) : nullptr;
}

// The free particles of x inside a collider at t, deeper than its contact band (DeepInside): a body placed there is
// pushed out by the collider's constraints within the step, energy the collider gives (not the step's to keep).
std::optional<DeepInside> deepInside(const MassSpringSystem& system, double t, const VecX& x) {
  std::optional<DeepInside> deepest;
  int pairs = 0;
  std::vector<int> inside;
  for (const auto& collider : system.colliders()) {
    collider->near(t, x, -collider->contact().epsilon, inside);
    for (const BodySlot& slot : system.bodies()) {
      DeepInside found{slot.body.name, collider->name(), 0, 0, collider->contact().epsilon};
      const int end = slot.first + int(slot.body.x.size() / 3);
      for (auto i = std::lower_bound(inside.begin(), inside.end(), slot.first); i != inside.end() && *i < end; ++i) {
        if (system.inverseMass()[*i] == 0) continue;
        const auto point = collider->query(t, particle(x, *i));
        ++found.particles;
        found.depth = std::max(found.depth, point ? -point->distance : 0.0);
      }
      if (found.particles == 0) continue;
      ++pairs;
      if (!deepest || found.depth > deepest->depth) deepest = found;
    }
  }
  if (deepest) deepest->other_pairs = pairs - 1;
  return deepest;
}

// RK4's penalty layer between bodies (IntegratorTraits::contact_in_stages), each particle's material its body's
// springs' mean ks times rest length (N).
std::unique_ptr<collision::StagePenalty> stagePenalty(const MassSpringSystem& system) {
  std::vector<double> stiffness(system.particleCount(), 0.0);
  for (const BodySlot& slot : system.bodies()) {
    const Springs& springs = slot.body.springs;
    double sum = 0;
    for (std::size_t s = 0; s < springs.size(); ++s) sum += springs.ks[s] * springs.rest[s];
    const double mean = springs.size() ? sum / double(springs.size()) : 0;
    std::fill_n(stiffness.begin() + slot.first, slot.body.particleCount(), mean);
  }
  return std::make_unique<collision::StagePenalty>(std::move(stiffness));
}

}  // namespace

namespace collision {

std::unique_ptr<BodyCollisions> makeBodyCollisions(const MassSpringSystem& system) {
  std::vector<Surface> surfaces;
  for (const BodySlot& slot : system.bodies()) {
    const Springs& springs = slot.body.springs;
    const double stiffness =
        springs.size() ? std::accumulate(springs.ks.begin(), springs.ks.end(), 0.0) / double(springs.size()) : 0.0;
    surfaces.push_back({&slot.body.surface, slot.first, slot.body.contact, stiffness});
  }
  if (!BodyCollisions::needed(surfaces)) return nullptr;
  return std::make_unique<BodyCollisions>(surfaces, system.inverseMass(), system.contactSettings(), system.parallel());
}

}  // namespace collision

Simulation::Simulation(MassSpringSystem& system, std::unique_ptr<Integrator> integrator, double dt)
    : system_(system),
      integrator_(std::move(integrator)),
      dt_(dt),
      x_(system.initialPositions()),
      v_(system.initialVelocities()),
      collisions_(collision::makeBodyCollisions(system)) {
  system.setStepSize(dt);
  const IntegratorTraits* traits = tableTraits(integrator_->name());
  if (collisions_ && traits && traits->contact_in_stages) stages_ = stagePenalty(system);
  if (collisions_) with_contact_ = std::make_unique<WithBodyContact>(system, *collisions_, stages_.get());
  for (int i = 0; i < system.particleCount(); ++i)
    max_speed_squared_ = std::max(max_speed_squared_, particle(v_, i).squaredNorm());
  energy_start_ = system.energy(x_, v_);
  inside_ = starts_inside_ = deepInside(system, 0, x_);
  lift_margin_ = system.liftEnergy();
  // An implicit integrator's steps are checked one by one (its steps are few and each costs several force
  // evaluations, against which the energy at its ends is cheap), where it keeps the bodies apart itself: with [contact]
  // in_solve = false the pass after the step is known to add energy (docs/energy.md), which no retake mends. An
  // integrator from outside the table has no traits.
  energy_retakes_ = traits && traits->implicit && (!collisions_ || integrator_->solvesBodyContact());
  rests_on_pass_ = traits && !traits->implicit && !stages_;
}

Simulation::~Simulation() = default;

double Simulation::heldEnergy() const { return stages_ ? stages_->energy(x_) : 0; }

double Simulation::maxSpeed() const { return std::sqrt(max_speed_squared_); }

std::optional<BlowUp> Simulation::advanceTo(double t_end) {
  // The number of steps is fixed first, from the whole interval, and step k ends at start + k dt (not at a running
  // sum): a remainder below kSliver steps is round-off, not a step to take, so landing never adds a sliver step.
  constexpr double kSliver = 1e-9;
  const double remaining = (t_end - t_) / dt_;
  if (!(remaining > kSliver)) return std::nullopt;
  const long count = std::max(1L, static_cast<long>(std::ceil(remaining - kSliver)));
  const double start = t_;
  interval_speed_squared_ = 0, interval_kinetic_ = 0;
  for (long k = 1; k <= count; ++k) {
    const bool last = k == count;
    ++steps_;
    if (auto blow_up = step(t_, last ? t_end - t_ : dt_, last ? t_end : start + double(k) * dt_,
                            collisions_ || energy_retakes_ ? system_.contactSettings().split_steps : 0))
      return blow_up;
  }
  checkEnergy();
  return std::nullopt;
}

std::optional<BlowUp> Simulation::step(double t0, double h, double t1, int splits) {
  const bool colliders = !system_.colliders().empty();
  if (collisions_ || colliders || energy_retakes_) x_before_ = x_, v_before_ = v_;
  // Where a step's energy may have been made up (energy_retakes_): the integrator solves every step exactly, or found
  // its linearized step made some up and solved it again, or the pass between bodies stopped a collision after it
  // (its impulses move the surface alone, and at a large step that compresses the springs behind it: docs/energy.md).
  const IntegratorStats& stats = integrator_->stats();
  const long exact_before = stats.exact_steps + stats.line_search_stops;
  const long pass_before = collisions_ ? collisions_->stats().ccd_hits + collisions_->stats().zone_activations : 0;
  if (stages_) {  // the pairs within reach over the step, for the penalty in its stages
    stage_pairs_.clear();
    x_reach_ = x_ + h * v_;
    collisions_->nearPairs(x_, x_reach_, stage_pairs_);
    stages_->begin(stage_pairs_, x_, system_.inverseMass(), h);
  }
  integrator_->step(stepped(), t0, h, x_, v_);
  if (stages_) stages_->end(x_, v_);
  // A resting contact on a collider is stopped without restitution: only the approach a particle brought into the step
  // bounces, not what the step's own forces added (contact/colliders/response.h; Guendelman, Bridson & Fedkiw 2003).
  system_.resolveCollisions(t1, x_, v_, colliders ? &v_before_ : nullptr);
  if (collisions_) {
    auto failure = collisions_->resolve(x_before_, x_, v_, h,
                                        {.repulsion = !integrator_->solvesBodyContact() && !stages_,
                                         .continues = x_is_last_pass_end_,
                                         .resting = rests_on_pass_});
    x_is_last_pass_end_ = !failure;
    if (failure) {
      if (splits > 0) {
        ++split_steps_;
        return retakeInHalves(t0, h, t1, splits);
      }
      t_ = t1;
      std::ostringstream reason;
      reason.precision(4);
      reason << failure->reason;
      if (const int halvings = system_.contactSettings().split_steps; halvings > 0)
        reason << " (in a part of " << h << " s of the step, halved " << halvings << " times: [contact] split_steps)";
      return BlowUp{std::string(integrator_->name()),
                    steps_,
                    t_,
                    failure->particle,
                    0,
                    reason.str(),
                    failure->fix.empty() ? contactFix() : failure->fix};
    }
  }
  t_ = t1;
  const double work = colliders ? system_.colliderWork(t0, h, x_before_, v_before_, x_, v_) : 0;
  const double penalty_work = integrator_->contactWork();
  // A step that made up energy (its end above its start plus the colliders' work by more than the step's margin:
  // integrator, colliders and pass together) is taken again in halves, each checked the same way; the smallest part
  // that still makes it up is left to the run's check (docs/energy.md, "A step that gains is taken again"). Not one
  // that starts with a body inside a collider: the collider pushes it out within the step, energy it gives whatever
  // the step's size (a smaller step only pushes it faster).
  const bool suspect =
      energy_retakes_ &&
      (!integrator_->linearizesItsStep() || stats.exact_steps + stats.line_search_stops != exact_before ||
       (collisions_ && collisions_->stats().ccd_hits + collisions_->stats().zone_activations != pass_before));
  if (suspect) {
    const double start_energy = system_.energy(x_before_, v_before_);
    if (system_.energy(x_, v_) - start_energy - work - penalty_work >
        kStepEnergyMargin * std::max(std::abs(start_energy), lift_margin_)) {
      if (auto inside = deepInside(system_, t0, x_before_)) {
        inside->step = steps_;
        if (!inside_ || inside->depth > inside_->depth) inside_ = std::move(inside);
      } else if (splits > 0) {
        ++energy_retakes_count_;
        return retakeInHalves(t0, h, t1, splits);
      } else {
        energy_retakes_exhausted_ = true;
      }
    }
  }
  if (auto blow_up = check()) return blow_up;
  collider_work_ += work;
  collider_work_unsigned_ += std::abs(work);
  penalty_work_ += penalty_work;
  if (energy_retakes_exhausted_) {  // the run's check at once, where it failed
    checkEnergy();
    energy_retakes_exhausted_ = false;
  }
  if (step_observer_) step_observer_(t_, x_);
  return std::nullopt;
}

// The same step again as two halves, from its start state (kept by step). What the integrator and the pass carry from
// step to step (backward Euler's pressed pairs, the pass's kept candidates) comes from the failed attempt as from any
// step before: guesses that each checks again. Static friction's stick time follows the halves' size, and is set back
// after them.
std::optional<BlowUp> Simulation::retakeInHalves(double t0, double h, double t1, int splits) {
  x_ = x_before_, v_ = v_before_;
  x_is_last_pass_end_ = false;
  const double size = system_.stepSize();
  system_.setStepSize(h / 2);
  const double mid = t0 + h / 2;
  auto blow_up = step(t0, h / 2, mid, splits - 1);
  if (!blow_up) blow_up = step(mid, t1 - mid, t1, splits - 1);
  system_.setStepSize(size);
  return blow_up;
}

void Simulation::checkEnergy() {
  if (energy_gain_) return;  // the first one is the news
  const double energy = system_.energy(x_, v_) + heldEnergy();
  const double margin =
      std::max(kEnergyGainRelative * (std::abs(energy_start_) + collider_work_unsigned_), lift_margin_);
  if (energy - energy_start_ - collider_work_ - penalty_work_ > margin)
    energy_gain_ = EnergyGain{std::string(integrator_->name()),
                              steps_,
                              t_,
                              energy_start_,
                              energy,
                              collider_work_,
                              margin,
                              collisions_ && contactSolveOff(),
                              integrator_->linearizesItsStep(),
                              std::any_of(system_.colliders().begin(), system_.colliders().end(),
                                          [](const auto& c) { return c->contact().restitution > 0; }),
                              collider_work_unsigned_ > 0,
                              energy_retakes_ ? system_.contactSettings().split_steps : -1,
                              inside_,
                              penalty_work_};
}

std::string EnergyGain::message(double dt) const {
  std::ostringstream out;
  out.precision(4);
  out << "the simulation gained energy: integrator " << integrator << ", step " << step << ", t = " << time
      << " s: total energy " << energy << " J against " << start << " J at the start";
  if (collider_work != 0) out << " plus " << collider_work << " J of work by moving colliders";
  if (penalty_work != 0)
    out << (penalty_work > 0 ? " plus " : " less ") << std::abs(penalty_work)
        << " J of work by the contact pairs' penalty";
  out << " (gained " << gained() << " J, " << gained() / std::max(std::abs(start), 1e-300)
      << " times the start's; allowed " << margin << " J, docs/energy.md). ";
  // A body inside a collider is pushed out with energy the collider gives, whatever the step: its own advice first.
  if (inside)
    out << "The likely cause: " << inside->describe()
        << "; the collider pushes them out, which no smaller step mends: move the body out of the collider (or start "
           "it above). Otherwise try";
  else out << "Try";
  out << " a smaller time step (--dt " << dt / 4 << ")";
  const IntegratorTraits* traits = tableTraits(integrator);
  if (!traits || !traits->a_stable)  // one stable at any step (integrator.h): not what gained it
    for (const std::string_view name : integratorNames())
      if (integratorTraits(name).a_stable) out << ", " << name << " (--integrator " << name << ")";
  if (contact_solve_off) out << ", contact between bodies in the solve ([contact] in_solve = true)";
  if (linearized) out << ", the exact step instead of its linearization ([simulation] newton = true)";
  if (bouncing) out << ", or a lower restitution";
  out << ".";
  // Steps that started inside a collider were left to this check, not taken again: no halving to report then.
  if (!inside && halvings > 0)
    out << " Every step that gained had been solved exactly (Newton's iteration with a line search on its incremental "
           "potential) and taken again in halves, down to a 1/"
        << (1L << halvings) << " part of the step ([contact] split_steps = " << halvings
        << "), and the smallest part still gained.";
  else if (!inside && halvings == 0)
    out << " Every step that gained had been solved exactly (Newton's iteration with a line search on its incremental "
           "potential) but not taken again in halves: [contact] split_steps = 0.";
  // A moving collider's count misses one case (docs/energy.md, "Limits"), which no step size or integrator mends.
  if (moving_colliders)
    out << " Moving colliders did work here: a platform that stops dead while it presses a body gives it energy that "
           "the count of their work misses (docs/energy.md, Limits); let it come to rest before the press, or press "
           "with a collider that keeps moving.";
  return out.str();
}

std::string DeepInside::describe() const {
  std::ostringstream out;
  out.precision(3);
  out << "body '" << body << "' " << (step == 0 ? "starts with " : "had ") << particles
      << (particles == 1 ? " particle" : " particles") << " inside collider '" << collider << "', up to " << depth
      << " m deep (its contact band is " << band << " m)";
  if (step > 0) out << " at the start of step " << step;
  if (other_pairs > 0) out << ", and " << other_pairs << " more body-collider pair(s) that deep";
  return out.str();
}

bool Simulation::contactSolveOff() const {
  return integratorTraits(integrator_->name()).body_contact_in_solve && !integrator_->solvesBodyContact();
}

// What of [contact] may resolve a failed contact step: more rounds, and for an integrator that can carry the contacts
// in its solve but was told not to, the solve.
std::string Simulation::contactFix() const {
  const collision::Settings& s = system_.contactSettings();
  std::ostringstream out;
  const bool solve = contactSolveOff();
  out << "a larger contact thickness, " << (solve ? "" : "or ")
      << "more rounds or halvings in [contact] (now zone_iterations = " << s.zone_iterations
      << ", ccd_iterations = " << s.ccd_iterations << ", split_steps = " << s.split_steps << ")";
  if (solve)
    out << ", or [contact] in_solve = true (" << integrator_->name() << " then keeps the bodies apart in its solve)";
  return out.str();
}

std::optional<BlowUp> Simulation::check() {
  double kinetic = 0, fastest = 0;
  for (int i = 0; i < system_.particleCount(); ++i) {
    const double s2 = particle(v_, i).squaredNorm();
    fastest = std::max(fastest, s2);
    max_speed_squared_ = std::max(max_speed_squared_, s2);
    kinetic += 0.5 * system_.mass()[i] * s2;
    if (std::isnan(s2) || std::isnan(particle(x_, i).sum()) || s2 > kBlowUpSpeedSquared)
      return BlowUp{std::string(integrator_->name()), steps_, t_, i, s2};
  }
  interval_speed_squared_ = std::max(interval_speed_squared_, fastest);
  interval_kinetic_ = std::max(interval_kinetic_, kinetic);
  return std::nullopt;
}

std::string BlowUp::message(double dt) const {
  std::ostringstream out;
  if (!reason.empty()) {
    out << "contact between bodies failed: integrator " << integrator << ", step " << step << ", t = " << time
        << " s: " << reason << ". Try a smaller time step (--dt " << dt / 4 << "), " << fix << ".";
    return out.str();
  }
  out << "the simulation blew up: integrator " << integrator << ", step " << step << ", t = " << time << " s: particle "
      << particle << (std::isnan(speed_squared) ? " has a NaN state" : " has |v|^2 = ")
      << (std::isnan(speed_squared) ? std::string() : std::to_string(speed_squared))
      << (std::isnan(speed_squared) ? "" : " > 1e6") << ". Try a smaller time step (--dt " << dt / 4
      << "), a more stable integrator (--integrator rk4), or softer springs.";
  return out.str();
}

}  // namespace wobble
