// WeightedStencil (sim/solver/stencil.h) holds four entries in place and moves to the heap past them (a mesh jelly's
// pairs, up to 32 particles). Its copies, moves and assignments must keep every entry across that boundary, and a
// vector of stencils must keep them through its reallocations: checked against the entries written, and against the
// sums a plain loop over them gives.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "sim/solver/stencil.h"

namespace wobble {
namespace {

WeightedStencil stencilOf(int count, int seed) {
  WeightedStencil s;
  for (int i = 0; i < count; ++i) s.add(3 * i + seed, 0.25 * (i + 1) + seed);
  return s;
}

void expectEntries(const WeightedStencil& s, int count, int seed) {
  ASSERT_EQ(s.size, count);
  for (int i = 0; i < count; ++i) {
    EXPECT_EQ(s.particle[i], 3 * i + seed);
    EXPECT_EQ(s.w[i], 0.25 * (i + 1) + seed);
  }
}

TEST(WeightedStencil, AddSumsTheWeightsOfAParticleAlreadyIn) {
  WeightedStencil s;
  s.add(7, 0.5);
  s.add(2, 1.0);
  s.add(7, 0.25);
  ASSERT_EQ(s.size, 2);
  EXPECT_EQ(s.particle[0], 7);
  EXPECT_EQ(s.w[0], 0.75);
  VecX y = VecX::Zero(3 * 8);
  y.segment<3>(3 * 7) = Vec3(1, 2, 3);
  y.segment<3>(3 * 2) = Vec3(-1, 0, 4);
  EXPECT_EQ(s.sum(y), Vec3(0.75 - 1, 1.5, 2.25 + 4));
}

TEST(WeightedStencil, CopiesAndMovesKeepEveryEntryInPlaceAndOnTheHeap) {
  for (const int count : {0, 3, WeightedStencil::kInline, WeightedStencil::kInline + 1, WeightedStencil::kCapacity}) {
    SCOPED_TRACE(count);
    const WeightedStencil original = stencilOf(count, 1);
    WeightedStencil copy(original);
    expectEntries(copy, count, 1);
    WeightedStencil moved(std::move(copy));
    expectEntries(moved, count, 1);
    for (const int other : {0, 2, WeightedStencil::kCapacity}) {  // assigned over a smaller and a larger stencil
      WeightedStencil target = stencilOf(other, 5);
      target = original;
      expectEntries(target, count, 1);
      WeightedStencil moved_over = stencilOf(other, 5);
      moved_over = std::move(target);
      expectEntries(moved_over, count, 1);
    }
    WeightedStencil self = original;
    const WeightedStencil& alias = self;
    self = alias;
    expectEntries(self, count, 1);
    expectEntries(original, count, 1);  // the source of every copy is left as it was
  }
}

TEST(WeightedStencil, AVectorKeepsItsStencilsThroughReallocation) {
  std::vector<WeightedStencil> stencils;
  for (int k = 0; k < 200; ++k) stencils.push_back(stencilOf(k % 12, k));  // grows past its capacity many times
  stencils.erase(stencils.begin() + 10, stencils.begin() + 40);            // and moves the rest down
  stencils.resize(300);                                                    // new ones empty
  for (int k = 0; k < 170; ++k) {
    const int made = k < 10 ? k : k + 30;
    expectEntries(stencils[k], made % 12, made);
  }
  for (int k = 170; k < 300; ++k) EXPECT_EQ(stencils[k].size, 0);
}

}  // namespace
}  // namespace wobble
