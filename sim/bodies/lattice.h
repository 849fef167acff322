// Lattice springs shared by the jelly (3-D) and cloth (2-D) builders: every pair of lattice points whose index
// offset is in a list becomes a spring with its initial distance as rest length.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "sim/body.h"
#include "sim/springs.h"

namespace wobble {

// A body of count particles of mass each, all free, at rest at the origin: the builders then place and link them.
Body particleBody(const std::string& name, const std::string& kind, int count, double mass);

struct LatticeOffset {
  std::array<int, 3> d;
  SpringType type;
};

// Lattice of dims[0] x dims[1] x dims[2] points, point (i, j, k) at index i + dims[0] (j + dims[1] k).
// Each offset must be "forward" (first non-zero component positive) so that every pair is linked once.
void addLatticeSprings(std::array<int, 3> dims, std::span<const LatticeOffset> offsets, const VecX& x, double ks,
                       double kd, Springs& springs);

// The springs of a partial lattice: nodes and cells of a dims[0] x dims[1] x dims[2]-point lattice, node_index[i +
// dims[0] (j + dims[1] k)] the particle of a node (-1: absent), cell_kept per cell (dims - 1 each way). An offset with
// components in {-1, 0, 1} links two nodes when a kept cell holds both; a longer one (bending, two apart along an
// axis) when both of its halves are linked. Same order as addLatticeSprings, so a full lattice gives the same springs.
void addPartialLatticeSprings(std::array<int, 3> dims, std::span<const LatticeOffset> offsets,
                              const std::vector<int>& node_index, const std::vector<char>& cell_kept, const VecX& x,
                              double ks, double kd, Springs& springs);

// How many springs addLatticeSprings makes, in 64-bit arithmetic: for sizing a body before building it.
std::int64_t latticeSpringCount(std::array<std::int64_t, 3> dims, std::span<const LatticeOffset> offsets);

}  // namespace wobble
