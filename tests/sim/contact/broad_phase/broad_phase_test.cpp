// The broad phase (sim/contact/broad_phase/broad_phase.h) against the plain double loop over every pair of boxes: the
// same pairs in the same ascending order, for one list on both sides and for two, with the culls' keep filter, and for
// the marked variant with few and with many marks (its two halves, marked queries and marked targets, found different
// ways).
#include "sim/contact/broad_phase/broad_phase.h"

#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <utility>
#include <vector>

namespace wobble::collision {
namespace {

// n boxes in a 1 m cube, each up to `size` on a side, a few of them large (a fast element's sweep).
std::vector<Box> randomBoxes(int n, double size, std::mt19937& rng) {
  std::uniform_real_distribution<double> at(0, 1), extent(0, size);
  std::vector<Box> boxes(n);
  for (int k = 0; k < n; ++k) {
    const Vec3 lo(at(rng), at(rng), at(rng));
    const double scale = k % 97 == 0 ? 20 : 1;
    boxes[k] = {lo, lo + scale * Vec3(extent(rng), extent(rng), extent(rng))};
  }
  return boxes;
}

std::vector<char> randomMarks(int n, double share, std::mt19937& rng) {
  std::bernoulli_distribution marked(share);
  std::vector<char> marks(n);
  for (char& m : marks) m = marked(rng);
  return marks;
}

// The oracle: every pair, in order.
std::vector<std::pair<int, int>> allPairs(const std::vector<Box>& queries, const std::vector<Box>& targets, bool same,
                                          const std::function<bool(int, int)>& keep, const std::vector<char>* qm,
                                          const std::vector<char>* tm) {
  std::vector<std::pair<int, int>> out;
  for (int q = 0; q < int(queries.size()); ++q)
    for (int t = same ? q + 1 : 0; t < int(targets.size()); ++t) {
      if (qm && !(*qm)[q] && !(*tm)[t]) continue;
      if (queries[q].overlaps(targets[t]) && keep(q, t)) out.emplace_back(q, t);
    }
  return out;
}

TEST(BroadPhase, FindsExactlyTheOverlappingPairsInOrder) {
  std::mt19937 rng(7);
  const auto keep = [](int q, int t) { return (q + 3 * t) % 5 != 0; };  // a filter, as the culls' adjacency test
  for (const bool parallel : {false, true}) {
    const auto queries = randomBoxes(1500, 0.04, rng), targets = randomBoxes(2500, 0.06, rng);
    std::vector<std::pair<int, int>> found;
    ASSERT_TRUE(overlappingPairs(queries, targets, false, parallel, keep, found));
    const auto expected = allPairs(queries, targets, false, keep, nullptr, nullptr);
    EXPECT_GT(expected.size(), 1000u);
    EXPECT_EQ(found, expected);
    ASSERT_TRUE(overlappingPairs(targets, targets, true, parallel, keep, found));
    EXPECT_EQ(found, allPairs(targets, targets, true, keep, nullptr, nullptr));
  }
}

TEST(BroadPhase, MarkedPairsAreThoseWithAMarkedElement) {
  std::mt19937 rng(11);
  const auto keep = [](int q, int t) { return (2 * q + t) % 7 != 0; };
  for (const double share : {0.01, 0.2, 0.9})
    for (const bool parallel : {false, true}) {
      const auto queries = randomBoxes(1500, 0.04, rng), targets = randomBoxes(2500, 0.06, rng);
      const auto qm = randomMarks(1500, share, rng), tm = randomMarks(2500, share, rng);
      std::vector<std::pair<int, int>> found;
      ASSERT_TRUE(overlappingMarkedPairs(queries, targets, false, parallel, qm, tm, keep, found));
      const auto expected = allPairs(queries, targets, false, keep, &qm, &tm);
      EXPECT_FALSE(expected.empty());
      EXPECT_EQ(found, expected) << "share " << share;
      ASSERT_TRUE(overlappingMarkedPairs(targets, targets, true, parallel, tm, tm, keep, found));
      EXPECT_EQ(found, allPairs(targets, targets, true, keep, &tm, &tm)) << "share " << share;
    }
}

TEST(BroadPhase, StopsOverTheLimit) {
  std::mt19937 rng(3);
  const auto boxes = randomBoxes(800, 0.3, rng);
  const auto all = allPairs(
      boxes, boxes, true, [](int, int) { return true; }, nullptr, nullptr);
  std::vector<std::pair<int, int>> found;
  EXPECT_FALSE(overlappingPairs(
      boxes, boxes, true, true, [](int, int) { return true; }, found, all.size() - 1));
  EXPECT_TRUE(overlappingPairs(
      boxes, boxes, true, true, [](int, int) { return true; }, found, all.size()));
  const std::vector<char> marks(800, 1);
  EXPECT_FALSE(overlappingMarkedPairs(
      boxes, boxes, true, true, marks, marks, [](int, int) { return true; }, found, all.size() - 1));
}

}  // namespace
}  // namespace wobble::collision
