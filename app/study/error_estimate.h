// `wobble run --estimate-error`: an estimate of a run's own error at its frames by step halving. A second copy of
// the scene is simulated in lock step at half the step (an adaptive method, rk45: at rtol and atol / 32, which halves
// its substeps since its local error goes as h^5); at every frame the distance d between the two runs' particle
// positions is Richardson-scaled by the method's order p (IntegratorTraits, sim/integrators/integrator.h),
// error(dt) ~ d 2^p / (2^p - 1), which is exact when the error is C dt^p. Reported over the frames compared and the
// moving particles, in metres: the largest, the RMS, and the largest at the last frame; plus the rerun's wall time
// (it costs about twice the run). Contacts make the error non-smooth in dt, so there the figure is an indication,
// not a bound.
#pragma once
#include <memory>
#include <string>

#include "app/run/run_driver.h"
#include "app/scene/scene_file.h"

namespace wobble {

struct ErrorEstimate {
  int order = 0;      // p used for the Richardson factor
  double factor = 0;  // 2^p / (2^p - 1)
  double max_error = 0, rms_error = 0, final_max_error = 0;
  int frames = 0;       // frames compared
  double seconds = 0;   // wall time of the half-step run
  std::string failure;  // non-empty when the half-step run blew up or failed: the estimate then covers fewer frames
};

class ErrorEstimator {
 public:
  // scene: a fresh copy of the run's scene (the estimator simulates its own system).
  ErrorEstimator(SceneFile scene, const std::string& integrator, const IntegratorOptions& options, double dt);
  // Advances the half-step run to time t and compares it with x, the run's positions at t.
  void compare(double t, const VecX& x);
  ErrorEstimate result() const;

 private:
  SceneFile scene_;
  std::unique_ptr<RunDriver> run_;  // the half-step run
  ErrorEstimate e_;
  double sum_squares_ = 0;
  long count_ = 0;
};

}  // namespace wobble
