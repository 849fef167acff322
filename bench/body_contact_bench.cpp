// The cost of contact between bodies (sim/collision/, docs/body-contact.md): a limp cloth folded in four layers
// (tests/sim/folded_cloth.h) is dropped onto the floor and collapses onto itself. After a warm-up of 0.5 s to the
// collapsed state, layers lying on each other (simulated once per case, untimed), each iteration is one step, with
// self-contact on (/1) against off (/0, the same cloth from its own warm-up, layers passing through each other); the
// last argument 0 turns the broad phase's culls off (sim/collision/body_collisions.h), to show what it saves:
//   BM_Folded/100/x: 100 x 100 cloth, backward Euler at dt 1/60 (the 2x target);
//   BM_Folded/256/x: 256 x 256 cloth, backward Euler at 1/60 (target: 50 ms a step on 2 threads);
//   BM_FoldedRk4/32/x: 32 x 32 cloth, RK4 at 2.5e-4 s, below its stable step (theory: 3.0e-4 s; at 100 x 100 it is
//   2.8e-6 s), detection once a step, not a stage.
// Counters per step: contacts (pairs within the thickness), CCD hits, impact-zone activations; min_dist is the
// smallest distance between non-adjacent elements seen in the timed steps (m; the thickness is a quarter of the
// particle spacing: 5.1 mm at 100, 2.0 mm at 256).
//   BM_StackInSolve/x: jelly_stack's two 5^3 jellies, the upper one resting on the lower, backward Euler at 1/60 with
//   the contacts in its solve (/1) against the pass after the step alone (/0, as before they went into the solve).
// Run: taskset -c 0,1 build/body_contact_bench (two cores).
#include <benchmark/benchmark.h>

#include <memory>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/colliders/plane.h"
#include "sim/collision/body_collisions.h"
#include "sim/simulation.h"
#include "tests/sim/folded_cloth.h"

namespace wobble {
namespace {

struct Folded {
  std::unique_ptr<MassSpringSystem> system;
  std::unique_ptr<Simulation> sim;
};

std::unique_ptr<Folded> folded(int n, bool self_contact, const char* integrator, double dt) {
  auto c = std::make_unique<Folded>();
  c->system = testing::foldedCloth(n, self_contact);
  c->sim = std::make_unique<Simulation>(*c->system, makeIntegrator(integrator), dt);
  c->sim->advanceTo(0.5);  // landed: the layers lie on each other
  return c;
}

void run(benchmark::State& state, const char* integrator, double dt) {
  const int n = int(state.range(0));
  const bool self_contact = state.range(1) != 0;
  collision::setBroadPhaseCulls(state.range(2) != 0);
  auto c = folded(n, self_contact, integrator, dt);
  Simulation& sim = *c->sim;
  const collision::Stats before = sim.bodyContact() ? *sim.bodyContact() : collision::Stats{};
  const long steps = sim.steps();
  for (auto _ : state) {
    if (sim.advanceTo(sim.time() + dt)) state.SkipWithError("the run stopped");
  }
  const double taken = double(sim.steps() - steps);
  if (const collision::Stats* s = sim.bodyContact()) {
    state.counters["contacts/step"] = double(s->contacts - before.contacts) / taken;
    state.counters["ccd_hits/step"] = double(s->ccd_hits - before.ccd_hits) / taken;
    state.counters["zones/step"] = double(s->zone_activations - before.zone_activations) / taken;
    state.counters["min_dist"] = s->min_distance;  // smallest since the start: the warm-up's included
  }
  state.counters["particles"] = n * n;
  collision::setBroadPhaseCulls(true);
}

void BM_Folded(benchmark::State& state) { run(state, "backward-euler", 1.0 / 60); }
void BM_FoldedRk4(benchmark::State& state) { run(state, "rk4", 2.5e-4); }

BENCHMARK(BM_Folded)
    ->Args({100, 0, 1})
    ->Args({100, 1, 1})
    ->Args({100, 1, 0})
    ->Args({256, 0, 1})
    ->Args({256, 1, 1})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FoldedRk4)->Args({32, 0, 1})->Args({32, 1, 1})->Unit(benchmark::kMillisecond);

// jelly_stack (scenes/jelly_stack.toml), the upper jelly dropped onto the lower: timed once it rests on it (1.5 s).
void BM_StackInSolve(benchmark::State& state) {
  const double dt = 1.0 / 60;
  MassSpringSystem system;
  JellyParams base{.n = 5, .size = 1, .mass = 0.1, .ks = 3000, .kd = 2, .center = Vec3(0, 0.52, 0)};
  system.addBody(buildJelly("base", base));
  JellyParams top = base;
  top.size = 0.8;
  top.center = Vec3(0.05, 2.1, -0.05);
  top.rotation_axis = Vec3::UnitY();
  top.rotation_deg = 30;
  system.addBody(buildJelly("top", top));
  system.addCollider(
      std::make_unique<PlaneCollider>("floor", ContactParams{0.2, 0.6, 0.01}, Vec3::Zero(), Vec3::UnitY()));
  IntegratorOptions options;
  options.body_contact_in_solve = state.range(0) != 0;
  Simulation sim(system, makeIntegrator("backward-euler", options), dt);
  if (sim.advanceTo(1.5)) state.SkipWithError("the warm-up stopped");
  const long steps = sim.steps();
  const IntegratorStats before = sim.integrator().stats();
  for (auto _ : state)
    if (sim.advanceTo(sim.time() + dt)) state.SkipWithError("the run stopped");
  const double taken = double(sim.steps() - steps);
  const IntegratorStats& after = sim.integrator().stats();
  state.counters["cg/step"] = double(after.cg_iterations - before.cg_iterations) / taken;
  state.counters["solves/step"] =
      1 + double(after.body_contact_solves - before.body_contact_solves + after.impact_solves - before.impact_solves) /
              taken;
}

BENCHMARK(BM_StackInSolve)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace wobble
