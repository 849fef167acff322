// The cost of mesh jellies (sim/bodies/mesh_jelly.h, docs/mesh-bodies.md), on a UV sphere of 20,448 triangles
// (72 rings x 144 segments, 10,226 vertices) made here:
//   BM_LatticeFill/cells:     filling the lattice (the inside test, the cells the surface cuts), cells 8, 16, 32;
//   BM_BuildMeshJelly/cells:  the whole body: the fill, the particles, the springs and the embedding of every vertex;
//   BM_EmbeddedSurface/cells: one frame's embedded surface (positions and normals of the 10,226 vertices);
//   BM_Step/kind:             one step of a jelly resting on the floor, rk4 at 1 ms: the sphere at cells 16
//                             (/1: its surface's 10,226 points meet the floor) against a cube jelly of about as many
//                             particles (/0: its 6 faces' particles meet the floor);
//   BM_Tremor/kind/steps:     not a timing: a jelly resting on the floor under backward Euler at 1/60 s (/1) or
//                             1/240 s (/4), the largest frame-to-frame movement of a surface vertex over the last
//                             second of five (millimetres), the sphere at cells 8 (kind 1) against a cube jelly (0);
//   BM_Overhang:              not a timing: how far the lattice reaches beyond the surface it carries, at rest and at
//                             most while the sphere (cells 8) strikes a 30-degree slope at 5 m/s (counters, metres).
// Run: build/mesh_jelly_bench (taskset -c 0,1 for two cores).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "sim/bodies/jelly.h"
#include "sim/bodies/mesh_jelly.h"
#include "sim/contact/colliders/mesh.h"
#include "sim/contact/colliders/plane.h"
#include "sim/contact/colliders/response.h"
#include "sim/simulation.h"
#include "tests/sim/test_models.h"

