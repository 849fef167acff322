#include "sim/bodies/lattice.h"

#include <algorithm>
#include <cstdlib>

namespace wobble {

void addLatticeSprings(std::array<int, 3> dims, std::span<const LatticeOffset> offsets, const VecX& x, double ks,
                       double kd, Springs& springs) {
  const auto index = [&](int i, int j, int k) { return i + dims[0] * (j + dims[1] * k); };
  for (const LatticeOffset& o : offsets)  // grouped by offset: springs of one type are contiguous
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i) {
          const int i2 = i + o.d[0], j2 = j + o.d[1], k2 = k + o.d[2];
          if (i2 < 0 || i2 >= dims[0] || j2 < 0 || j2 >= dims[1] || k2 < 0 || k2 >= dims[2]) continue;
          const int a = index(i, j, k), b = index(i2, j2, k2);
          springs.add(a, b, (particle(x, a) - particle(x, b)).norm(), ks, kd, o.type);
        }
}

std::int64_t latticeSpringCount(std::array<std::int64_t, 3> dims, std::span<const LatticeOffset> offsets) {
  std::int64_t count = 0;
  for (const LatticeOffset& o : offsets) {
    std::int64_t pairs = 1;
    for (int a = 0; a < 3; ++a) pairs *= std::max<std::int64_t>(0, dims[a] - std::abs(o.d[a]));
    count += pairs;
  }
  return count;
}

}  // namespace wobble
