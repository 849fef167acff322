// A time integrator advances (x, v) by one step of a Dynamics. Integrators know nothing about particles,
// springs or contacts; they may only call Dynamics::acceleration, and write x and v once, at the step's end.
#pragma once
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "sim/dynamics.h"

namespace wobble {

// backward-euler's preconditioner (filtered_pcg.h). Auto: block-Jacobi, and two-level on a system of at least
// kTwoLevelParticles particles once a block-Jacobi solve has taken more than kTwoLevelIterations iterations, back to
// block-Jacobi when a two-level solve takes fewer than a quarter of that (measured: docs/integrators.md).
enum class CgPreconditioner { Auto, BlockJacobi, TwoLevel };
inline constexpr int kTwoLevelParticles = 2000;
inline constexpr int kTwoLevelIterations = 40;

// What backward Euler's Newton iteration backtracks on (IntegratorOptions::line_search).
enum class LineSearch { Potential, Residual };

// Settings that only some methods read (adaptive and implicit ones); the defaults suit the shipped scenes.
struct IntegratorOptions {
  double rtol = 1e-6, atol = 1e-9;  // rk45: relative and absolute error tolerances per step
  long max_substeps = 100000;       // rk45: attempted substeps allowed in one step() before it gives up
  bool newton = false;              // backward-euler: iterate Newton to convergence instead of one step
  double newton_tolerance = 1e-8;   // backward-euler newton: max |M^-1 residual| (m/s), relative to max(1, |v|)
  int newton_max_iterations = 50;   // backward-euler: linear solves of a step's Newton iteration, the first included
  // backward-euler: what Newton's iteration backtracks on (backward_euler.h): the step's incremental potential
  // (Gast et al. 2015; a step that would raise it is not taken) or the residual's norm; and at most how many halvings
  // of a Newton step it tries.
  LineSearch line_search = LineSearch::Potential;
  int line_search_halvings = 10;
  // backward-euler: the conjugate-gradient solve stops at this relative residual |S (b - A dv)| / |S (b - A z)|
  // (filtered_pcg.h); docs/integrators.md, "The linear solve", for how the default was chosen.
  double cg_tolerance = 1e-3;
  // backward-euler (without newton): the solve also stops once its error is at most this fraction of the step's own
  // error, estimated from the last two steps (after three without contact constraints); 0: cg_tolerance alone
  // (docs/integrators.md, "The error rule").
  double cg_error_fraction = 0.1;
  int cg_max_iterations = 1000;
  CgPreconditioner cg_preconditioner = CgPreconditioner::Auto;
  // backward-euler: contact between bodies inside the solve (a penalty on each near pair, docs/body-contact.md); false:
  // left to the pass after the step, as for the explicit methods (for comparison: the benchmarks and the docs'
  // figures).
  bool body_contact_in_solve = true;
};

// Work counters for the studies. Every method counts steps and evaluations; the others stay 0 where meaningless.
struct IntegratorStats {
  long steps = 0;                   // step() calls
  long evaluations = 0;             // Dynamics::acceleration calls, plus smooth-force evaluations of Newton residuals
  long accepted = 0, rejected = 0;  // rk45: adaptive substeps
  double next_substep = 0;          // rk45: the controller's preferred size of the next substep
  long jacobians = 0;               // backward-euler: force-Jacobian assemblies
  long cg_iterations = 0;           // backward-euler: conjugate-gradient iterations, all steps
  int last_cg_iterations = 0;       // backward-euler: in the last step (summed over its linear solves)
  int last_linear_solves = 0;       // backward-euler: in the last step (1 unless newton)
  double last_residual = 0;         // backward-euler newton: the last step's final |M^-1 residual|_inf (m/s)
  double last_cg_residual = 0;      // backward-euler: achieved relative CG residual, the last step's worst solve
  double max_cg_residual = 0;       // backward-euler: the same, worst over all steps
  long error_rule_stops = 0;        // backward-euler: solves that stopped by cg_error_fraction before cg_tolerance
  long tolerance_stops = 0;         // backward-euler: solves that reached cg_tolerance (or had nothing to solve)
  long iteration_cap_stops = 0;     // backward-euler: solves stopped by cg_max_iterations above both bounds
  double max_cg_residual_error_rule = 0;  // backward-euler: the worst relative residual of the error rule's stops
  double max_cg_residual_cap = 0;         // backward-euler: ... of the iteration cap's
  long pattern_setups = 0;   // backward-euler: matrices sized for a new Jacobian pattern (once per topology)
  long impact_solves = 0;    // backward-euler: extra solves with impact constraints (contact/constraints/constraints.h)
  long friction_solves = 0;  // backward-euler: extra solves with friction brought within Coulomb's cone (boundFriction)
  long body_contact_solves = 0;  // backward-euler: extra solves with contact between bodies (ContactPair)
  long body_contact_pairs = 0;   // backward-euler: pairs of surface elements in those solves, all steps
  // backward-euler: Newton iterations that stopped because no step along their direction lowered the incremental
  // potential (line_search = potential)
  long line_search_stops = 0;
  // backward-euler: Newton iterates whose end changed which contact pairs are pressed (the active set taken anew)
  long newton_pair_updates = 0;
  long exact_steps = 0;  // backward-euler without newton: steps whose linearized solve made up energy,
                         // solved exactly instead (ForceJacobian::energyMadeUp)
  // backward-euler, contact between bodies in the solve (run.json's body_contact, docs/body-contact.md):
  long linear_solves = 0;                   // linear solves, all steps and causes
  long body_contact_steps = 0;              // steps whose solve carried at least one pair
  long body_contact_pairs_carried = 0;      // near pairs in a step's solve (pressed or released), summed over steps
  long body_contact_active_set_solves = 0;  // extra solves because pairs joined or the pressed set changed
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual std::string_view name() const = 0;
  // Advances x, v from time t to t + h.
  virtual void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) = 0;
  // Whether step() keeps the surfaces of bodies apart itself (ForceJacobian::bodyContacts): then the pass after the
  // step (sim/contact/collisions/body_collisions.h) only checks for collisions and leaves out its repulsion.
  virtual bool solvesBodyContact() const { return false; }
  // Whether step() solves one linearization of an implicit method's equations rather than the equations themselves
  // (backward Euler without newton): a spring that turns or shortens by much of its length within a step may then
  // store energy the linearization makes up (docs/contact.md, Friction under backward Euler).
  virtual bool linearizesItsStep() const { return false; }
  // The work its contact forces did on the bodies over its last step (J), where they are not a potential the energy
  // can count: backward Euler's pairs' penalty, whose normal, weights and rest gap each step takes afresh
  // (PenaltyPairs::work; docs/energy.md, "What counts as energy"). 0 for the others.
  virtual double contactWork() const { return 0; }
  const IntegratorStats& stats() const { return stats_; }

