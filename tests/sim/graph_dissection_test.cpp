// One level of nested dissection (sim/solver/graph_dissection.h), checked on graphs whose answer is known: no edge ever joins
// the two parts (what lets the coarse solve run them on two threads), the parts of a grid hold 40% of the nodes or
// more each, the separator of a grid is about one diagonal, and other components go to part 1.
#include <gtest/gtest.h>

#include <algorithm>

#include "sim/solver/graph_dissection.h"

namespace wobble {
namespace {

using Edges = std::vector<std::pair<int, int>>;

// A w x h grid with its 8 neighbours (as the aggregates of a cloth: rows, columns and diagonals), numbered from
// `first`.
Edges grid(int w, int h, int first = 0) {
  Edges edges;
  const auto at = [&](int x, int y) { return first + y * w + x; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (x + 1 < w) edges.emplace_back(at(x, y), at(x + 1, y));
      if (y + 1 < h) edges.emplace_back(at(x, y), at(x, y + 1));
      if (x + 1 < w && y + 1 < h) edges.emplace_back(at(x, y), at(x + 1, y + 1));
      if (x > 0 && y + 1 < h) edges.emplace_back(at(x, y), at(x - 1, y + 1));
    }
  return edges;
}

int countOf(const std::vector<int>& part, int k) { return int(std::count(part.begin(), part.end(), k)); }

void expectNoEdgeBetweenTheParts(const std::vector<int>& part, const Edges& edges) {
  for (const auto& [i, j] : edges) EXPECT_NE(part[i] + part[j], 1) << "edge " << i << " - " << j;
}

TEST(GraphDissection, AGridSplitsInNearHalvesWithAShortSeparator) {
  for (const auto& [w, h] : {std::pair{18, 19}, std::pair{30, 10}, std::pair{7, 40}}) {
    const int n = w * h;
    const Edges edges = grid(w, h);
    const std::vector<int> part = dissect(n, edges);
    ASSERT_EQ(int(part.size()), n);
    expectNoEdgeBetweenTheParts(part, edges);
    // 45% or more each when a level allows it, else the middle level: here at least 40%.
    EXPECT_GE(5 * countOf(part, 0), 2 * n) << w << " x " << h;
    EXPECT_GE(5 * countOf(part, 1), 2 * n) << w << " x " << h;
    // The separator is one breadth-first level: with diagonal neighbours, the nodes at one Chebyshev distance from
    // the start, a row, an L or a U across the grid: at most w + h nodes, a small part of the n.
    EXPECT_LE(countOf(part, 2), w + h) << w << " x " << h;
    EXPECT_GT(countOf(part, 2), 0);
  }
}

TEST(GraphDissection, APathIsCutAtOneNode) {
  Edges edges;
  for (int i = 0; i + 1 < 9; ++i) edges.emplace_back(i, i + 1);
  const std::vector<int> part = dissect(9, edges);
  expectNoEdgeBetweenTheParts(part, edges);
  EXPECT_EQ(countOf(part, 2), 1);
  EXPECT_EQ(countOf(part, 0), 4);
  EXPECT_EQ(countOf(part, 1), 4);
}

TEST(GraphDissection, OtherComponentsGoToPartOne) {
  Edges edges = grid(6, 6);  // nodes 0..35, the searched component
  const Edges other = grid(4, 4, 36);
  edges.insert(edges.end(), other.begin(), other.end());
  const std::vector<int> part = dissect(36 + 16 + 1, edges);  // and node 52 alone
  expectNoEdgeBetweenTheParts(part, edges);
  for (int i = 36; i < 53; ++i) EXPECT_EQ(part[i], 1) << i;
  EXPECT_GT(countOf(part, 0), 0);
}

TEST(GraphDissection, TinyGraphs) {
  EXPECT_TRUE(dissect(0, {}).empty());
  EXPECT_EQ(dissect(1, {}), std::vector<int>{2});  // one node: the separator, two empty parts
  const std::vector<int> two = dissect(2, {{0, 1}});
  expectNoEdgeBetweenTheParts(two, {{0, 1}});
}

}  // namespace
}  // namespace wobble
