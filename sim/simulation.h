// Steps a MassSpringSystem with an integrator: fixed steps of dt, the last one before a requested time shortened
// to land on it exactly (never an extra sliver step for round-off: a 3 s run at dt 1e-4 is 30000 steps); contact
// resolution at every step end; blow-up detection after every step.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "sim/collision/body_collisions.h"
#include "sim/integrators/integrator.h"
#include "sim/system.h"

namespace wobble {

// The course framework's rule: the run is unstable once any velocity is NaN or any |v|^2 exceeds this.
inline constexpr double kBlowUpSpeedSquared = 1e6;

struct BlowUp {
  std::string integrator;
  long step;             // 1-based index of the step that blew up
  double time;           // simulated time at its end
  int particle;          // first offending particle
  double speed_squared;  // NaN when a value was NaN
  std::string reason;    // set when contact between bodies failed (then speed_squared is 0): what is left, where
  // One paragraph for the user: what happened, where, and what to try.
  std::string message(double dt) const;
};

class Simulation {
 public:
  // Sets the system's step size (for static friction) to dt.
  Simulation(MassSpringSystem& system, std::unique_ptr<Integrator> integrator, double dt);

  // Steps until time() == t_end. Stops at once and returns what happened if the state blows up.
  std::optional<BlowUp> advanceTo(double t_end);

  const VecX& x() const { return x_; }
  const VecX& v() const { return v_; }
  double time() const { return t_; }
  long steps() const { return steps_; }
  double dt() const { return dt_; }
  // Largest particle speed seen at any step end so far (initial state included).
  double maxSpeed() const;
  const Integrator& integrator() const { return *integrator_; }
  const MassSpringSystem& system() const { return system_; }
  // Contact between bodies (sim/collision/): nothing when no two surface elements may meet.
  const collision::Stats* bodyContact() const { return collisions_ ? &collisions_->stats() : nullptr; }

 private:
  std::optional<BlowUp> check();

  const MassSpringSystem& system_;
  std::unique_ptr<Integrator> integrator_;
  double dt_;
  VecX x_, v_;
  double t_ = 0;
  long steps_ = 0;
  double max_speed_squared_ = 0;
  std::unique_ptr<collision::BodyCollisions> collisions_;
  VecX x_start_;  // the step's start, for collisions_
};

}  // namespace wobble