namespace wobble {
namespace {

const ModelMesh& sphereModel() {
  static const ModelMesh model = testing::uvSphere(0.5, 72, 144);
  return model;
}

MeshJellyParams sphereParams(int cells) {
  MeshJellyParams p{.cells = cells, .ks = 2000, .kd = 5};
  p.placement.center = Vec3(0, 0.6, 0);
  return p;
}

void BM_LatticeFill(benchmark::State& state) {
  const std::vector<Vec3> local = localPoints(sphereModel(), 1);
  for (auto _ : state) benchmark::DoNotOptimize(fillLattice(local, sphereModel().triangles, int(state.range(0))));
  state.counters["triangles"] = double(sphereModel().triangles.size());
}

void BM_BuildMeshJelly(benchmark::State& state) {
  int particles = 0;
  for (auto _ : state) {
    const Body body = buildMeshJelly("sphere", sphereModel(), sphereParams(int(state.range(0))));
    particles = body.particleCount();
    benchmark::DoNotOptimize(body.x.data());
  }
  state.counters["particles"] = particles;
}

void BM_EmbeddedSurface(benchmark::State& state) {
  const Body body = buildMeshJelly("sphere", sphereModel(), sphereParams(int(state.range(0))));
  for (auto _ : state) benchmark::DoNotOptimize(evaluateSurface(body.surface, body.x, 0).positions.data());
  state.counters["vertices"] = double(body.surface.vertexCount());
}

// A jelly settled on the floor (0.5 s, untimed), then one step per iteration.
void BM_Step(benchmark::State& state) {
  const bool mesh = state.range(0) != 0;
  Body sphere = buildMeshJelly("sphere", sphereModel(), sphereParams(16));
  const int n = int(std::lround(std::cbrt(double(sphere.particleCount()))));  // the cube of about as many particles
  Body body = mesh ? std::move(sphere)
                   : buildJelly("cube", {.n = n, .size = 1, .ks = 2000, .kd = 5, .center = Vec3(0, 0.6, 0)});
  MassSpringSystem system;
  system.addBody(std::move(body));
  system.addCollider(
      std::make_unique<PlaneCollider>("floor", ContactParams{0.3, 0.5, 0.01}, Vec3::Zero(), Vec3::UnitY()));
  const double dt = 1e-3;
  Simulation sim(system, makeIntegrator("rk4"), dt);
  if (sim.advanceTo(0.5)) state.SkipWithError("the warm-up blew up");
  for (auto _ : state)
    if (sim.advanceTo(sim.time() + dt)) state.SkipWithError("the run stopped");
  state.counters["particles"] = system.particleCount();
  state.counters["springs"] = double(system.springs().size());
  double short_runs = 0;  // the springs the force loop takes outside long runs (pair_schedule.h)
  for (const PairRun& run : system.jacobianPattern().runs()) short_runs += run.length < kMinPairRun ? run.length : 0;
  state.counters["springs_in_short_runs"] = short_runs;
  const WeightedPoints& points = system.embeddedPoints();
  state.counters["contact_points"] = points.size();
  if (points.empty()) return;
  // At the last state: the points of the cells the floor may be near (blended), and those near it (asked).
  std::vector<Eigen::AlignedBox3d> boxes;
  points.cellBounds(sim.x(), boxes);
  const Collider& floor = *system.colliders()[0];
  double in_boxes = 0;
  for (int p = 0; p < points.size(); ++p) in_boxes += floor.mayBeNear(sim.time(), boxes[points.cell(p)], 0.01);
  std::vector<int> near;
  VecX at;
  CellBoxes cells;
  nearPoints(floor, sim.time(), points, sim.x(), cells, 0.01, near, at);
  state.counters["points_in_near_boxes"] = in_boxes;
  state.counters["near_points"] = double(near.size());
}

// The largest signed distance of a lattice particle outside the embedded surface (the surface as a mesh collider:
// positive outside it).
double overhang(const Body& body, const VecX& x) {
  const SurfaceFrame frame = evaluateSurface(body.surface, x, 0);
  std::vector<Vec3> points;
  for (const auto& p : frame.positions) points.push_back(p.cast<double>());
  const MeshCollider surface("surface", {}, points, body.surface.triangles, Vec3::Zero());
  double most = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < body.particleCount(); ++i) most = std::max(most, surface.query(0, particle(x, i))->distance);
  return most;
}

void BM_Overhang(benchmark::State& state) {
  const ModelMesh model = testing::uvSphere(0.5, 24, 48);
  MeshJellyParams p = sphereParams(8);
  p.placement.center = Vec3(0, 1.2, 0);
  p.velocity = Vec3(0, -5, 0);
  const Body body = buildMeshJelly("sphere", model, p);
  MassSpringSystem system;
  system.addBody(body);
  const double slope = 30 * EIGEN_PI / 180;
  system.addCollider(std::make_unique<PlaneCollider>("slope", ContactParams{0.3, 0.5, 0.01}, Vec3::Zero(),
                                                     Vec3(-std::sin(slope), std::cos(slope), 0)));
  double at_rest = 0, impact = 0;
  for (auto _ : state) {
    Simulation sim(system, makeIntegrator("rk4"), 1e-3);
    at_rest = overhang(body, sim.x());
    impact = at_rest;
    for (int frame = 1; frame <= 30; ++frame) {  // 0.5 s at 60 frames a second
      if (sim.advanceTo(frame / 60.0)) state.SkipWithError("the run stopped");
      impact = std::max(impact, overhang(body, sim.x()));
    }
  }
  state.counters["cell_m"] = 1.0 / 8;
  state.counters["at_rest_m"] = at_rest;
  state.counters["impact_m"] = impact;
}

// The largest frame-to-frame movement (at 60 frames a second) of any surface vertex over the last of 5 s, a jelly
// resting on the floor under backward Euler at steps/frame steps a frame: the sphere at cells 8 (/1) against a cube
// jelly of about as many particles (/0).
void BM_Tremor(benchmark::State& state) {
  const bool mesh = state.range(0) != 0;
  const int steps = int(state.range(1));
  MeshJellyParams p{.cells = 8, .ks = 1400, .kd = 50};
  p.placement.center = Vec3(0, 0.55, 0);
  Body sphere = buildMeshJelly("sphere", testing::uvSphere(0.5, 24, 48), p);
  const int n = int(std::lround(std::cbrt(double(sphere.particleCount()))));
  Body body = mesh ? std::move(sphere)
                   : buildJelly("cube", {.n = n, .size = 1, .ks = 1400, .kd = 50, .center = Vec3(0, 0.55, 0)});
  const SurfaceMesh surface = body.surface;
  double most = 0;
  for (auto _ : state) {
    MassSpringSystem system;
    system.addBody(body);
    system.addCollider(
        std::make_unique<PlaneCollider>("floor", ContactParams{0.3, 0.5, 0.01}, Vec3::Zero(), Vec3::UnitY()));
    Simulation sim(system, makeIntegrator("backward-euler"), 1.0 / (60 * steps));
    if (sim.advanceTo(4.0)) state.SkipWithError("the settling blew up");
    SurfaceFrame last = evaluateSurface(surface, sim.x(), 0);
    most = 0;
    for (int frame = 241; frame <= 300; ++frame) {
      if (sim.advanceTo(frame / 60.0)) state.SkipWithError("the run stopped");
      SurfaceFrame now = evaluateSurface(surface, sim.x(), 0);
      for (std::size_t v = 0; v < now.positions.size(); ++v)
        most = std::max(most, double((now.positions[v] - last.positions[v]).norm()));
      last = std::move(now);
    }
  }
  state.counters["particles"] = body.particleCount();
  state.counters["tremor_mm"] = 1000 * most;
}

BENCHMARK(BM_LatticeFill)->Arg(8)->Arg(16)->Arg(32)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BuildMeshJelly)->Arg(8)->Arg(16)->Arg(32)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmbeddedSurface)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Overhang)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Tremor)->ArgsProduct({{0, 1}, {1, 4}})->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace wobble
