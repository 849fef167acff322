// A pile comes to rest (docs/body-contact.md, "Rest"). Oracles: the speeds themselves over the last frames (every
// particle under 0.05 m/s from 3 s after the top jelly lands), the total energy (no rise after the landing: nothing
// moves the floor, so nothing may feed the pile), and the independent triangle test (no surface through another).
// Three small jellies dropped in a slightly offset column onto a floor that does not bounce (restitution 0: the floor's
// rule for resting particles is tested on its own, colliders/resting_restitution_test.cpp). Then the six stiff
// jellies of the reported pile: static friction between them holds (BodyStick), and they sway as the same column glued
// into one body (StackedColumn, the oracle for what keeps them moving).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "sim/simulation.h"
#include "tests/sim/jelly_column.h"
#include "tests/sim/triangle_intersection.h"

namespace wobble {
namespace {

constexpr double kRestSpeed = 0.05;  // m/s: every particle, 3 s after the landing
constexpr double kSettleTime = 3;    // s after the landing
constexpr double kFrame = 1.0 / 60;
// s after the landing: the pile's bounces, where backward Euler's linearized step may make up a little energy (0.07 J
// of 30 J at 1/240 s here; docs/energy.md). From then on the pile is settling, and its energy may only fall.
constexpr double kBounceTime = 1;

// The reported pile's jellies (issue 53): stiffer and heavier than ColumnParams' soft ones.
const JellyParams kStiffJelly{.n = 4, .size = 0.4, .mass = 0.1, .ks = 3000, .kd = 2};

struct Case {
  const char* integrator;
  double dt;
  bool stiff = false;
};
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.integrator << " at 1/" << std::lround(1 / c.dt) << " s, " << (c.stiff ? "stiff" : "soft") << " jellies";
}

struct Column {
  testing::ColumnParams params;
  std::unique_ptr<MassSpringSystem> system;
  testing::ParticleTriangles tris;
  explicit Column(const testing::ColumnParams& p) : params(p), system(testing::jellyColumn(p)) {
    for (std::size_t b = 0; b < system->bodies().size(); ++b)
      testing::addSurface(tris, system->bodies()[b].body.surface, system->bodies()[b].first, int(b));
  }
  // The top jelly's mean vertical velocity.
  double topVelocity(const VecX& v) const {
    const BodySlot& top = system->bodies().back();
    double sum = 0;
    for (int i = 0; i < top.body.particleCount(); ++i) sum += particle(v, top.first + i).y();
    return sum / top.body.particleCount();
  }
};

// Degrees between jelly b's lattice vertical axis (its bottom layer's mean to its top layer's) and the vertical.
double tilt(const MassSpringSystem& system, const VecX& x, int b, int n) {
  const BodySlot& slot = system.bodies()[b];
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) {
      lo += particle(x, slot.first + i + n * n * k);
      hi += particle(x, slot.first + i + n * ((n - 1) + n * k));
    }
  return std::acos(std::min(1.0, std::abs((hi - lo).normalized().y()))) * 180 / EIGEN_PI;
}

// A dropped column's landing and the energy's largest rise after it. The landing: the first frame at which the top
// jelly falls 0.5 m/s slower than in free fall (it hit the one below; the column lands bottom first, the top one last).
// The rise: of the energy from kBounceTime after the landing over its lowest value since then.
struct Settling {
  double landing = -1, lowest_energy = 0, rise = 0;
  // One frame at time t, its energy and the top jelly's mean vertical velocity; true once past the bounce.
  bool frame(double t, double energy, double top_velocity) {
    if (landing < 0) {
      if (top_velocity > -9.8 * t + 0.5) landing = t;
      lowest_energy = energy;
      return false;
    }
    if (t < landing + kBounceTime) {
      lowest_energy = energy;
      return false;
    }
    rise = std::max(rise, energy - lowest_energy);
    lowest_energy = std::min(lowest_energy, energy);
    return true;
  }
  bool landed() const { return landing >= 0; }
};

class BodyRest : public ::testing::TestWithParam<Case> {};

