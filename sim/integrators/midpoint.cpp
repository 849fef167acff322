// Explicit midpoint (RK2): one Euler half step, then the full step with the midpoint derivative. Second order.
#include "sim/integrators/methods.h"
#include "sim/solver/parallel.h"

namespace wobble {
namespace {

class Midpoint final : public Integrator {
 public:
  std::string_view name() const override { return "midpoint"; }
  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override {
    ++stats_.steps;
    stats_.evaluations += 2;
    dynamics.acceleration(t, x, v, a_);
    xm_.resize(x.size());
    vm_.resize(v.size());
    forEachSegment(x.size(), [&](Eigen::Index i, Eigen::Index n) {
      xm_.segment(i, n) = x.segment(i, n) + (h / 2) * v.segment(i, n);
      vm_.segment(i, n) = v.segment(i, n) + (h / 2) * a_.segment(i, n);
    });
    dynamics.acceleration(t + h / 2, xm_, vm_, a_);
    forEachSegment(x.size(), [&](Eigen::Index i, Eigen::Index n) {
      x.segment(i, n) += h * vm_.segment(i, n);
      v.segment(i, n) += h * a_.segment(i, n);
    });
  }

 private:
  VecX a_, xm_, vm_;
};

}  // namespace
std::unique_ptr<Integrator> makeMidpoint(const IntegratorOptions&) { return std::make_unique<Midpoint>(); }
}  // namespace wobble
