// The coarse level's block LDL^T (sim/solver/block_ldlt.h) against a dense solve of the same matrix: a symmetric, blockwise
// diagonally dominant (so positive definite) matrix of 3 x 3 blocks on a grid graph cut by one level of nested
// dissection, in an order with fill-in. Also: the same bytes with the parts on one thread or two, a pivot that is not
// positive definite reported (and a zero solve), a block between the parts refused.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstring>
#include <random>
#include <stdexcept>

#include "sim/solver/block_ldlt.h"
#include "sim/solver/graph_dissection.h"

namespace wobble {
namespace {

struct BlockSystem {
  int n = 0, p1 = 0, p2 = 0;
  std::vector<std::pair<int, int>> lower;  // (row, column) in the factor's order
  std::vector<Eigen::Matrix3d> diagonal, blocks;
  Eigen::MatrixXd dense;
};

// A w x h grid of blocks with its 8 neighbours, ordered part 0, part 1, separator (rows in grid order within each:
// not fill-reducing, so the factor has fill-in), random off-diagonal blocks and diagonal blocks that dominate them.
BlockSystem gridSystem(int w, int h, unsigned seed) {
  std::vector<std::pair<int, int>> edges;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int i = y * w + x;
      if (x + 1 < w) edges.emplace_back(i, i + 1);
      if (y + 1 < h) edges.emplace_back(i, i + w);
      if (x + 1 < w && y + 1 < h) edges.emplace_back(i, i + w + 1);
      if (x > 0 && y + 1 < h) edges.emplace_back(i, i + w - 1);
    }
  BlockSystem s;
  s.n = w * h;
  const std::vector<int> part = dissect(s.n, edges);
  std::vector<int> column(s.n);
  int next = 0;
  for (int k = 0; k < 3; ++k) {
    if (k == 1) s.p1 = next;
    if (k == 2) s.p2 = next;
    for (int i = 0; i < s.n; ++i)
      if (part[i] == k) column[i] = next++;
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  s.dense = Eigen::MatrixXd::Zero(3 * s.n, 3 * s.n);
  for (const auto& [a, b] : edges) {
    const int i = std::max(column[a], column[b]), j = std::min(column[a], column[b]);
    Eigen::Matrix3d block;
    for (int c = 0; c < 9; ++c) block(c / 3, c % 3) = u(rng);
    s.lower.emplace_back(i, j);
    s.blocks.push_back(block);
    s.dense.block<3, 3>(3 * i, 3 * j) = block;
    s.dense.block<3, 3>(3 * j, 3 * i) = block.transpose();
  }
  s.diagonal.resize(s.n);
  for (int i = 0; i < s.n; ++i) {
    const double off = s.dense.middleRows(3 * i, 3).cwiseAbs().rowwise().sum().maxCoeff();
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity() * (off + 1.0);
    d(0, 1) = d(1, 0) = 0.25 * u(rng);
    s.diagonal[i] = d;
    s.dense.block<3, 3>(3 * i, 3 * i) = d;
  }
  return s;
}

void load(BlockLdlt& ldlt, const BlockSystem& s) {
  ldlt.analyze(s.n, s.lower, s.p1, s.p2);
  for (int i = 0; i < s.n; ++i) ldlt.diagonal(i) = s.diagonal[i];
  for (std::size_t k = 0; k < s.blocks.size(); ++k) ldlt.lower(int(k)) = s.blocks[k];
}

TEST(BlockLdlt, SolvesLikeADenseFactorization) {
  const BlockSystem s = gridSystem(9, 7, 1);
  ASSERT_GT(s.p1, 0);
  ASSERT_GT(s.p2, s.p1);
  ASSERT_LT(s.p2, s.n);
  BlockLdlt ldlt;
  load(ldlt, s);
  ASSERT_TRUE(ldlt.factorize(false));
  EXPECT_GT(ldlt.factorBlocks(), s.lower.size());  // fill-in: the symbolic step added blocks
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd b(3 * s.n);
  for (Eigen::Index c = 0; c < b.size(); ++c) b[c] = u(rng);
  Eigen::VectorXd y = b;
  ldlt.solve(y.data());
  const Eigen::VectorXd expected = s.dense.ldlt().solve(b);
  EXPECT_LT((y - expected).norm(), 1e-12 * expected.norm());
  EXPECT_LT((s.dense * y - b).norm(), 1e-12 * b.norm());
}

TEST(BlockLdlt, SameBytesWithThePartsOnOneThreadOrTwo) {
  const BlockSystem s = gridSystem(12, 10, 3);
  BlockLdlt serial, parallel;
  load(serial, s);
  load(parallel, s);
  ASSERT_TRUE(serial.factorize(false));
  ASSERT_TRUE(parallel.factorize(true));
  Eigen::VectorXd y0 = Eigen::VectorXd::LinSpaced(3 * s.n, -1, 2), y1 = y0;
  serial.solve(y0.data(), false);
  parallel.solve(y1.data(), true);
  EXPECT_EQ(std::memcmp(y0.data(), y1.data(), sizeof(double) * y0.size()), 0);
}

TEST(BlockLdlt, FillWritesEachPartsRightHandSideBeforeItsSolve) {
  const BlockSystem s = gridSystem(8, 8, 4);
  BlockLdlt ldlt;
  load(ldlt, s);
  ASSERT_TRUE(ldlt.factorize(true));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(3 * s.n, 1, 3);
  const int begin[4] = {0, s.p1, s.p2, s.n};
  Eigen::VectorXd y = Eigen::VectorXd::Constant(3 * s.n, 1e300);  // garbage until filled
  ldlt.solve(y.data(), true, [&](int k) {
    y.segment(3 * begin[k], 3 * (begin[k + 1] - begin[k])) = b.segment(3 * begin[k], 3 * (begin[k + 1] - begin[k]));
  });
  EXPECT_LT((s.dense * y - b).norm(), 1e-12 * b.norm());
}

TEST(BlockLdlt, ReportsAPivotThatIsNotPositiveDefinite) {
  BlockSystem s = gridSystem(6, 6, 5);
  s.diagonal[s.n - 1] = -s.diagonal[s.n - 1];  // the last separator pivot
  BlockLdlt ldlt;
  load(ldlt, s);
  EXPECT_FALSE(ldlt.factorize(false));
  Eigen::VectorXd y = Eigen::VectorXd::Ones(3 * s.n);
  ldlt.solve(y.data());
  EXPECT_EQ(y.norm(), 0);
}

TEST(BlockLdlt, RefusesABlockBetweenTheParts) {
  BlockLdlt ldlt;
  // Parts: {0, 1}, {2}, separator {3}.
  EXPECT_THROW(ldlt.analyze(4, {{2, 1}, {1, 0}}, 2, 3), std::invalid_argument);  // (2, 1): part 1 to part 0
  EXPECT_THROW(ldlt.analyze(4, {{1, 0}, {2, 0}}, 2, 3), std::invalid_argument);  // (2, 0): likewise
  EXPECT_THROW(ldlt.analyze(4, {{0, 1}}, 2, 3), std::invalid_argument);          // above the diagonal
  EXPECT_NO_THROW(ldlt.analyze(4, {{1, 0}, {3, 0}, {3, 2}}, 2, 3));              // parts to the separator only
}

}  // namespace
}  // namespace wobble
