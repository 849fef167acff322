// The spring-run kernel (sim/spring_runs.h) against the scalar spring loop: the schedule's runs cover every spring
// exactly once with the endpoints they claim, and on a random cloth state the run kernel's forces equal the scalar
// loop's to round-off (the terms are summed in another order), coincident endpoints inside a run included.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "dense_matrix.h"
#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/force_jacobian.h"
#include "sim/solver/pair_block_matrix.h"
#include "sim/spring_runs.h"
#include "sim/system.h"

namespace wobble {
namespace {

// Every pair of the schedule lies in exactly one run, and run.first + k is the pair (a + k, a + offset + k).
void expectRunsCoverEveryPairOnce(const PairSchedule& schedule) {
  std::vector<int> seen(schedule.size(), 0);
  for (const PairRun& run : schedule.runs()) {
    ASSERT_GE(run.length, 1);
    for (int k = 0; k < run.length; ++k) {
      const int e = run.first + k;
      ASSERT_LT(e, static_cast<int>(schedule.size()));
      ++seen[e];
      EXPECT_EQ(schedule.a()[e], run.a + k);
      EXPECT_EQ(schedule.b()[e], run.a + run.offset + k);
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<std::ptrdiff_t>(schedule.size()));
  // The tasks' runs (runByRuns) are the same runs, each once.
  std::size_t pairs = 0;
  schedule.runByRuns(false, [&](std::span<const PairRun> runs) {
    for (const PairRun& run : runs) pairs += run.length;
  });
  EXPECT_EQ(pairs, schedule.size());
}

MassSpringSystem clothSystem(int n) {
  ClothParams p;
  p.nx = p.ny = n;
  MassSpringSystem system;
  system.addBody(buildCloth("cloth", p));
  return system;
}

TEST(SpringRuns, CoverEveryPairExactlyOnce) {
  expectRunsCoverEveryPairOnce(clothSystem(100).jacobianPattern());
  MassSpringSystem jelly;
  jelly.addBody(buildJelly("jelly", {.n = 14}));
  expectRunsCoverEveryPairOnce(jelly.jacobianPattern());
  // Irregular pairs: mostly runs of one.
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pick(0, 4999);
  std::vector<int> a, b;
  for (int e = 0; e < 20000; ++e) {
    a.push_back(pick(rng));
    b.push_back(pick(rng));
  }
  expectRunsCoverEveryPairOnce(PairSchedule(a, b, 5000));
}

TEST(SpringRuns, MatchTheScalarLoopOnARandomClothState) {
  // 100 x 100: five schedule blocks, rows of 99 springs (runs), the cross-block tasks' short runs (scalar loop).
  const MassSpringSystem system = clothSystem(100);
  const Springs& s = system.springs();
  const PairSchedule& schedule = system.jacobianPattern();
  const auto longest = std::max_element(schedule.runs().begin(), schedule.runs().end(),
                                        [](const PairRun& p, const PairRun& q) { return p.length < q.length; });
  ASSERT_GE(longest->length, 2 * kMinPairRun);  // the run kernel really runs

  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, 0.01);
  VecX x = system.initialPositions(), v(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += noise(rng), v[i] = 100 * noise(rng);
  // Two endpoints of a spring inside the longest run coincide: no direction, no force, no NaN.
  const int e = longest->first + longest->length / 2;
  particle(x, s.a[e]) = particle(x, s.b[e]);

  VecX scalar = VecX::Zero(x.size()), runs = VecX::Zero(x.size());
  addSpringForces(s, x, v, scalar);
  schedule.runByRuns(false, [&](std::span<const PairRun> task) { addSpringForces(s, task, x, v, runs); });

  double largest_term = 0;  // of a single spring's force: the scale of the round-off
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Vec3 d = particle(x, s.a[i]) - particle(x, s.b[i]);
    const double len = d.norm();
    largest_term = std::max(largest_term, s.ks[i] * std::abs(len - s.rest[i]) +
                                              s.kd[i] * (particle(v, s.a[i]) - particle(v, s.b[i])).norm());
  }
  ASSERT_GT(largest_term, 1.0);  // the noise really loads the springs
  ASSERT_TRUE(runs.allFinite());
  EXPECT_GT(scalar.cwiseAbs().maxCoeff(), 1.0);
  EXPECT_LE((runs - scalar).cwiseAbs().maxCoeff(), 1e-13 * largest_term);
}

TEST(SpringRuns, JacobianBlocksEqualTheTripletJacobians) {
  // The solver's matrix, filled on the fixed pattern with its pair blocks stored as a I + w w^T (run kernel and scalar
  // loop), against -(cx dF/dx + cv dF/dv) assembled from the triplet Jacobians: every entry, and the product with a
  // random vector. The state stretches some springs and compresses others (whose transverse stiffness is clamped to 0).
  const MassSpringSystem system = clothSystem(30);
  const int n = system.particleCount();
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 0.02);
  VecX x = system.initialPositions(), v(x.size()), y(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += noise(rng), v[i] = 50 * noise(rng), y[i] = noise(rng);
  const double cx = 1e-4, cv = 1e-2;
  const Springs& s = system.springs();
  int compressed = 0, stretched = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double len = (particle(x, s.a[i]) - particle(x, s.b[i])).norm();
    compressed += len<s.rest[i], stretched += len> s.rest[i];
  }
  ASSERT_GT(compressed, 100);
  ASSERT_GT(stretched, 100);

  PairBlockMatrix a;
  a.reset(system.jacobianPattern());
  system.fillJacobian(0, x, v, cx, cv, a, nullptr, nullptr);
  const Eigen::MatrixXd blocks = testing::denseMatrix(a);

  Triplets tx, tv;
  system.addForceJacobians(0, x, v, tx, tv);
  Eigen::SparseMatrix<double> kx(3 * n, 3 * n), kv(3 * n, 3 * n);
  kx.setFromTriplets(tx.begin(), tx.end());
  kv.setFromTriplets(tv.begin(), tv.end());
  const Eigen::MatrixXd expected = -(cx * Eigen::MatrixXd(kx) + cv * Eigen::MatrixXd(kv));
  const double scale = expected.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0);
  EXPECT_LE((blocks - expected).cwiseAbs().maxCoeff(), 1e-12 * scale);

  VecX product;
  a.multiply(y, product, false);
  const VecX dense_product = expected * y;
  EXPECT_LE((product - dense_product).cwiseAbs().maxCoeff(), 1e-12 * dense_product.cwiseAbs().maxCoeff());

  // The diagonal blocks (block-Jacobi's setup) against the dense matrix's, the same bytes on one thread and on the
  // schedule's tasks.
  std::vector<Sym3> serial, tasks;
  a.diagonal(serial, false);
  a.diagonal(tasks, true);
  ASSERT_EQ(serial.size(), std::size_t(n));
  double worst = 0;
  for (int p = 0; p < n; ++p) {
    worst = std::max(worst, (serial[p].dense() - expected.block<3, 3>(3 * p, 3 * p)).cwiseAbs().maxCoeff());
    EXPECT_EQ(serial[p].dense(), tasks[p].dense()) << "particle " << p;
  }
  EXPECT_LE(worst, 1e-12 * scale);
}

}  // namespace
}  // namespace wobble
