// The cost of contact between bodies (sim/contact/, docs/body-contact.md): a limp cloth folded in four layers
// (tests/sim/folded_cloth.h) is dropped onto the floor and collapses onto itself. After a warm-up of 0.5 s to the
// collapsed state, layers lying on each other (simulated once per case, untimed), each of 10 iterations is one step
// (steps 31 to 40: the same states in every run; wall time, and CPU time of the whole process, both threads), with
// self-contact on (/1) against off (/0, the same cloth from its own warm-up, layers passing through each other); the
// last argument 0 turns the broad phase's culls off (sim/contact/collisions/body_collisions.h), to show what it saves:
//   BM_Folded/{100,256}/x: 100 x 100 cloth, backward Euler at dt 1/60 (the 2x target), and 256 x 256 (its
//   folds spring open violently on release: the broad phase's budget once stopped it at its third step);
//   BM_Stacked/{100,256}/x: the same cloth laid in four layers half a spacing apart, each fold one short spring and
//   every spring at rest in that shape (foldedCloth's layer_gap), on a floor without friction, backward Euler at
//   1/60 with CG up to 20 000 iterations: it drops 1 cm and its layers settle onto each other (the 256 x 256 target:
//   at most 50 ms a step); the same warm-up and timed steps.
// Backward Euler's counters per step: cg/step, the CG iterations; solves/step, the linear solves of every cause (the
// first, impacts, pairs between bodies, friction, exact steps' Newton iterations); friction_solves/step, those of them
// solved again with friction brought within Coulomb's cone; exact/step, the steps solved exactly for energy.
//   BM_FoldedRk4/32/x: 32 x 32 cloth, RK4 at 2.5e-4 s, below its stable step (theory: 3.0e-4 s; at 100 x 100 it is
//   2.8e-6 s), detection once a step, not a stage; 400 fixed steps (0.1 s).
// Counters per step: contacts (pairs within the thickness), CCD hits, impact-zone activations; min_dist is the
// smallest distance between non-adjacent elements seen in the timed steps (m; the thickness is a quarter of the
// particle spacing: 5.1 mm at 100); crossings, the triangle pairs sharing no vertex that intersect at the last step's
// end (tests/sim/triangle_intersection.h, the contact tests' independent test; untimed).
//   BM_StackInSolve/x: jelly_stack's two 5^3 jellies, the upper one resting on the lower, backward Euler at 1/60 with
//   the contacts in its solve (/1) against the pass after the step alone (/0, as before they went into the solve).
//   BM_NothingNear/s/k: cloth_sphere's 25 x 25 cloth (tests/sim/cloth_on_sphere.h) draping over the sphere under
//   explicit Euler at 1e-4 s, each iteration its first second (10 000 steps): its elements never come within the
//   thickness; skipped: the share of the passes skipped. Self-contact off (s = 0) and on (1); k = 0 turns off the
//   skipping of detection where nothing can come near (contact/candidates/clearance.h), to show what it saves.
//   BM_BroadPhase/x: the broad phase of one step of the 100 x 100 cloth at step 31 (its vertices' and triangles',
//   and its edges' swept boxes from that step's start to its end, padded as contact/candidates/search.cpp pads
//   them): the spatial hash wobble uses (/0, broad_phase.h) against Embree's rtcCollide (/1: a BVH of user boxes per
//   list, the float boxes rounded outward, its pairs filtered by the double boxes and sorted as the hash's); both give
//   the same pairs (checked). Boxes only: the diagonals contact/candidates/search.cpp keeps beside them filter
//   the pairs after.
// Run: taskset -c 0,1 build/body_contact_bench (two cores).
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/contact/broad_phase/broad_phase.h"
#include "sim/contact/colliders/plane.h"
#include "sim/contact/collisions/body_collisions.h"
#include "sim/simulation.h"
#include "tests/sim/cloth_on_sphere.h"
#include "tests/sim/folded_cloth.h"
#include "tests/sim/jelly_stack.h"
#include "tests/sim/triangle_intersection.h"

