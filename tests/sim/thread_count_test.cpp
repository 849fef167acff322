// Results do not depend on the number of threads: every integrator, on a jelly resting on a tilted plane and on a
// cloth falling onto a sphere, gives the same bytes with 1 and 2 TBB threads, and the same as the serial path small
// systems take. The systems are large enough to be cut into several particle chunks and schedule blocks
// (parallel.h, pair_schedule.h), so the threaded loops really run on two threads here.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include <tbb/global_control.h>

#include "sim/bodies/jelly.h"
#include "sim/colliders/plane.h"
#include "sim/solver/parallel.h"
#include "sim/simulation.h"
#include "tests/sim/cloth_on_sphere.h"

namespace wobble {
namespace {

// A 20^3 jelly (8000 particles, 4 schedule blocks), tilted, its lowest corner resting on a floor: contact forces,
// friction and (backward Euler) contact constraints are all at work.
std::unique_ptr<MassSpringSystem> jellyOnFloor() {
  JellyParams p;
  p.n = 20;
  p.rotation_deg = 30;
  p.center = Vec3(0, 0, 0);
  Body body = buildJelly("jelly", p);
  const double lowest = body.x.reshaped(3, body.particleCount()).row(1).minCoeff();
  for (int i = 0; i < body.particleCount(); ++i) body.x[3 * i + 1] -= lowest;
  auto system = std::make_unique<MassSpringSystem>();
  system->addBody(std::move(body));
  system->addCollider(std::make_unique<PlaneCollider>("floor", ContactParams{}, Vec3::Zero(), Vec3::UnitY()));
  return system;
}

struct Run {
  VecX x, v;
};

Run simulate(MassSpringSystem& system, const std::string& method, double dt, int steps, int threads, int threshold) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  const int saved = parallelThreshold();
  setParallelThreshold(threshold);
  Simulation sim(system, makeIntegrator(method), dt);
  EXPECT_FALSE(sim.advanceTo(steps * dt)) << method;
  setParallelThreshold(saved);
  return {sim.x(), sim.v()};
}

bool sameBytes(const VecX& a, const VecX& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

void expectSameBytesForAnyThreadCount(MassSpringSystem& system, double dt, int steps) {
  for (std::string_view name : integratorNames()) {
    const std::string method(name);
    const int steps_here = method == "backward-euler" ? 3 : steps;
    const double dt_here = method == "backward-euler" ? 1.0 / 60 : dt;
    const Run one = simulate(system, method, dt_here, steps_here, 1, 0);
    const Run two = simulate(system, method, dt_here, steps_here, 2, 0);
    const Run serial = simulate(system, method, dt_here, steps_here, 2, std::numeric_limits<int>::max());
    EXPECT_TRUE(sameBytes(one.x, two.x) && sameBytes(one.v, two.v)) << method << ": 1 and 2 threads differ";
    EXPECT_TRUE(sameBytes(one.x, serial.x) && sameBytes(one.v, serial.v)) << method << ": threads and serial differ";
    EXPECT_FALSE(sameBytes(one.x, system.initialPositions())) << method << ": nothing moved";
  }
}

TEST(ThreadCount, JellyOnAFloorGivesTheSameBytes) {
  auto system = jellyOnFloor();
  expectSameBytesForAnyThreadCount(*system, 1e-3, 10);
}

TEST(ThreadCount, ClothOnASphereGivesTheSameBytes) {
  auto system = testing::clothOnSphere(100);  // 10^4 particles, 5 blocks
  expectSameBytesForAnyThreadCount(*system, 1e-4, 10);
}

}  // namespace
}  // namespace wobble
