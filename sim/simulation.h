// Steps a MassSpringSystem with an integrator: fixed steps of dt, the last one before a requested time shortened
// to land on it exactly (never an extra sliver step for round-off: a 3 s run at dt 1e-4 is 30000 steps); contact
// resolution at every step end; blow-up detection after every step. A step the pass between bodies cannot make free
// of collisions (impact zones over their cap, a broad phase over its budget) is taken again from its start as two
// halves, up to [contact] split_steps halvings deep (docs/body-contact.md), before the run stops. So is a step of an
// implicit integrator (backward Euler, which has already solved such a step exactly by Newton's iteration on its
// incremental potential: Gast et al. 2015, "Optimization integrator for large time steps"; Li et al. 2020,
// "Incremental Potential Contact") whose end, pass between bodies included, still has more energy than its start plus
// the colliders' work and push-out: the error of an inexact step, and the pass's, shrink with the step
// (docs/energy.md).
#pragma once
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "sim/contact/collisions/body_collisions.h"
#include "sim/integrators/integrator.h"
#include "sim/system.h"

namespace wobble {

namespace collision {
class StagePenalty;
// The pass between a system's bodies (their Body::contact), or nothing when no two surface elements may meet.
std::unique_ptr<BodyCollisions> makeBodyCollisions(const MassSpringSystem& system);
}  // namespace collision

// The course framework's rule: the run is unstable once any velocity is NaN or any |v|^2 exceeds this.
inline constexpr double kBlowUpSpeedSquared = 1e6;

struct BlowUp {
  std::string integrator;
  long step;             // 1-based index of the step that blew up
  double time;           // simulated time at its end
  int particle;          // first offending particle
  double speed_squared;  // NaN when a value was NaN
  std::string reason;    // set when contact between bodies failed (then speed_squared is 0): what is left, where
  std::string fix;       // ... and then what to try besides a smaller step (Simulation::contactFix)
  // One paragraph for the user: what happened, where, and what to try.
  std::string message(double dt) const;
};

// The run's own energy check (docs/energy.md): the total energy (kinetic + gravitational + elastic) less the work
// backward Euler's contact pairs' penalty did (Simulation::countedEnergy) may not exceed the start's plus the work
// moving colliders did on the bodies by more than kEnergyGainRelative of (|start| + the
// colliders' work, counted unsigned) or, whichever is more, the energy of lifting every particle by kEnergyGainLift
// (m |g|, with |g| at least 1 m/s^2; system.h). A stable integrator's drift and the contact band's slack stay far
// below either; the gains of an unstable contact or step are multiples of the start.
inline constexpr double kEnergyGainRelative = 0.1;

// Free particles inside a collider deeper than its contact band (ContactParams::epsilon): the collider pushes them out
// within a step, energy it gives whatever the step's size. The (body, collider) pair with the deepest particle.
struct DeepInside {
  std::string body, collider;
  int particles = 0;    // the body's particles inside that collider, deeper than its band
  double depth = 0;     // m, the deepest of them below the collider's surface
  double band = 0;      // m, the collider's contact band
  long step = 0;        // the step at whose start they were found (0: the run's start)
  int other_pairs = 0;  // further (body, collider) pairs with particles that deep
  // "body 'jelly' has 12 particles inside collider 'left', up to 0.08 m deep (its contact band is 0.01 m)".
  std::string describe() const;
};

struct EnergyGain {
  std::string integrator;
  long step;                      // 1-based index of the step at whose end the check failed
  double time;                    // simulated time there
  double start;                   // J, total energy at t = 0
  double energy;                  // J, total energy there
  double collider_work;           // J, work done on the bodies by moving colliders up to there
  double margin;                  // J, the gain allowed
  bool contact_solve_off;         // the integrator could carry contact between bodies in its solve, but was told not to
  bool linearized = false;        // the integrator solved a linearized step (Integrator::linearizesItsStep)
  bool bouncing = false;          // a collider gives bounces back (restitution > 0): a lower one is worth trying
  bool moving_colliders = false;  // moving colliders did work on the bodies before the check
  // How often a step that made up energy was halved and taken again before this ([contact] split_steps); -1: the
  // integrator's steps are checked at the frames only (Simulation's energy retakes)
  int halvings = -1;
  // Particles were inside a collider, deeper than its band, at the run's start or at the start of a step that gained:
  // the likeliest cause, named first with its own advice (a smaller step does not help)
  std::optional<DeepInside> inside;
  double penalty_work = 0;  // J, work done by the integrator's contact forces up to there (Simulation::penaltyWork)
  double gained() const { return energy - start - collider_work - penalty_work; }
  // One paragraph for the user: what happened, where, and what to try.
  std::string message(double dt) const;
};

class Simulation {
 public:
  // Sets the system's step size (for static friction) to dt.
  Simulation(MassSpringSystem& system, std::unique_ptr<Integrator> integrator, double dt);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Steps until time() == t_end. Stops at once and returns what happened if the state blows up. At the end, checks the
  // energy (EnergyGain above): energyGain() holds the first check that failed; the caller decides whether to go on
  // (`wobble run` stops; the stability study runs on, so that a cell that then blows up counts as a blow-up).
  std::optional<BlowUp> advanceTo(double t_end);
  const std::optional<EnergyGain>& energyGain() const { return energy_gain_; }
  // Called after every step that did not blow up, with its end time and state (e.g. the renderer's motion blur keeps
  // the states inside a frame's shutter). Observing changes nothing in the stepping.
  using StepObserver = std::function<void(double t, const VecX& x)>;
  void observeSteps(StepObserver observer) { step_observer_ = std::move(observer); }
  double energyStart() const { return energy_start_; }
  // The energy the run's checks count (docs/energy.md): the system's total (kinetic, gravitational, elastic) at the
  // current state, plus what RK4's penalty layer holds (heldEnergy), less the work the integrator's contact forces did
  // on the bodies so far (penaltyWork: backward Euler's pairs' penalty, not a potential across steps). Without moving
  // colliders it may only fall. Tests read the same.
  double countedEnergy() const { return system_.energy(x_, v_) + heldEnergy() - penalty_work_; }
  // The energy RK4's penalty layer between bodies holds at the state (J; contact/collisions/stage_penalty.h): a
  // potential, part of countedEnergy. 0 for the other integrators.
  double heldEnergy() const;
  // Free particles that start inside a collider, deeper than its band (DeepInside); `wobble run` warns of them.
  const std::optional<DeepInside>& startsInside() const { return starts_inside_; }
  // Work done on the bodies by moving colliders so far (J): each step's contact impulse on a particle touching a
  // moving surface, times the surface's velocity (MassSpringSystem::colliderWork).
  double colliderWork() const { return collider_work_; }
  // Work done on the bodies by the integrator's contact forces so far (J): backward Euler's pairs' penalty
  // (Integrator::contactWork), over the steps taken.
  double penaltyWork() const { return penalty_work_; }

