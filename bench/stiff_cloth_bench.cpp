// The stiff cloth: 100 x 100 particles, ks 1e5 (kd 750, mass 1 per particle, 4 x 4 m, corners pinned), falling
// under gravity for one simulated second, no colliders. Backward Euler at dt 1/60 against RK4 at its largest stable
// dt, wall time side by side, with backward Euler's conjugate-gradient iterations per step (its defaults; the
// tolerance alone, without the error rule (cg_error_fraction 0); block-Jacobi alone). RK4's largest stable dt
// is found once, before timing: bisection in log dt (to 2%) on 0.25 s runs between a stable and a blowing-up step,
// then shrunk by 2% until a whole second survives (the blow-up rule of sim/simulation.h).
// Run: build/stiff_cloth_bench (about a minute: the search runs RK4 a dozen times).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>

#include "sim/bodies/cloth.h"
#include "sim/integrators/integrator.h"
#include "sim/simulation.h"
#include "sim/springs.h"

namespace wobble {
namespace {

MassSpringSystem makeCloth() {
  ClothParams p;
  p.nx = p.ny = 100;
  p.ks = 1e5;
  p.pinned = clothPinSet("corners", p.nx, p.ny);
  MassSpringSystem system;
  system.addBody(buildCloth("cloth", p));
  return system;
}

bool survives(double dt, double duration) {
  MassSpringSystem system = makeCloth();
  Simulation sim(system, makeIntegrator("rk4"), dt);
  return !sim.advanceTo(duration);
}

double rk4LargestStableDt() {
  static const double dt = [] {
    double lo = 2e-5, hi = 2e-3;  // stable, unstable
    while (hi / lo > 1.02) {
      const double mid = std::sqrt(lo * hi);
      (survives(mid, 0.25) ? lo : hi) = mid;
    }
    while (!survives(lo, 1.0)) lo /= 1.02;
    std::printf("rk4 largest stable dt on the stiff cloth: %.4g s (%.4g s blew up within 0.25 s)\n", lo, hi);
    return lo;
  }();
  return dt;
}

void report(benchmark::State& state, const Simulation& sim, const MassSpringSystem& system, bool blew_up) {
  const IntegratorStats& s = sim.integrator().stats();
  state.counters["dt"] = sim.dt();
  state.counters["steps"] = double(sim.steps());
  state.counters["evals"] = double(s.evaluations);
  state.counters["cg_per_step"] = s.steps ? double(s.cg_iterations) / double(s.steps) : 0;
  state.counters["cg_max_residual"] = s.max_cg_residual;
  state.counters["error_rule_stops"] = double(s.error_rule_stops);
  state.counters["max_strain"] = maxStrain(system.springs(), sim.x());
  state.counters["blew_up"] = blew_up ? 1 : 0;
}

// error_rule: backward Euler's cg_error_fraction at its default (true) or 0, cg_tolerance alone (false).
void stiffCloth(benchmark::State& state, const char* method, CgPreconditioner preconditioner, bool error_rule) {
  const double dt = std::string_view(method) == "rk4" ? rk4LargestStableDt() : 1.0 / 60;
  IntegratorOptions options;
  options.cg_preconditioner = preconditioner;
  if (!error_rule) options.cg_error_fraction = 0;
  for (auto _ : state) {
    state.PauseTiming();
    MassSpringSystem system = makeCloth();
    state.ResumeTiming();
    Simulation sim(system, makeIntegrator(method, options), dt);
    const bool blew_up = sim.advanceTo(1.0).has_value();
    state.PauseTiming();
    report(state, sim, system, blew_up);
    state.ResumeTiming();
  }
}

BENCHMARK_CAPTURE(stiffCloth, backward_euler_dt_1_60, "backward-euler", CgPreconditioner::Auto, true)
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(stiffCloth, backward_euler_tolerance_only_dt_1_60, "backward-euler", CgPreconditioner::Auto, false)
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(stiffCloth, backward_euler_block_jacobi_dt_1_60, "backward-euler", CgPreconditioner::BlockJacobi,
                  true)
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(stiffCloth, rk4_largest_stable_dt, "rk4", CgPreconditioner::Auto, true)
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace wobble