TEST_P(BodyRest, ThreeJellyColumnComesToRest) {
  const Case c = GetParam();
  testing::ColumnParams p;
  if (c.stiff) p.jelly = kStiffJelly;
  p.floor.restitution = 0;
  Column column(p);
  MassSpringSystem& system = *column.system;
  Simulation sim(system, makeIntegrator(c.integrator), c.dt);
  ASSERT_TRUE(sim.bodyContact());
  Settling s;
  double settled_speed = 0;
  int worst = 0, frame = 0;
  while (!s.landed() || sim.time() < s.landing + kSettleTime + 0.5 - 1e-9) {
    ++frame;
    ASSERT_FALSE(sim.advanceTo(frame * kFrame)) << c.integrator;
    ASSERT_TRUE(s.landed() || frame * kFrame < 3) << "the top jelly never landed";
    worst = std::max(worst, testing::intersectingPairs(column.tris, sim.x()));
    if (!s.frame(sim.time(), sim.countedEnergy(), column.topVelocity(sim.v()))) continue;
    if (sim.time() > s.landing + kSettleTime - 1e-9)
      settled_speed = std::max(settled_speed, sim.lastIntervalMaxSpeed());
  }
  const double landing = s.landing, rise = s.rise;
  EXPECT_LT(settled_speed, kRestSpeed) << c.integrator << " at 1/" << 1 / c.dt << " s: landed at " << landing
                                       << " s; largest particle speed from " << landing + kSettleTime << " s on";
  // Rounding and the solve's tolerance only: with the active set's band a quarter of the thickness for every pair
  // (activeSlack; docs/body-contact.md, "Rest") the soft pile's energy rises by 0.02 J within a second at rest. The
  // energy counted (Simulation::countedEnergy) is the total less the pairs' penalty's work: measured 0 from frame to
  // frame, soft and stiff (the total alone rose by 2.4 mJ of the stiff pile's 118 J at 1/60 s as its pairs unloaded).
  EXPECT_LT(rise, 1e-4) << c.integrator << ": the energy rose while the pile settled";
  EXPECT_EQ(worst, 0) << c.integrator;
  EXPECT_FALSE(sim.energyGain()) << sim.energyGain()->message(c.dt);
  std::printf(
      "%s 1/%g s, %s: landed at %.3f s, largest speed from %.3f s on %.4f m/s, largest energy rise from %.3f s on %.2e "
      "J\n",
      c.integrator, 1 / c.dt, c.stiff ? "stiff" : "soft", landing, landing + kSettleTime, settled_speed,
      landing + kBounceTime, rise);
}

// Backward Euler only: RK4 is measured against the same column glued into one body (RestUnderRk4 below). The stiff
// cases are three of the reported pile's jellies: the six of the report sway on their contacts for longer (below).
INSTANTIATE_TEST_SUITE_P(Stacks, BodyRest,
                         ::testing::Values(Case{"backward-euler", 1.0 / 60}, Case{"backward-euler", 1.0 / 240},
                                           Case{"backward-euler", 1.0 / 60, true},
                                           Case{"backward-euler", 1.0 / 240, true}),
                         [](const auto& info) {
                           return "backward_euler_" + std::to_string(std::lround(1 / info.param.dt)) +
                                  (info.param.stiff ? "_stiff" : "");
                         });

