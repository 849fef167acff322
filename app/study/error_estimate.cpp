#include "app/study/error_estimate.h"

#include <chrono>
#include <cmath>
#include <sstream>

namespace wobble {

ErrorEstimator::ErrorEstimator(SceneFile scene, const std::string& integrator, const IntegratorOptions& options,
                               double dt)
    : scene_(std::move(scene)) {
  IntegratorOptions half = options;
  const IntegratorTraits& traits = integratorTraits(integrator);
  const bool adaptive = traits.adaptive;
  if (adaptive) {
    half.rtol /= 32;
    half.atol /= 32;
  }
  e_.order = traits.order;  // at least 1: checked where the method table is compiled
  e_.factor = std::ldexp(1.0, e_.order) / (std::ldexp(1.0, e_.order) - 1);
  run_ = std::make_unique<RunDriver>(*scene_.system, integrator, half, adaptive ? dt : dt / 2);
}

void ErrorEstimator::compare(double t, const VecX& x) {
  if (!e_.failure.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  try {
    if (const auto blow_up = run_->advanceTo(t)) {
      std::ostringstream m;
      m << "the half-step run blew up at t = " << blow_up->time << " s";
      e_.failure = m.str();
    }
  } catch (const std::exception& ex) {
    e_.failure = std::string("the half-step run failed: ") + ex.what();
  }
  e_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!e_.failure.empty()) return;
  const MassSpringSystem& system = *scene_.system;
  double frame_max = 0;
  for (int i = 0; i < system.particleCount(); ++i) {
    if (system.inverseMass()[i] == 0) continue;
    const double d = e_.factor * (particle(x, i) - particle(run_->x(), i)).norm();
    frame_max = std::max(frame_max, d);
    sum_squares_ += d * d;
    ++count_;
  }
  e_.max_error = std::max(e_.max_error, frame_max);
  e_.final_max_error = frame_max;
  ++e_.frames;
}

ErrorEstimate ErrorEstimator::result() const {
  ErrorEstimate e = e_;
  e.rms_error = count_ > 0 ? std::sqrt(sum_squares_ / double(count_)) : 0;
  return e;
}

}  // namespace wobble