 protected:
  IntegratorStats stats_;
};

// What a study or an estimate needs to know of a method, kept beside its constructor in the method table
// (integrator.cpp), so that no caller compares names. Every method must state its order (checked when compiled).
struct IntegratorTraits {
  int order = 0;          // of global accuracy (docs/numerics.md): error ~ C h^order on a smooth problem
  bool adaptive = false;  // chooses its own substeps: dt is only its largest step, tolerances set the accuracy
  bool a_stable = false;  // stable at any step on a damped linear oscillator: no fixed-step limit
  bool implicit = false;  // solves a linear system each step: assembles force Jacobians (memory, scene_limits.h)
  // can carry contact between bodies inside its solve ([contact] in_solve, IntegratorOptions::body_contact_in_solve);
  // the others always leave it to the pass after the step
  bool body_contact_in_solve = false;
  // explicit: carries contact between bodies as a penalty inside its stages (contact/collisions/stage_penalty.h)
  bool contact_in_stages = false;
};

// The names makeIntegrator accepts, in the order the docs list them.
std::span<const std::string_view> integratorNames();
// Throws std::invalid_argument naming the allowed values when name is unknown.
const IntegratorTraits& integratorTraits(std::string_view name);
// Throws std::invalid_argument naming the allowed values when name is unknown.
std::unique_ptr<Integrator> makeIntegrator(std::string_view name, const IntegratorOptions& options = {});

}  // namespace wobble
