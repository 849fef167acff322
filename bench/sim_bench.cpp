// One step of each integrator on the default jelly (10^3), the default cloth (25 x 25) and a 256 x 256 cloth, with
// 1 and 2 TBB threads (second argument; systems below the parallel threshold run on one either way), reporting
// springs per second: springs x steps / wall second. A method with k force evaluations per step (RK4: 4) does k
// times that many spring evaluations; compare methods by "steps/s", the force loop by explicit Euler's "springs/s".
// threshold/METHOD/SIDE/PARALLEL: a SIDE x SIDE cloth (dt 1e-4), serially (PARALLEL 0) or on 2 threads with the
// parallel threshold lowered to 0 (1): where threads start to pay (sim/solver/parallel.h's threshold).
// Run: build/sim_bench [--benchmark_filter=rk4]
#include <benchmark/benchmark.h>

#include <tbb/global_control.h>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/integrators/integrator.h"
#include "sim/solver/parallel.h"
#include "sim/system.h"

namespace wobble {
namespace {

MassSpringSystem makeSystem(int which) {
  MassSpringSystem system;
  if (which == 0) {
    system.addBody(buildJelly("jelly", {}));
  } else {
    ClothParams p;
    if (which == 2) p.nx = p.ny = 256;
    p.pinned = clothPinSet("corners", p.nx, p.ny);
    system.addBody(buildCloth("cloth", p));
  }
  return system;
}

const char* kSystemNames[] = {"jelly10", "cloth25", "cloth256"};

// Steps system with method at dt, one step per benchmark iteration.
void stepWhileTimed(benchmark::State& state, MassSpringSystem& system, std::string_view method, double dt) {
  system.setStepSize(dt);
  auto integrator = makeIntegrator(method);
  VecX x = system.initialPositions(), v = system.initialVelocities();
  double t = 0;
  for (auto _ : state) {
    integrator->step(system, t, dt, x, v);
    t += dt;
    benchmark::DoNotOptimize(x.data());
  }
}

void step(benchmark::State& state, std::string_view method) {
  const int which = static_cast<int>(state.range(0));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(1));
  MassSpringSystem system = makeSystem(which);
  stepWhileTimed(state, system, method, which == 0 ? 1e-3 : 1e-4);
  state.SetLabel(kSystemNames[which]);
  state.counters["steps/s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["springs/s"] =
      benchmark::Counter(double(state.iterations() * system.springs().size()), benchmark::Counter::kIsRate);
}

void threshold(benchmark::State& state, std::string_view method) {
  const int side = static_cast<int>(state.range(0));
  const bool parallel = state.range(1) != 0;
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, parallel ? 2 : 1);
  const int saved = parallelThreshold();
  setParallelThreshold(parallel ? 0 : side * side + 1);
  {
    ClothParams p;
    p.nx = p.ny = side;
    p.pinned = clothPinSet("corners", p.nx, p.ny);
    MassSpringSystem system;
    system.addBody(buildCloth("cloth", p));
    stepWhileTimed(state, system, method, 1e-4);
  }
  setParallelThreshold(saved);
}

void registerAll() {
  for (std::string_view method : {"explicit-euler", "rk4", "backward-euler"})
    benchmark::RegisterBenchmark(("threshold/" + std::string(method)).c_str(), threshold, method)
        ->ArgsProduct({{16, 24, 28, 32, 48, 64, 80, 100}, {0, 1}})
        ->UseRealTime()
        ->Unit(benchmark::kMicrosecond);
  for (std::string_view method : integratorNames())
    benchmark::RegisterBenchmark(("step/" + std::string(method)).c_str(), step, method)
        ->ArgsProduct({{0, 1, 2}, {1, 2}})
        ->UseRealTime()  // wall time: the CPU time of the main thread alone would flatter two threads
        ->Unit(benchmark::kMicrosecond);
}

const int registered = (registerAll(), 0);

}  // namespace
}  // namespace wobble
