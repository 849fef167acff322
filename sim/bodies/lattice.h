// Lattice springs shared by the jelly (3-D) and cloth (2-D) builders: every pair of lattice points whose index
// offset is in a list becomes a spring with its initial distance as rest length.
#pragma once
#include <array>
#include <cstdint>
#include <span>

#include "sim/springs.h"

namespace wobble {

struct LatticeOffset {
  std::array<int, 3> d;
  SpringType type;
};

// Lattice of dims[0] x dims[1] x dims[2] points, point (i, j, k) at index i + dims[0] (j + dims[1] k).
// Each offset must be "forward" (first non-zero component positive) so that every pair is linked once.
void addLatticeSprings(std::array<int, 3> dims, std::span<const LatticeOffset> offsets, const VecX& x, double ks,
                       double kd, Springs& springs);

// How many springs addLatticeSprings makes, in 64-bit arithmetic: for sizing a body before building it.
std::int64_t latticeSpringCount(std::array<std::int64_t, 3> dims, std::span<const LatticeOffset> offsets);

}  // namespace wobble
