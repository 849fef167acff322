// Classical fourth-order Runge-Kutta on the first-order system (x' = v, v' = a). Every stage starts from the
// step's start state (x0, v0); forgetting that is what made a course framework's RK4 jelly fall in slow motion.
#include "sim/integrators/methods.h"
#include "sim/solver/parallel.h"

namespace wobble {
namespace {

class RungeKutta4 final : public Integrator {
 public:
  std::string_view name() const override { return "rk4"; }
  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override {
    ++stats_.steps;
    stats_.evaluations += 4;
    // Stage k_i = (dx_i, dv_i) = (v_i, a(x_i, v_i)), accumulated into sum_x, sum_v with weights 1, 2, 2, 1.
    // The vector updates between evaluations run in one pass each, elementwise (forEachSegment).
    const Eigen::Index size = x.size();
    for (VecX* y : {&xs_, &vs_, &sum_x_, &sum_v_}) y->resize(size);
    dynamics.acceleration(t, x, v, a_);
    forEachSegment(size, [&](Eigen::Index i, Eigen::Index n) {
      sum_x_.segment(i, n) = v.segment(i, n);
      sum_v_.segment(i, n) = a_.segment(i, n);
      xs_.segment(i, n) = x.segment(i, n) + (h / 2) * v.segment(i, n);
      vs_.segment(i, n) = v.segment(i, n) + (h / 2) * a_.segment(i, n);
    });
    dynamics.acceleration(t + h / 2, xs_, vs_, a_);
    forEachSegment(size, [&](Eigen::Index i, Eigen::Index n) {
      sum_x_.segment(i, n) += 2 * vs_.segment(i, n);
      sum_v_.segment(i, n) += 2 * a_.segment(i, n);
      xs_.segment(i, n) = x.segment(i, n) + (h / 2) * vs_.segment(i, n);
      vs_.segment(i, n) = v.segment(i, n) + (h / 2) * a_.segment(i, n);
    });
    dynamics.acceleration(t + h / 2, xs_, vs_, a_);
    forEachSegment(size, [&](Eigen::Index i, Eigen::Index n) {
      sum_x_.segment(i, n) += 2 * vs_.segment(i, n);
      sum_v_.segment(i, n) += 2 * a_.segment(i, n);
      xs_.segment(i, n) = x.segment(i, n) + h * vs_.segment(i, n);
      vs_.segment(i, n) = v.segment(i, n) + h * a_.segment(i, n);
    });
    dynamics.acceleration(t + h, xs_, vs_, a_);
    forEachSegment(size, [&](Eigen::Index i, Eigen::Index n) {
      sum_x_.segment(i, n) += vs_.segment(i, n);
      sum_v_.segment(i, n) += a_.segment(i, n);
      x.segment(i, n) += (h / 6) * sum_x_.segment(i, n);
      v.segment(i, n) += (h / 6) * sum_v_.segment(i, n);
    });
  }

 private:
  VecX a_, xs_, vs_, sum_x_, sum_v_;
};

}  // namespace
std::unique_ptr<Integrator> makeRk4(const IntegratorOptions&) { return std::make_unique<RungeKutta4>(); }
}  // namespace wobble
