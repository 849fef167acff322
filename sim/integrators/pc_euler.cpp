// The course framework's "implicit Euler", named honestly: a predictor-corrector built from explicit stages.
// Predict (xp, vp) by explicit Euler, re-evaluate the acceleration there, and apply it from the start state:
//   x1 = x0 + h vp,  v1 = v0 + h a(t + h, xp, vp).
// On y' = lambda y this is y1 = (1 + z + z^2) y0 with z = h lambda: an explicit method, first order, stable on an
// undamped oscillator only up to omega h = 1. It is not backward Euler.
#include "sim/integrators/methods.h"
#include "sim/solver/parallel.h"

namespace wobble {
namespace {

class PredictorCorrectorEuler final : public Integrator {
 public:
  std::string_view name() const override { return "pc-euler"; }
  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override {
    ++stats_.steps;
    stats_.evaluations += 2;
    dynamics.acceleration(t, x, v, a_);
    xp_.resize(x.size());
    vp_.resize(v.size());
    forEachSegment(x.size(), [&](Eigen::Index i, Eigen::Index n) {
      xp_.segment(i, n) = x.segment(i, n) + h * v.segment(i, n);
      vp_.segment(i, n) = v.segment(i, n) + h * a_.segment(i, n);
    });
    dynamics.acceleration(t + h, xp_, vp_, a_);
    forEachSegment(x.size(), [&](Eigen::Index i, Eigen::Index n) {
      x.segment(i, n) += h * vp_.segment(i, n);
      v.segment(i, n) += h * a_.segment(i, n);
    });
  }

 private:
  VecX a_, xp_, vp_;
};

}  // namespace
std::unique_ptr<Integrator> makePcEuler(const IntegratorOptions&) {
  return std::make_unique<PredictorCorrectorEuler>();
}
}  // namespace wobble