// Under RK4 the pile rests on the penalty layer inside RK4's stages (sim/contact/collisions/stage_penalty.h): the same
// three soft jellies dropped the same way at 1/240 s stand, lose energy all the way and need no impulse after the
// step once down, but keep swaying past 3 s, as the same column glued into one body does under RK4 (StackedColumn's
// rk4 case): RK4 takes no energy out of a slow sway, and these jellies' dampers (kd 0.5) little. Oracles: the total
// energy with what the layer holds (Simulation::heldEnergy), never rising from 1 s after the landing by more than 1 mJ;
// continuous collision detection, finding no hit over the last second (the layer alone keeps the surfaces apart); the
// independent triangle test; the jellies' tilt (standing). At 1/60 s the glued column itself falls under RK4.
TEST(RestUnderRk4, ThreeJellyColumnStandsAndLosesEnergy) {
  testing::ColumnParams p;
  p.floor.restitution = 0;
  Column column(p);
  MassSpringSystem& system = *column.system;
  Simulation sim(system, makeIntegrator("rk4"), 1.0 / 240);
  Settling s;
  double speed = 0, lean = 0;
  long hits_before = 0;
  int worst = 0;
  for (int frame = 1; !s.landed() || sim.time() < s.landing + kSettleTime + 0.5 - 1e-9; ++frame) {
    ASSERT_FALSE(sim.advanceTo(frame * kFrame));
    ASSERT_TRUE(s.landed() || frame * kFrame < 3) << "the top jelly never landed";
    worst = std::max(worst, testing::intersectingPairs(column.tris, sim.x()));
    for (int b = 0; b < p.count; ++b) lean = std::max(lean, tilt(system, sim.x(), b, p.jelly.n));
    if (!s.frame(sim.time(), sim.countedEnergy(), column.topVelocity(sim.v()))) continue;
    if (sim.time() < s.landing + kSettleTime - 0.5 + 1e-9) hits_before = sim.bodyContact()->ccd_hits;
    if (sim.time() > s.landing + kSettleTime - 1e-9) speed = std::max(speed, sim.lastIntervalMaxSpeed());
  }
  const double landing = s.landing, rise = s.rise;
  const long late_hits = sim.bodyContact()->ccd_hits - hits_before;
  EXPECT_LT(rise, 1e-3) << "J: the energy rose while the pile settled";
  EXPECT_EQ(late_hits, 0) << "collisions stopped after the step over the last second: the layer lets surfaces meet";
  EXPECT_EQ(worst, 0);
  EXPECT_LT(lean, 10) << "degrees: the column fell";
  EXPECT_FALSE(sim.energyGain()) << sim.energyGain()->message(1.0 / 240);
  std::printf(
      "rk4 1/240 s: landed at %.3f s; from %.3f s on largest speed %.4f m/s; largest energy rise from %.3f s on %.2e "
      "J; "
      "tilt up to %.1f degrees; CCD hits %ld in all, %ld over the last second\n",
      landing, landing + kSettleTime, speed, landing + kBounceTime, rise, lean, sim.bodyContact()->ccd_hits, late_hits);
}

// The mean velocity of a jelly's lattice layer j (0: the bottom, n - 1: the top).
Vec3 layerVelocity(const MassSpringSystem& system, const VecX& v, int b, int n, int j) {
  const BodySlot& slot = system.bodies()[b];
  Vec3 sum = Vec3::Zero();
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) sum += particle(v, slot.first + i + n * (j + n * k));
  return sum / (n * n);
}

// Static friction between bodies holds: the reported six stiff jellies set down on each other (2 mm apart, each
// shifted from the one below) stand, and where each rests on the one below, the touching layers move together
// sideways (slower than 2 mm/s relative to each other, the friction's stick speed 1 mm/s plus the layers' own
// deformation) while the column sways on its contacts at up to 0.15 m/s. Oracle: the layers' velocities themselves.
// Without friction between the bodies the jellies slide off each other within 2 s.
class BodyStick : public ::testing::TestWithParam<Case> {};

TEST_P(BodyStick, SixStiffJelliesStickOnEachOther) {
  const Case c = GetParam();
  testing::ColumnParams p;
  p.count = 6;
  p.jelly = kStiffJelly;
  p.gap = 0.002;
  p.floor.restitution = 0;
  Column column(p);
  MassSpringSystem& system = *column.system;
  Simulation sim(system, makeIntegrator(c.integrator), c.dt);
  const int n = p.jelly.n;
  double slip = 0, sway = 0, lean = 0;
  for (int frame = 1; frame <= 3 * 60; ++frame) {
    ASSERT_FALSE(sim.advanceTo(frame * kFrame)) << c.integrator;
    if (sim.time() < 1 - 1e-9) continue;  // the 5 cm drop onto the floor and its bounce
    for (int b = 1; b < p.count; ++b) {
      const Vec3 d = layerVelocity(system, sim.v(), b, n, 0) - layerVelocity(system, sim.v(), b - 1, n, n - 1);
      slip = std::max(slip, std::hypot(d.x(), d.z()));
      lean = std::max(lean, tilt(system, sim.x(), b, n));
    }
    sway = std::max(sway, sim.lastIntervalMaxSpeed());
  }
  EXPECT_LT(slip, 2e-3) << "m/s: the jellies slide on each other";
  EXPECT_LT(lean, 10) << "degrees: the column fell";
  std::printf("%s 1/%g s: largest sideways slip between resting jellies %.2e m/s, tilt %.1f degrees, speed %.3f m/s\n",
              c.integrator, 1 / c.dt, slip, lean, sway);
}

INSTANTIATE_TEST_SUITE_P(Stacks, BodyStick,
                         ::testing::Values(Case{"backward-euler", 1.0 / 60, true},
                                           Case{"backward-euler", 1.0 / 240, true}),
                         [](const auto& info) {
                           return "backward_euler_" + std::to_string(std::lround(1 / info.param.dt));
                         });

