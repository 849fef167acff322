// What two of contact's defaults cost between jellies (docs/body-contact.md, "Momentum" and "Self-contact"):
//   BM_FreePairImpact/k: the free pair of scenes/jelly_shot.toml (tests/sim/jelly_shot.h: a 1.28 kg jelly at 25 m/s
//   into a 25.6 kg one, no gravity, no colliders) under backward Euler at 1/60 s with cg_tolerance 10^-k, each
//   iteration the run from the start to 0.25 s (15 steps, the impact and the rebound). k = 3 is the default, whose
//   momentum the rigid-mode correction keeps (keepMomentum, backward_euler.h); k = 8 keeps it by solving tightly
//   instead, the other way to the same momentum; 4 and 5 between. Counters: drift, |p - p0| / |p0| at the end;
//   cg/step, the CG iterations a step; solves/step.
//   BM_JellySelfContact/i/s: scenes/jelly_stack.toml's two jellies (tests/sim/jelly_stack.h), the upper one dropped
//   onto the lower, landing at about 0.5 s and coming to rest: each iteration the run from the start to 1.5 s, with
//   both jellies' self-contact off (s = 0) and on (1, the default of a jelly among other bodies); i = 0: backward
//   Euler at 1/60 s, 1: RK4 at 1e-3 s (the scene's own integrator).
//   BM_WellSelfContact/s: bench/scenes/jelly_well.toml, two soft jellies pressed into a well barely wider than they
//   are (the squeeze that folds the lower one through itself without self-contact:
//   tests/app/self_contact_default_test.cpp), with self-contact off (s = 0) and at the shipped default (1), backward
//   Euler at 1/60 s, each iteration the run from the start to 3 s.
// Wall time (each iteration one run; setup untimed) and the process's CPU time (both threads).
// Run from the project root: taskset -c 0,1 build/jelly_contact_bench (two cores).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "app/scene/scene_file.h"
#include "sim/simulation.h"
#include "tests/sim/jelly_shot.h"
#include "tests/sim/jelly_stack.h"
#include "tests/sim/momentum.h"

namespace wobble {
namespace {

constexpr const char* kWell = "bench/scenes/jelly_well.toml";

// Runs a fresh copy of `build`'s system to `end`, timed; counters per step of the last run.
template <class Build>
void runs(benchmark::State& state, Build&& build, const char* integrator, const IntegratorOptions& options, double dt,
          double end) {
  for (auto _ : state) {
    state.PauseTiming();
    const std::unique_ptr<MassSpringSystem> system = build();
    Simulation sim(*system, makeIntegrator(integrator, options), dt);
    const Vec3 p0 = testing::momentum(*system, sim.v());
    state.ResumeTiming();
    if (sim.advanceTo(end)) state.SkipWithError("the run stopped");
    state.PauseTiming();
    const double steps = double(sim.steps());
    const IntegratorStats& s = sim.integrator().stats();
    if (s.cg_iterations > 0) {
      state.counters["cg/step"] = double(s.cg_iterations) / steps;
      state.counters["solves/step"] = double(s.linear_solves) / steps;
    }
    if (const collision::Stats* c = sim.bodyContact()) state.counters["contacts/step"] = double(c->contacts) / steps;
    if (p0.norm() > 0) state.counters["drift"] = (testing::momentum(*system, sim.v()) - p0).norm() / p0.norm();
    state.ResumeTiming();
  }
}

void BM_FreePairImpact(benchmark::State& state) {
  IntegratorOptions options;
  options.cg_tolerance = std::pow(10.0, -double(state.range(0)));
  runs(
      state, [] { return testing::jellyShot(); }, "backward-euler", options, 1.0 / 60, 0.25);
}

void BM_JellySelfContact(benchmark::State& state) {
  const bool self_contact = state.range(1) != 0;
  const auto build = [&] { return testing::jellyStack(self_contact); };
  if (state.range(0) == 0) runs(state, build, "backward-euler", {}, 1.0 / 60, 1.5);
  else runs(state, build, "rk4", {}, 1e-3, 1.5);
}

// bench/scenes/jelly_well.toml (tests/app/self_contact_default_test.cpp's well), read as `wobble run` reads it, with
// both jellies' self-contact off or at the shipped default (on), under the scene's own integrator and step.
void BM_WellSelfContact(benchmark::State& state) {
  const std::vector<std::string> off = {"bodies.low.self_contact=false", "bodies.high.self_contact=false"};
  const std::vector<std::string> sets = state.range(0) != 0 ? std::vector<std::string>{} : off;
  const SceneFile scene = loadScene(kWell, sets);
  runs(
      state, [&] { return loadScene(kWell, sets).system; }, scene.integrator.c_str(), scene.integrator_options,
      scene.dt, scene.duration);
}

void perRun(benchmark::internal::Benchmark* b) {
  b->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_FreePairImpact)->Arg(3)->Arg(4)->Arg(5)->Arg(8)->Iterations(5)->Apply(perRun);
BENCHMARK(BM_JellySelfContact)->Args({0, 0})->Args({0, 1})->Args({1, 0})->Args({1, 1})->Iterations(3)->Apply(perRun);
BENCHMARK(BM_WellSelfContact)->Arg(0)->Arg(1)->Iterations(3)->Apply(perRun);

}  // namespace
}  // namespace wobble
