// The cost of contact between bodies (sim/collision/, docs/body-contact.md): a cloth hanging above the floor is
// released and crumples onto itself on the floor. After a warm-up to the crumpled state (simulated once per case,
// untimed), each iteration is one step, with self-contact on (/1) against off (/0), side by side:
//   BM_Crumple/100/x: 100 x 100 cloth, backward Euler at dt 1/60 (the 2x target);
//   BM_Crumple/256/x: 256 x 256 cloth, backward Euler at 1/60 (target: 50 ms a step on 2 threads).
// Counters per step: contacts, CCD hits, impact-zone activations, and the pass's share of the step's time.
//   BM_StackInSolve/x: jelly_stack's two 5^3 jellies, the upper one resting on the lower, backward Euler at 1/60 with
//   the contacts in its solve (/1) against the pass after the step alone (/0, as before they went into the solve).
// Run: build/body_contact_bench (taskset -c 0,1 for two cores).
#include <benchmark/benchmark.h>

#include <memory>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/colliders/plane.h"
#include "sim/simulation.h"

namespace wobble {
namespace {

struct Crumple {
  MassSpringSystem system;
  std::unique_ptr<Simulation> sim;
};

std::unique_ptr<Crumple> crumpled(int n, bool self_contact, const char* integrator, double dt) {
  auto c = std::make_unique<Crumple>();
  ClothParams p;
  p.nx = p.ny = n;
  p.size_x = p.size_y = 2;
  p.hanging = true;
  p.center = Vec3(0, 1.3, 0);  // the bottom row 0.3 m above the floor
  p.mass = 4.0 / (n * n);      // 4 kg in all, whatever the resolution
  p.ks = 20 * n * n / 4.0;     // the same sheet stiffness at every resolution
  p.kd = p.ks / 1000;
  Body cloth = buildCloth("cloth", p);
  cloth.contact.self_contact = self_contact;
  cloth.contact.thickness = 0.25 * 2.0 / (n - 1);
  c->system.addBody(std::move(cloth));
  c->system.addCollider(
      std::make_unique<PlaneCollider>("floor", ContactParams{0, 0.5, 0.005}, Vec3::Zero(), Vec3::UnitY()));
  c->sim = std::make_unique<Simulation>(c->system, makeIntegrator(integrator), dt);
  c->sim->advanceTo(0.5);  // the bottom has landed and the cloth is folding onto itself
  return c;
}

void run(benchmark::State& state, const char* integrator, double dt) {
  const int n = int(state.range(0));
  const bool self_contact = state.range(1) != 0;
  auto c = crumpled(n, self_contact, integrator, dt);
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
    state.counters["min_dist"] = s->min_distance;
  }
  state.counters["particles"] = n * n;
}

void BM_Crumple(benchmark::State& state) { run(state, "backward-euler", 1.0 / 60); }

BENCHMARK(BM_Crumple)->Args({100, 0})->Args({100, 1})->Args({256, 0})->Args({256, 1})->Unit(benchmark::kMillisecond);

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