// Not a test: the measurement of docs/body-contact.md ("Rest"), six jellies in the offset column (the soft ones of the
// test, and the reported pile's stiffer 4^3 ones under backward Euler at 1/240 s and 1/60 s), the floor's restitution
// 0.2 (jelly_stack's) and 0: over 14 s, the largest particle speed over each half second, the total energy, each
// jelly's tilt (degrees between its lattice's vertical axis and the vertical). Run with
// --gtest_also_run_disabled_tests.
struct TraceCase {
  const char* integrator;
  double dt;
  bool stiff;
  double restitution;
};
void PrintTo(const TraceCase& c, std::ostream* os) {
  *os << c.integrator << " at 1/" << std::lround(1 / c.dt) << " s, " << (c.stiff ? "stiff" : "soft")
      << " jellies, floor restitution " << c.restitution;
}

class ColumnTrace : public ::testing::TestWithParam<TraceCase> {};

TEST_P(ColumnTrace, DISABLED_SixJellies) {
  const TraceCase c = GetParam();
  testing::ColumnParams p;
  p.count = 6;
  if (c.stiff) p.jelly = kStiffJelly;
  p.floor.restitution = c.restitution;
  auto system = testing::jellyColumn(p);
  Simulation sim(*system, makeIntegrator(c.integrator), c.dt);
  std::printf("%s 1/%g s, %s jellies, floor restitution %g\n", c.integrator, 1 / c.dt, c.stiff ? "stiff" : "soft",
              c.restitution);
  double speed = 0;  // the largest over the current half second
  for (int frame = 1; frame <= 14 * 60; ++frame) {
    if (sim.advanceTo(frame * kFrame)) {
      std::printf("blew up at %g s\n", sim.time());
      return;
    }
    speed = std::max(speed, sim.lastIntervalMaxSpeed());
    if (frame % 30) continue;
    std::printf("t %4.1f s  largest speed %.3f m/s  energy %.3f J  tilts", sim.time(), speed,
                system->energy(sim.x(), sim.v()));
    for (int b = 0; b < p.count; ++b) std::printf(" %4.1f", tilt(*system, sim.x(), b, p.jelly.n));
    std::printf("\n");
    speed = 0;
  }
  if (sim.energyGain()) std::printf("%s\n", sim.energyGain()->message(c.dt).c_str());
}

// Not a test either: the sway of columns of 3 to 6 of the stiff jellies set down 2 mm apart (backward Euler at
// 1/240 s, dead floor), as docs/body-contact.md ("Rest") gives it: the times at which the top jelly's tilt passes a
// least value (its sway's period), the tilt's range and the largest particle speed over the 6th second.
TEST(ColumnSway, DISABLED_ByHeight) {
  for (int count = 3; count <= 6; ++count) {
    testing::ColumnParams p;
    p.count = count;
    p.jelly = kStiffJelly;
    p.gap = 0.002;
    p.floor.restitution = 0;
    auto system = testing::jellyColumn(p);
    Simulation sim(*system, makeIntegrator("backward-euler"), 1.0 / 240);
    std::printf("%d jellies: least tilt at", count);
    double before = -1, last = -1, low = 180, high = 0, speed = 0;
    for (int frame = 1; frame <= 6 * 60; ++frame) {
      ASSERT_FALSE(sim.advanceTo(frame * kFrame));
      const double top = tilt(*system, sim.x(), count - 1, p.jelly.n);
      if (frame % 3 == 0) {  // every 0.05 s
        if (before >= 0 && last < before && last <= top) std::printf(" %.2f", sim.time() - 0.05);
        before = last, last = top;
      }
      if (sim.time() > 1) low = std::min(low, top), high = std::max(high, top);
      if (sim.time() > 5) speed = std::max(speed, sim.lastIntervalMaxSpeed());
    }
    std::printf(" s; top tilt %.2f-%.2f degrees after 1 s, largest speed in the 6th second %.3f m/s\n", low, high,
                speed);
  }
}

// The six stiff jellies' sway against the same column glued into one body (testing::fusedColumn: the jellies' lattice
// with springs across each gap where the stack has contact). Both are set down still on a dead floor, the stack's
// jellies one contact thickness apart, and given the same push: the velocity of a turn about the column's foot (the
// top at 0.1 m/s). Each is sampled every frame: the top jelly's mean velocity along the push.
struct Sway {
  std::vector<double> time, speed;  // the top jelly's mean velocity along the push
  double lean = 0;                  // degrees: the most the top jelly's centre leans from the bottom one's
  double last_speed = 0;            // m/s: the largest particle speed over the last second
};

