// Results do not depend on the number of threads: every integrator, on a jelly resting on a tilted plane and on a
// cloth falling onto a sphere, gives the same bytes with 1 and 2 TBB threads, and the same as the serial path small
// systems take. The systems are large enough to be cut into several particle chunks and schedule blocks
// (parallel.h, pair_schedule.h), so the threaded loops really run on two threads here: a test-only observer of TBB's
// arena (tests/threads_seen.h) sees a second thread join the two-thread runs, and none the one-thread runs. The default
// threshold (which the jelly's 8000 particles pass, the cloth's 10^4 too) gives the same bytes as well. A cloth folding
// onto itself does the same for contact between bodies under backward Euler and RK4.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <tuple>

#include <tbb/global_control.h>

#include "sim/bodies/jelly.h"
#include "sim/contact/colliders/plane.h"
#include "sim/simulation.h"
#include "sim/solver/parallel.h"
#include "tests/sim/cloth_on_sphere.h"
#include "tests/sim/folded_cloth.h"
#include "tests/threads_seen.h"

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
  int other_threads = 0;  // threads besides the caller's that joined TBB's parallel work
};

Run simulate(MassSpringSystem& system, const std::string& method, double dt, int steps, int threads, int threshold) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  const int saved = parallelThreshold();
  setParallelThreshold(threshold);
  const testing::ThreadsSeen seen;
  Simulation sim(system, makeIntegrator(method), dt);
  EXPECT_FALSE(sim.advanceTo(steps * dt)) << method;
  setParallelThreshold(saved);
  return {sim.x(), sim.v(), seen.others()};
}

bool sameBytes(const VecX& a, const VecX& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

// On two threads with every loop threaded, until a second thread took part (a short run may end before a worker
// wakes on a busy machine; 20 tries at most): every try must give the same bytes, returned with its thread count.
Run simulateOnTwoThreads(MassSpringSystem& system, const std::string& method, double dt, int steps) {
  Run first = simulate(system, method, dt, steps, 2, 0);
  for (int attempt = 1; attempt < 20 && first.other_threads == 0; ++attempt) {
    const Run again = simulate(system, method, dt, steps, 2, 0);
    EXPECT_TRUE(sameBytes(first.x, again.x) && sameBytes(first.v, again.v)) << method << ": try " << attempt;
    first.other_threads = again.other_threads;
  }
  return first;
}

void expectSameBytesForAnyThreadCount(MassSpringSystem& system, double dt, int steps) {
  for (std::string_view name : integratorNames()) {
    const std::string method(name);
    const int steps_here = method == "backward-euler" ? 3 : steps;
    const double dt_here = method == "backward-euler" ? 1.0 / 60 : dt;
    const Run one = simulate(system, method, dt_here, steps_here, 1, 0);
    const Run two = simulateOnTwoThreads(system, method, dt_here, steps_here);
    const Run serial = simulate(system, method, dt_here, steps_here, 2, std::numeric_limits<int>::max());
    const Run by_default = simulate(system, method, dt_here, steps_here, 2, parallelThreshold());
    EXPECT_TRUE(sameBytes(one.x, two.x) && sameBytes(one.v, two.v)) << method << ": 1 and 2 threads differ";
    EXPECT_TRUE(sameBytes(one.x, serial.x) && sameBytes(one.v, serial.v)) << method << ": threads and serial differ";
    EXPECT_TRUE(sameBytes(one.x, by_default.x) && sameBytes(one.v, by_default.v))
        << method << ": the default threshold differs";
    EXPECT_EQ(one.other_threads, 0) << method;
    EXPECT_GE(two.other_threads, 1) << method << ": no second thread ran";
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

// Contact between bodies on threads (the broad phase's lookups, the step's candidate lists and their updates, the
// searches' and the pass's tests run in chunks): the folded 20 x 20 cloth of the contact tests, landing and collapsing
// onto itself under backward Euler at 1/60 s and under RK4 at 5e-4 s, gives the same bytes on one thread, on two with
// every loop threaded, and serially, with contacts found on the way.
TEST(ThreadCount, ClothFoldingOntoItselfGivesTheSameBytes) {
  for (const auto& [method, dt, steps] : {std::tuple{"backward-euler", 1.0 / 60, 36}, std::tuple{"rk4", 5e-4, 400}}) {
    auto system = testing::foldedCloth(20, true);
    const wobble::Run one = simulate(*system, method, dt, steps, 1, 0);
    const wobble::Run two = simulateOnTwoThreads(*system, method, dt, steps);
    const wobble::Run serial = simulate(*system, method, dt, steps, 2, std::numeric_limits<int>::max());
    EXPECT_TRUE(sameBytes(one.x, two.x) && sameBytes(one.v, two.v)) << method << ": 1 and 2 threads differ";
    EXPECT_TRUE(sameBytes(one.x, serial.x) && sameBytes(one.v, serial.v)) << method << ": threads and serial differ";
    EXPECT_GE(two.other_threads, 1) << method << ": no second thread ran";
    Simulation sim(*system, makeIntegrator(method), dt);
    ASSERT_FALSE(sim.advanceTo(steps * dt));
    EXPECT_GT(sim.bodyContact()->contacts, 0) << method;
  }
}

}  // namespace
}  // namespace wobble