namespace wobble {
namespace {

struct Folded {
  std::unique_ptr<MassSpringSystem> system;
  std::unique_ptr<Simulation> sim;
};

// stacked: the layers 0.5 spacings apart, the springs at rest in the folded shape, a floor without friction, and
// CG up to 20 000 iterations (the stack's first step needs about 3 600 at 256 x 256).
std::unique_ptr<Folded> folded(int n, bool self_contact, const char* integrator, double dt, bool stacked = false) {
  auto c = std::make_unique<Folded>();
  c->system = stacked ? testing::foldedCloth(n, self_contact, 4, 0.5, 0) : testing::foldedCloth(n, self_contact);
  IntegratorOptions options;
  if (stacked) options.cg_max_iterations = 20000;
  c->sim = std::make_unique<Simulation>(*c->system, makeIntegrator(integrator, options), dt);
  c->sim->advanceTo(0.5);  // landed: the layers lie on each other
  return c;
}

// An implicit step's counters over `taken` steps: CG iterations and linear solves a step, all causes (run.json's
// body_contact.solves_per_step), and of them the re-solves with friction brought within Coulomb's cone.
void solverCounters(benchmark::State& state, const IntegratorStats& before, const IntegratorStats& after,
                    double taken) {
  state.counters["cg/step"] = double(after.cg_iterations - before.cg_iterations) / taken;
  state.counters["solves/step"] = double(after.linear_solves - before.linear_solves) / taken;
  state.counters["friction_solves/step"] = double(after.friction_solves - before.friction_solves) / taken;
  // Steps whose linearized solve made up energy and were solved exactly (docs/energy.md)
  state.counters["exact/step"] = double(after.exact_steps - before.exact_steps) / taken;
}

void run(benchmark::State& state, const char* integrator, double dt, bool stacked = false) {
  const int n = int(state.range(0));
  const bool self_contact = state.range(1) != 0;
  collision::setBroadPhaseCulls(state.range(2) != 0);
  auto c = folded(n, self_contact, integrator, dt, stacked);
  Simulation& sim = *c->sim;
  const collision::Stats before = sim.bodyContact() ? *sim.bodyContact() : collision::Stats{};
  const long steps = sim.steps();
  const IntegratorStats solver = sim.integrator().stats();
  for (auto _ : state) {
    if (sim.advanceTo(sim.time() + dt)) state.SkipWithError("the run stopped");
  }
  const double taken = double(sim.steps() - steps);
  if (sim.integrator().stats().cg_iterations > 0) solverCounters(state, solver, sim.integrator().stats(), taken);
  state.counters["retakes"] = double(sim.energyRetakes());  // steps taken again in halves for energy, warm-up included
  if (const collision::Stats* s = sim.bodyContact()) {
    state.counters["contacts/step"] = double(s->contacts - before.contacts) / taken;
    state.counters["ccd_hits/step"] = double(s->ccd_hits - before.ccd_hits) / taken;
    state.counters["zones/step"] = double(s->zone_activations - before.zone_activations) / taken;
    state.counters["min_dist"] = s->min_distance;  // smallest since the start: the warm-up's included
  }
  // Triangle pairs intersecting at the last step's end, by the tests' independent triangle-triangle test (untimed).
  testing::ParticleTriangles triangles;
  for (std::size_t b = 0; b < c->system->bodies().size(); ++b)
    testing::addSurface(triangles, c->system->bodies()[b].body.surface, c->system->bodies()[b].first, int(b));
  state.counters["crossings"] = testing::intersectingPairs(triangles, sim.x());
  state.counters["particles"] = n * n;
  collision::setBroadPhaseCulls(true);
}

void BM_Folded(benchmark::State& state) { run(state, "backward-euler", 1.0 / 60); }
void BM_FoldedRk4(benchmark::State& state) { run(state, "rk4", 2.5e-4); }
void BM_Stacked(benchmark::State& state) { run(state, "backward-euler", 1.0 / 60, true); }

// Each iteration one step: wall time, and the process's CPU time (both threads).
void perStep(benchmark::internal::Benchmark* b) {
  b->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kMillisecond);
}

// The folded and stacked cloths at 100 x 100 and 256 x 256, self-contact off and on (culls on), 10 steps each.
void bothSizes(benchmark::internal::Benchmark* b) {
  for (const int n : {100, 256})
    for (const int self_contact : {0, 1}) b->Args({n, self_contact, 1});
  b->Iterations(10)->Apply(perStep);
}

BENCHMARK(BM_Folded)->Apply(bothSizes)->Args({100, 1, 0});
BENCHMARK(BM_Stacked)->Apply(bothSizes);
BENCHMARK(BM_FoldedRk4)->Args({32, 0, 1})->Args({32, 1, 1})->Iterations(400)->Apply(perStep);

void BM_NothingNear(benchmark::State& state) {
  collision::setSkipWhileApart(state.range(1) != 0);
  for (auto _ : state) {
    state.PauseTiming();
    const auto system = testing::clothOnSphere(25, ClothParams{}.ks, state.range(0) != 0);
    Simulation sim(*system, makeIntegrator("explicit-euler"), 1e-4);
    state.ResumeTiming();
    if (sim.advanceTo(1.0)) state.SkipWithError("the run stopped");
    if (const collision::Stats* s = sim.bodyContact())
      state.counters["skipped"] = double(s->passes_skipped) / double(s->passes);
  }
  collision::setSkipWhileApart(true);
}

BENCHMARK(BM_NothingNear)->Args({0, 1})->Args({1, 1})->Args({1, 0})->Iterations(3)->Unit(benchmark::kMillisecond);

// jelly_stack (scenes/jelly_stack.toml), the upper jelly dropped onto the lower: timed once it rests on it (1.5 s).
void BM_StackInSolve(benchmark::State& state) {
  const double dt = 1.0 / 60;
  const auto system = testing::jellyStack();
  IntegratorOptions options;
  options.body_contact_in_solve = state.range(0) != 0;
  Simulation sim(*system, makeIntegrator("backward-euler", options), dt);
  if (sim.advanceTo(1.5)) state.SkipWithError("the warm-up stopped");
  const long steps = sim.steps();
  const IntegratorStats before = sim.integrator().stats();
  for (auto _ : state)
    if (sim.advanceTo(sim.time() + dt)) state.SkipWithError("the run stopped");
  const double taken = double(sim.steps() - steps);
  const IntegratorStats& after = sim.integrator().stats();
  solverCounters(state, before, after, taken);
}

BENCHMARK(BM_StackInSolve)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The broad phase's input: boxes of the surface's vertices, triangles and edges over one step, and the pairs that
// contact/candidates/search.h keeps (elements of no common vertex).
struct BroadPhaseInput {
  std::vector<collision::Box> vertices, triangles, edges;
  std::vector<std::array<int, 3>> triangle_vertices;
  std::vector<std::array<int, 2>> edge_vertices;
  bool keepVertexTriangle(int v, int t) const {
    const auto& c = triangle_vertices[t];
    return v != c[0] && v != c[1] && v != c[2];
  }
  bool keepEdgeEdge(int e, int f) const {
    const auto &a = edge_vertices[e], &b = edge_vertices[f];
    return a[0] != b[0] && a[0] != b[1] && a[1] != b[0] && a[1] != b[1];
  }
};

BroadPhaseInput broadPhaseInput() {
  auto c = folded(100, true, "backward-euler", 1.0 / 60);
  const VecX x0 = c->sim->x();
  c->sim->advanceTo(c->sim->time() + 1.0 / 60);
  const VecX& x1 = c->sim->x();
  const BodySlot& cloth = c->system->bodies()[0];
  const double pad = cloth.body.contact.thickness;  // half the thickness, and the step candidates' margin as much
  BroadPhaseInput in;
  const auto box = [&](auto vertices) {
    collision::Box b{Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)};
    for (const int v : vertices)
      for (const VecX* x : {&x0, &x1}) {
        const Vec3 p = x->segment<3>(3 * (cloth.first + cloth.body.surface.particle[v]));
        b.lo = b.lo.cwiseMin(p), b.hi = b.hi.cwiseMax(p);
      }
    b.lo.array() -= pad, b.hi.array() += pad;
    return b;
  };
  for (int v = 0; v < int(cloth.body.surface.vertexCount()); ++v) in.vertices.push_back(box(std::array<int, 1>{v}));
  for (const auto& t : cloth.body.surface.triangles) {
    in.triangle_vertices.push_back(t);
    in.triangles.push_back(box(t));
    for (int k = 0; k < 3; ++k)
      in.edge_vertices.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  }
  std::sort(in.edge_vertices.begin(), in.edge_vertices.end());
  in.edge_vertices.erase(std::unique(in.edge_vertices.begin(), in.edge_vertices.end()), in.edge_vertices.end());
  for (const auto& e : in.edge_vertices) in.edges.push_back(box(e));
  return in;
}