constexpr double kFitFrom = 2;  // s: after the column has sunk under its load

struct SwayFit {
  double period = 0;  // s: twice the mean time between sign changes of the speed
  double decay = 0;   // 1/s: lambda of the half-cycles' peak speeds ~ exp(-lambda t), least squares on their logs
  int half_cycles = 0;
};

SwayFit fit(const Sway& s, double from) {
  std::vector<double> crossings, peak_time, peak_log;
  double peak = 0, at = 0;
  for (std::size_t f = 1; f < s.speed.size(); ++f) {
    if (s.time[f] < from) continue;
    const double a = s.speed[f - 1], b = s.speed[f];
    if ((a < 0) != (b < 0)) {
      crossings.push_back(s.time[f - 1] + (s.time[f] - s.time[f - 1]) * a / (a - b));
      if (crossings.size() > 1) peak_time.push_back(at), peak_log.push_back(std::log(peak));
      peak = 0;
    }
    if (std::abs(b) > peak) peak = std::abs(b), at = s.time[f];
  }
  SwayFit r;
  r.half_cycles = int(peak_time.size());
  if (crossings.size() > 1) r.period = 2 * (crossings.back() - crossings.front()) / double(crossings.size() - 1);
  if (peak_time.size() > 1) {
    double mt = 0, ml = 0, stt = 0, stl = 0;
    for (std::size_t i = 0; i < peak_time.size(); ++i) mt += peak_time[i], ml += peak_log[i];
    mt /= double(peak_time.size()), ml /= double(peak_time.size());
    for (std::size_t i = 0; i < peak_time.size(); ++i)
      stt += (peak_time[i] - mt) * (peak_time[i] - mt), stl += (peak_time[i] - mt) * (peak_log[i] - ml);
    r.decay = -stl / stt;
  }
  return r;
}

// The column's jellies set down still on the floor, one contact thickness apart, and pushed: the top at push m/s.
std::vector<Body> pushedColumn(const testing::ColumnParams& p, double push) {
  std::vector<Body> jellies = testing::columnJellies(p);
  const double drop = 0.048;  // columnJellies sets the bottom 0.05 m up: now 2 mm, within the floor's band
  const double height = p.count * p.jelly.size + (p.count - 1) * p.gap;
  const double omega = push / height;  // about -z: the top moves along +x
  for (Body& b : jellies)
    for (int q = 0; q < b.particleCount(); ++q) {
      Vec3 x = particle(b.x, q) - Vec3(0, drop, 0);
      particle(b.x, q) = x;
      particle(b.v, q) = Vec3(omega * x.y(), -omega * x.x(), 0);
    }
  return jellies;
}

// Runs system (its particles: the jellies' in order, n^3 each, whether as bodies or as the fused lattice) for seconds.
Sway runSway(MassSpringSystem& system, const std::vector<int>& top, const std::vector<int>& bottom, double dt,
             double seconds, const char* integrator) {
  Simulation sim(system, makeIntegrator(integrator), dt);
  Sway s;
  const auto mean = [](const VecX& y, const std::vector<int>& ids) {
    Vec3 sum = Vec3::Zero();
    for (int q : ids) sum += particle(y, q);
    return Vec3(sum / double(ids.size()));
  };
  for (int frame = 1; frame <= std::lround(seconds / kFrame); ++frame) {
    if (sim.advanceTo(frame * kFrame)) break;
    s.time.push_back(sim.time());
    s.speed.push_back(mean(sim.v(), top).x());
    const Vec3 d = mean(sim.x(), top) - mean(sim.x(), bottom);
    s.lean = std::max(s.lean, std::atan2(std::hypot(d.x(), d.z()), d.y()) * 180 / double(EIGEN_PI));
    if (sim.time() > seconds - 1) s.last_speed = std::max(s.last_speed, sim.lastIntervalMaxSpeed());
  }
  return s;
}

// The particles of jelly b, in the stack (bodies in order) and in the fused lattice.
std::vector<int> stackedJelly(int b, int n) {
  std::vector<int> ids;
  for (int q = 0; q < n * n * n; ++q) ids.push_back(b * n * n * n + q);
  return ids;
}
std::vector<int> fusedJelly(int b, int n, int count) {
  std::vector<int> ids;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) ids.push_back(testing::fusedParticle(b, n, count, i, j, k));
  return ids;
}

