// Classical fourth-order Runge-Kutta on the first-order system (x' = v, v' = a). Every stage starts from the
// step's start state (x0, v0); forgetting that is what made a course framework's RK4 jelly fall in slow motion.
#include "sim/integrators/methods.h"

namespace wobble {
namespace {

class RungeKutta4 final : public Integrator {
 public:
  std::string_view name() const override { return "rk4"; }
  void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) override {
    ++stats_.steps;
    stats_.evaluations += 4;
    // Stage k_i = (dx_i, dv_i) = (v_i, a(x_i, v_i)), accumulated into sum_x, sum_v with weights 1, 2, 2, 1.
    dynamics.acceleration(t, x, v, a_);
    sum_x_ = v;
    sum_v_ = a_;

    xs_ = x + (h / 2) * v;
    vs_ = v + (h / 2) * a_;
    dynamics.acceleration(t + h / 2, xs_, vs_, a_);
    sum_x_ += 2 * vs_;
    sum_v_ += 2 * a_;

    xs_ = x + (h / 2) * vs_;
    vs_ = v + (h / 2) * a_;
    dynamics.acceleration(t + h / 2, xs_, vs_, a_);
    sum_x_ += 2 * vs_;
    sum_v_ += 2 * a_;

    xs_ = x + h * vs_;
    vs_ = v + h * a_;
    dynamics.acceleration(t + h, xs_, vs_, a_);
    sum_x_ += vs_;
    sum_v_ += a_;

    x += (h / 6) * sum_x_;
    v += (h / 6) * sum_v_;
  }

 private:
  VecX a_, xs_, vs_, sum_x_, sum_v_;
};

}  // namespace
std::unique_ptr<Integrator> makeRk4(const IntegratorOptions&) { return std::make_unique<RungeKutta4>(); }
}  // namespace wobble