  const VecX& x() const { return x_; }
  const VecX& v() const { return v_; }
  double time() const { return t_; }
  long steps() const { return steps_; }
  double dt() const { return dt_; }
  // Largest particle speed seen at any step end so far (initial state included).
  double maxSpeed() const;
  // Over the step ends of the last advanceTo (a frame of `wobble run`): the largest particle speed and the largest
  // total kinetic energy (the end state, as run.json reports it: whether the scene has come to rest).
  double lastIntervalMaxSpeed() const { return std::sqrt(interval_speed_squared_); }
  double lastIntervalMaxKinetic() const { return interval_kinetic_; }
  const Integrator& integrator() const { return *integrator_; }
  const MassSpringSystem& system() const { return system_; }
  // Contact between bodies (sim/contact/): nothing when no two surface elements may meet.
  const collision::Stats* bodyContact() const { return collisions_ ? &collisions_->stats() : nullptr; }
  // Steps (or parts of one) the pass between bodies failed on and took again as two halves ([contact] split_steps).
  long splitSteps() const { return split_steps_; }
  // Steps (or parts of one) of an implicit integrator that made up energy, taken again the same way.
  long energyRetakes() const { return energy_retakes_count_; }

 private:
  // Step steps_ (or a part of it) of h from t0 to t1 (the end time exact for advanceTo's last step), with the contact
  // passes after it; splits: how many more times a step the pass between bodies fails on may be halved. Leaves t_ at
  // t1 (on a failure, at the end of the part that failed).
  std::optional<BlowUp> step(double t0, double h, double t1, int splits);
  // The same step again as two halves from its start state (x_before_, v_before_), splits - 1 more halvings allowed.
  std::optional<BlowUp> retakeInHalves(double t0, double h, double t1, int splits);
  std::optional<BlowUp> check();
  std::string contactFix() const;
  // Whether the integrator could carry contact between bodies in its solve but was told not to ([contact] in_solve).
  bool contactSolveOff() const;
  void checkEnergy();

  MassSpringSystem& system_;
  std::unique_ptr<Integrator> integrator_;
  double dt_;
  VecX x_, v_;
  double t_ = 0;
  long steps_ = 0, split_steps_ = 0, energy_retakes_count_ = 0;
  bool energy_retakes_ = false;            // every step's end is checked (an implicit integrator's)
  bool energy_retakes_exhausted_ = false;  // a smallest part made up energy: the run's check runs at every step
  // An explicit integrator: bodies resting on each other are held by the pass after the step alone
  // (BodyCollisions::resolve's resting).
  bool rests_on_pass_ = false;
  double max_speed_squared_ = 0;
  double interval_speed_squared_ = 0, interval_kinetic_ = 0;  // over the last advanceTo's steps
  std::unique_ptr<collision::BodyCollisions> collisions_;
  // x_ is as collisions_'s last pass left it: the next step's start continues from it (resolve's continues)
  bool x_is_last_pass_end_ = false;
  // What the integrator steps: the system, with the pairs of collisions_ for an implicit solve when bodies may touch
  // (ForceJacobian::bodyContacts); the system alone otherwise.
  // An explicit integrator's contact between bodies inside its stages (IntegratorTraits::contact_in_stages): the
  // penalty layer over the pairs within reach at each step's start (found towards x_reach_ = x + h v).
  std::unique_ptr<collision::StagePenalty> stages_;
  std::vector<ContactPair> stage_pairs_;
  VecX x_reach_;
  std::unique_ptr<Dynamics> with_contact_;
  const Dynamics& stepped() const { return with_contact_ ? *with_contact_ : system_; }
  double energy_start_ = 0, collider_work_ = 0, collider_work_unsigned_ = 0, lift_margin_ = 0;
  double penalty_work_ = 0;   // J: penaltyWork()
  VecX x_before_, v_before_;  // the state at the step's start, for collisions_ and the colliders' work
  std::optional<EnergyGain> energy_gain_;
  // Deepest particles inside a collider found so far (at the start, or at a gaining step's start), for EnergyGain
  std::optional<DeepInside> starts_inside_, inside_;
  StepObserver step_observer_;
};

}  // namespace wobble