struct SwayPair {
  Sway stacked, fused;
};

SwayPair swayPair(const testing::ColumnParams& p, double push, double dt, double seconds,
                  const char* integrator = "backward-euler") {
  const std::vector<Body> jellies = pushedColumn(p, push);
  const int n = p.jelly.n;
  MassSpringSystem stack, glued;
  for (const Body& b : jellies) stack.addBody(b);
  testing::addFloor(stack, p);
  glued.addBody(testing::fusedColumn(jellies, n));
  testing::addFloor(glued, p);
  return {runSway(stack, stackedJelly(p.count - 1, n), stackedJelly(0, n), dt, seconds, integrator),
          runSway(glued, fusedJelly(p.count - 1, n, p.count), fusedJelly(0, n, p.count), dt, seconds, integrator)};
}

testing::ColumnParams swayColumn(double offset) {
  testing::ColumnParams p;
  p.count = 6;
  p.jelly = kStiffJelly;
  p.gap = SurfaceContact{}.thickness;
  p.offset = offset;
  p.floor.restitution = 0;
  return p;
}

// The three soft jellies of BodyRest (6% offsets), one contact thickness apart on a dead floor.
testing::ColumnParams softColumn() {
  testing::ColumnParams p;
  p.gap = SurfaceContact{}.thickness;
  p.floor.restitution = 0;
  return p;
}

// What keeps the six stiff jellies swaying is the column's own mode, not its contacts: stacked, they sway with the
// period of the same lattice glued into one body (testing::fusedColumn, the oracle: no contact at all) and lose their
// sway at least as fast. Both straight, set down still on a dead floor, the stack's jellies one contact thickness
// apart, given the same push (the top at 0.1 m/s), backward Euler for 10 s; fitted from 2 s on. docs/body-contact.md
// ("Rest") has the figures, and those of the offset column (ColumnSway.DISABLED_StackedAgainstFused).
class StackedColumn : public ::testing::TestWithParam<Case> {};

TEST_P(StackedColumn, SwaysAsTheSameColumnGluedIntoOneBody) {
  const Case c = GetParam();
  const SwayPair r = swayPair(c.stiff ? swayColumn(0) : softColumn(), 0.1, c.dt, 10, c.integrator);
  const SwayFit stacked = fit(r.stacked, kFitFrom), fused = fit(r.fused, kFitFrom);
  std::printf(
      "1/%g s: stacked: period %.3f s, decay %.3f 1/s, lean %.2f deg; glued: period %.3f s, decay %.3f 1/s, "
      "lean %.2f deg\n",
      1 / c.dt, stacked.period, stacked.decay, r.stacked.lean, fused.period, fused.decay, r.fused.lean);
  ASSERT_EQ(r.stacked.time.size(), r.fused.time.size()) << "a run stopped early";
  ASSERT_GE(fused.half_cycles, 5);
  ASSERT_GT(fused.decay, 0) << "the glued column's own sway must decay";
  EXPECT_LT(r.stacked.lean, 10) << "degrees: the stack fell";
  EXPECT_NEAR(stacked.period / fused.period, 1, 0.15) << "the stack sways in a mode the glued column does not have";
  EXPECT_GE(stacked.decay, 0.8 * fused.decay) << "the contacts keep the sway going (or feed it)";
}

// And under RK4 the soft three of BodyRest (RestUnderRk4): the stack on its penalty layer sways as the glued column.
INSTANTIATE_TEST_SUITE_P(Stacks, StackedColumn,
                         ::testing::Values(Case{"backward-euler", 1.0 / 60, true},
                                           Case{"backward-euler", 1.0 / 240, true}, Case{"rk4", 1.0 / 240}),
                         [](const auto& info) {
                           std::string name = info.param.integrator;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name + "_" + std::to_string(std::lround(1 / info.param.dt)) +
                                  (info.param.stiff ? "" : "_soft_three");
                         });