// rtcCollide over two lists of boxes (the same list twice for pairs within one): the pairs whose double boxes overlap
// and keep accepts, ascending, each unordered pair of one list once as (smaller, larger).
class EmbreeBroadPhase {
 public:
  EmbreeBroadPhase() : device_(rtcNewDevice(nullptr)) {}
  ~EmbreeBroadPhase() { rtcReleaseDevice(device_); }
  template <class Keep>
  void pairs(const std::vector<collision::Box>& a, const std::vector<collision::Box>& b, bool same, Keep&& keep,
             std::vector<std::pair<int, int>>& out) {
    RTCScene sa = scene(a), sb = same ? sa : scene(b);
    found_.clear();
    rtcCollide(sa, sb, &EmbreeBroadPhase::collect, this);
    rtcReleaseScene(sa);
    if (!same) rtcReleaseScene(sb);
    out.clear();
    for (auto [i, j] : found_) {
      if (same && i > j) std::swap(i, j);
      if ((!same || i != j) && a[i].overlaps(b[j]) && keep(i, j)) out.emplace_back(i, j);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

 private:
  static float down(double d) { return float(d) > d ? std::nextafter(float(d), -INFINITY) : float(d); }
  static float up(double d) { return float(d) < d ? std::nextafter(float(d), INFINITY) : float(d); }
  static void bounds(const RTCBoundsFunctionArguments* args) {
    const collision::Box& b = (*static_cast<const std::vector<collision::Box>*>(args->geometryUserPtr))[args->primID];
    *args->bounds_o =
        RTCBounds{down(b.lo.x()), down(b.lo.y()), down(b.lo.z()), 0, up(b.hi.x()), up(b.hi.y()), up(b.hi.z()), 0};
  }
  static void collect(void* self, RTCCollision* found, unsigned count) {
    auto& me = *static_cast<EmbreeBroadPhase*>(self);
    const std::lock_guard<std::mutex> lock(me.mutex_);  // called from Embree's threads
    for (unsigned k = 0; k < count; ++k) me.found_.emplace_back(int(found[k].primID0), int(found[k].primID1));
  }
  RTCScene scene(const std::vector<collision::Box>& boxes) {
    RTCScene s = rtcNewScene(device_);
    rtcSetSceneBuildQuality(s, RTC_BUILD_QUALITY_LOW);
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, unsigned(boxes.size()));
    rtcSetGeometryUserData(g, const_cast<std::vector<collision::Box>*>(&boxes));
    rtcSetGeometryBoundsFunction(g, &EmbreeBroadPhase::bounds, nullptr);
    rtcCommitGeometry(g);
    rtcAttachGeometry(s, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(s);
    return s;
  }
  RTCDevice device_;
  std::mutex mutex_;
  std::vector<std::pair<int, int>> found_;
};

void BM_BroadPhase(benchmark::State& state) {
  const BroadPhaseInput in = broadPhaseInput();
  const auto vf = [&](int v, int t) { return in.keepVertexTriangle(v, t); };
  const auto ee = [&](int e, int f) { return in.keepEdgeEdge(e, f); };
  std::vector<std::pair<int, int>> hash_vf, hash_ee, vf_pairs, ee_pairs;
  collision::overlappingPairs(in.vertices, in.triangles, false, true, vf, hash_vf);
  collision::overlappingPairs(in.edges, in.edges, true, true, ee, hash_ee);
  EmbreeBroadPhase embree;
  for (auto _ : state) {
    if (state.range(0) == 0) {
      collision::overlappingPairs(in.vertices, in.triangles, false, true, vf, vf_pairs);
      collision::overlappingPairs(in.edges, in.edges, true, true, ee, ee_pairs);
    } else {
      embree.pairs(in.vertices, in.triangles, false, vf, vf_pairs);
      embree.pairs(in.edges, in.edges, true, ee, ee_pairs);
    }
  }
  if (vf_pairs != hash_vf || ee_pairs != hash_ee) state.SkipWithError("the two broad phases disagree");
  state.counters["pairs"] = double(hash_vf.size() + hash_ee.size());
}

BENCHMARK(BM_BroadPhase)->Arg(0)->Arg(1)->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace wobble
