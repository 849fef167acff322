// Explicit midpoint (RK2): one Euler half step, then the full step with the midpoint derivative. Second order.
#include "sim/integrators/methods.h"

namespace wobble {
namespace {

class Midpoint final : public Integrator {
 public:
  std::string_view name() const override { return "midpoint"; }
  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override {
    ++stats_.steps;
    stats_.evaluations += 2;
    dynamics.acceleration(t, x, v, a_);
    xm_ = x + (h / 2) * v;
    vm_ = v + (h / 2) * a_;
    dynamics.acceleration(t + h / 2, xm_, vm_, a_);
    x += h * vm_;
    v += h * a_;
  }

 private:
  VecX a_, xm_, vm_;
};

}  // namespace
std::unique_ptr<Integrator> makeMidpoint(const IntegratorOptions&) { return std::make_unique<Midpoint>(); }
}  // namespace wobble