// Not a test: the figures of docs/body-contact.md ("Rest"): period, decay and lean of the stack and of the fused
// column, straight and offset, backward Euler at 1/60 s and 1/240 s, over 10 s.
TEST(ColumnSway, DISABLED_StackedAgainstFused) {
  for (double push : {0.1, 0.05})
    for (double offset : {0.0, 0.06})
      for (double dt : {1.0 / 60, 1.0 / 240}) {
        const SwayPair r = swayPair(swayColumn(offset), push, dt, 10);
        for (const auto& [name, s] : {std::pair{"stacked", &r.stacked}, std::pair{"fused", &r.fused}}) {
          const SwayFit f = fit(*s, kFitFrom);
          std::printf(
              "push %.2f m/s, offset %.2f, 1/%g s, %-7s: period %.3f s, decay %.3f 1/s over %d half-cycles, lean up to "
              "%.2f deg, "
              "largest speed in the last second %.4f m/s; ran %.2f s\n",
              push, offset, 1 / dt, name, f.period, f.decay, f.half_cycles, s->lean, s->last_speed, s->time.back());
          std::printf("  peaks:");
          double peak = 0;
          for (std::size_t i = 1; i < s->speed.size(); ++i) {
            if ((s->speed[i - 1] < 0) != (s->speed[i] < 0)) std::printf(" %.1f:%.4f", s->time[i], peak), peak = 0;
            peak = std::max(peak, std::abs(s->speed[i]));
          }
          std::printf("\n");
        }
      }
}

// Not a test: the soft three-jelly column of BodyRest (6% offsets, dead floor), stacked and glued into one body, set
// down and given the same push (the top at 0.1 m/s), under RK4 and backward Euler: docs/body-contact.md ("Rest").
TEST(ColumnSway, DISABLED_SoftThreeStackedAgainstFused) {
  const testing::ColumnParams p = softColumn();
  for (const char* integrator : {"rk4", "backward-euler"})
    for (double dt : {1.0 / 60, 1.0 / 240}) {
      const SwayPair r = swayPair(p, 0.1, dt, 6, integrator);
      for (const auto& [name, s] : {std::pair{"stacked", &r.stacked}, std::pair{"glued", &r.fused}}) {
        const SwayFit f = fit(*s, 1);
        std::printf(
            "%s 1/%g s, %-7s: period %.3f s, decay %.3f 1/s over %d half-cycles, lean up to %.2f deg, "
            "largest speed in the last second %.4f m/s; ran %.2f s\n  peaks:",
            integrator, 1 / dt, name, f.period, f.decay, f.half_cycles, s->lean, s->last_speed, s->time.back());
        double peak = 0;
        for (std::size_t i = 1; i < s->speed.size(); ++i) {
          if ((s->speed[i - 1] < 0) != (s->speed[i] < 0)) std::printf(" %.1f:%.4f", s->time[i], peak), peak = 0;
          peak = std::max(peak, std::abs(s->speed[i]));
        }
        std::printf("\n");
      }
    }
}

