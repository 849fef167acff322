// Explicit (forward) Euler: x1 = x0 + h v0, v1 = v0 + h a(x0, v0). First order; unstable on undamped oscillators.
#include "sim/integrators/methods.h"
#include "sim/solver/parallel.h"

namespace wobble {
namespace {

class ExplicitEuler final : public Integrator {
 public:
  std::string_view name() const override { return "explicit-euler"; }
  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override {
    ++stats_.steps;
    stats_.evaluations += 1;
    dynamics.acceleration(t, x, v, a_);
    forEachSegment(x.size(), [&](Eigen::Index i, Eigen::Index n) {
      x.segment(i, n) += h * v.segment(i, n);
      v.segment(i, n) += h * a_.segment(i, n);
    });
  }

 private:
  VecX a_;
};

}  // namespace
std::unique_ptr<Integrator> makeExplicitEuler(const IntegratorOptions&) { return std::make_unique<ExplicitEuler>(); }
}  // namespace wobble
