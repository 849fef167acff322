// The course framework's "implicit Euler", named honestly: a predictor-corrector built from explicit stages.
// Predict (xp, vp) by explicit Euler, re-evaluate the acceleration there, and apply it from the start state:
//   x1 = x0 + h vp,  v1 = v0 + h a(t + h, xp, vp).
// On y' = lambda y this is y1 = (1 + z + z^2) y0 with z = h lambda: an explicit method, first order, stable on an
// undamped oscillator only up to omega h = 1. It is not backward Euler.
#include "sim/integrators/methods.h"

namespace wobble {
namespace {

class PredictorCorrectorEuler final : public Integrator {
 public:
  std::string_view name() const override { return "pc-euler"; }
  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override {
    ++stats_.steps;
    stats_.evaluations += 2;
    dynamics.acceleration(t, x, v, a_);
    xp_ = x + h * v;
    vp_ = v + h * a_;
    dynamics.acceleration(t + h, xp_, vp_, a_);
    x += h * vp_;
    v += h * a_;
  }

 private:
  VecX a_, xp_, vp_;
};

}  // namespace
std::unique_ptr<Integrator> makePcEuler(const IntegratorOptions&) {
  return std::make_unique<PredictorCorrectorEuler>();
}
}  // namespace wobble
