// Symplectic (semi-implicit) Euler: v1 = v0 + h a(t, x0, v0), then x1 = x0 + h v1.
// First order, one evaluation per step. Symplectic for conservative forces: on an undamped oscillator the energy
// oscillates but does not drift, and it is stable up to omega h = 2; with explicit damping (dampers, drag) the limit
// drops to 2 (sqrt(1 + zeta^2) - zeta). No options.
#include "sim/integrators/methods.h"
#include "sim/solver/parallel.h"

namespace wobble {
namespace {

class SymplecticEuler final : public Integrator {
 public:
  std::string_view name() const override { return "symplectic-euler"; }
  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override {
    ++stats_.steps;
    ++stats_.evaluations;
    dynamics.acceleration(t, x, v, a_);
    forEachSegment(x.size(), [&](Eigen::Index i, Eigen::Index n) {
      v.segment(i, n) += h * a_.segment(i, n);
      x.segment(i, n) += h * v.segment(i, n);  // with the new velocity: what makes the map symplectic
    });
  }

 private:
  VecX a_;
};

}  // namespace
std::unique_ptr<Integrator> makeSymplecticEuler(const IntegratorOptions&) {
  return std::make_unique<SymplecticEuler>();
}
}  // namespace wobble