INSTANTIATE_TEST_SUITE_P(
    Measure, ColumnTrace,
    ::testing::Values(TraceCase{"rk4", 1.0 / 60, false, 0.2}, TraceCase{"rk4", 1.0 / 240, false, 0.2},
                      TraceCase{"backward-euler", 1.0 / 60, false, 0.2},
                      TraceCase{"backward-euler", 1.0 / 240, false, 0.2}, TraceCase{"rk4", 1.0 / 240, false, 0},
                      TraceCase{"backward-euler", 1.0 / 240, false, 0},
                      TraceCase{"backward-euler", 1.0 / 240, true, 0.2},
                      TraceCase{"backward-euler", 1.0 / 240, true, 0}, TraceCase{"backward-euler", 1.0 / 60, true, 0.2},
                      TraceCase{"backward-euler", 1.0 / 60, true, 0}),
    [](const auto& info) {
      const TraceCase& c = info.param;
      std::string name = std::string(c.integrator) + "_" + std::to_string(std::lround(1 / c.dt)) +
                         (c.stiff ? "_stiff" : "_soft") + (c.restitution > 0 ? "_bouncing_floor" : "_dead_floor");
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

// The soft three-jelly column of BodyRest set one contact thickness apart and dropped 5 cm onto the dead floor (it
// lands at 0.1 s), stacked or glued into one body (testing::fusedColumn: the same lattice, particles and springs, and
// springs across each gap instead of contact), under rk4 for seconds: the largest particle speed over each half second,
// over the last second (from 3 s after the landing) and the total energy's largest rise from 1 s after it.
struct Drop {
  std::vector<double> speeds;  // largest over each half second
  double late_speed = 0, rise = 0, energy = 0;
  int crossings = 0;
  bool stopped = false, gained = false;
};
Drop dropColumn(bool glued, double dt, double seconds) {
  testing::ColumnParams p;
  p.floor.restitution = 0;
  p.gap = SurfaceContact{}.thickness;
  const std::vector<Body> jellies = testing::columnJellies(p);
  MassSpringSystem system;
  testing::ParticleTriangles tris;
  if (glued) system.addBody(testing::fusedColumn(jellies, p.jelly.n));
  else
    for (const Body& b : jellies) system.addBody(b);
  for (std::size_t b = 0; b < system.bodies().size(); ++b)
    testing::addSurface(tris, system.bodies()[b].body.surface, system.bodies()[b].first, int(b));
  testing::addFloor(system, p);
  Simulation sim(system, makeIntegrator("rk4"), dt);
  Drop d;
  double most = 0, lowest = 1e300;
  constexpr double kLanding = 0.1;
  for (int frame = 1; frame <= std::lround(seconds / kFrame); ++frame) {
    if ((d.stopped = bool(sim.advanceTo(frame * kFrame)))) break;
    most = std::max(most, sim.lastIntervalMaxSpeed());
    if (frame % 30 == 0) d.speeds.push_back(most), most = 0;
    if (!glued) d.crossings = std::max(d.crossings, testing::intersectingPairs(tris, sim.x()));
    d.energy = sim.countedEnergy();
    if (sim.time() > kLanding + kBounceTime - 1e-9) d.rise = std::max(d.rise, d.energy - lowest);
    lowest = std::min(lowest, d.energy);
    if (sim.time() > kLanding + kSettleTime - 1e-9) d.late_speed = std::max(d.late_speed, sim.lastIntervalMaxSpeed());
  }
  d.gained = bool(sim.energyGain());
  return d;
}

// Under rk4 the pile's aim is the same column glued into one body: rk4 at 1/240 s takes out little of the column's own
// sway (its dampers, kd 0.5, act on strain rates), and the glued column, dropped the same way, still moves at 0.19 m/s
// 3 s after landing. The stack, on its contacts, must settle at least as fast, with no surface through another and no
// gain reported; its energy may rise by at most 0.15% after the bounce (9.6 mJ of 30.4 J here with RK4's penalty
// layer, stage_penalty.h; 27 mJ with the pass alone holding the pile, as it does for the other explicit integrators),
// where the glued column's only falls. docs/body-contact.md, "Rest".
TEST(RestUnderRk4, TheStackSettlesAtLeastAsFastAsTheColumnGluedIntoOneBody) {
  const double dt = 1.0 / 240, seconds = 4;
  const Drop stacked = dropColumn(false, dt, seconds), glued = dropColumn(true, dt, seconds);
  ASSERT_FALSE(stacked.stopped || glued.stopped);
  EXPECT_LE(stacked.late_speed, glued.late_speed) << "m/s, from 3 s after the landing";
  EXPECT_LT(stacked.rise, 1.5e-3 * stacked.energy) << "J: the stack's energy rose while it settled";
  EXPECT_EQ(glued.rise, 0) << "J: the glued column's energy rose (the oracle)";
  EXPECT_EQ(stacked.crossings, 0);
  EXPECT_FALSE(stacked.gained);
  std::printf(
      "rk4 1/240 s: from 3 s after the landing, stacked %.4f m/s, glued %.4f m/s; energy rise %.2e J of %.2f J\n",
      stacked.late_speed, glued.late_speed, stacked.rise, stacked.energy);
}

// Not a test: the figures of docs/body-contact.md ("Rest", rk4): dropColumn's speeds over each half second for 8 s,
// stacked and glued, rk4 at 1/60, 1/240 and 1/960 s.
TEST(ColumnDrop, DISABLED_StackedAgainstGlued) {
  for (double dt : {1.0 / 60, 1.0 / 240, 1.0 / 960})
    for (bool glued : {false, true}) {
      const Drop d = dropColumn(glued, dt, 8);
      std::printf("rk4 1/%g s, %s:", 1 / dt, glued ? "glued" : "stacked");
      for (double v : d.speeds) std::printf(" %.3f", v);
      std::printf("%s%s; from 3 s after the landing %.4f m/s, energy rise %.2e J, at the end %.4f J\n",
                  d.stopped ? " (stopped)" : "", d.gained ? " (energy gain reported)" : "", d.late_speed, d.rise,
                  d.energy);
    }
}

}  // namespace
}  // namespace wobble
