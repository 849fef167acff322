#include "sim/bodies/lattice.h"

#include <algorithm>
#include <cstdlib>

namespace wobble {

Body particleBody(const std::string& name, const std::string& kind, int count, double mass) {
  Body body;
  body.name = name;
  body.kind = kind;
  body.x = VecX::Zero(3 * count);
  body.v = VecX::Zero(3 * count);
  body.mass = VecX::Constant(count, mass);
  body.pinned.assign(count, false);
  return body;
}

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

namespace wobble {

void addPartialLatticeSprings(std::array<int, 3> dims, std::span<const LatticeOffset> offsets,
                              const std::vector<int>& node_index, const std::vector<char>& cell_kept, const VecX& x,
                              double ks, double kd, Springs& springs) {
  const auto node = [&](int i, int j, int k) { return node_index[i + dims[0] * (j + dims[1] * k)]; };
  const std::array<int, 3> cells{dims[0] - 1, dims[1] - 1, dims[2] - 1};
  const auto kept = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < cells[0] && j < cells[1] && k < cells[2] &&
           cell_kept[i + cells[0] * (j + cells[1] * k)];
  };
  // A kept cell holding nodes a and b (offset d, components in {-1, 0, 1}): its corner c has c <= min(a, b) and
  // c >= max(a, b) - 1 in each axis: one choice where d moves, two where it does not.
  const auto shareCell = [&](std::array<int, 3> a, std::array<int, 3> d) {
    std::array<int, 3> lo, hi;
    for (int ax = 0; ax < 3; ++ax) {
      lo[ax] = std::max(a[ax], a[ax] + d[ax]) - 1;
      hi[ax] = std::min(a[ax], a[ax] + d[ax]);
    }
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i)
          if (kept(i, j, k)) return true;
    return false;
  };
  const auto linked = [&](std::array<int, 3> a, std::array<int, 3> d) {
    bool unit = true;
    for (int c : d) unit = unit && std::abs(c) <= 1;
    if (unit) return shareCell(a, d);
    std::array<int, 3> half, mid;
    for (int ax = 0; ax < 3; ++ax) {
      half[ax] = d[ax] / 2;
      mid[ax] = a[ax] + half[ax];
    }
    return node(mid[0], mid[1], mid[2]) >= 0 && shareCell(a, half) && shareCell(mid, half);
  };
  for (const LatticeOffset& o : offsets)
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i) {
          const int i2 = i + o.d[0], j2 = j + o.d[1], k2 = k + o.d[2];
          if (i2 < 0 || i2 >= dims[0] || j2 < 0 || j2 >= dims[1] || k2 < 0 || k2 >= dims[2]) continue;
          const int a = node(i, j, k), b = node(i2, j2, k2);
          if (a < 0 || b < 0 || !linked({i, j, k}, o.d)) continue;
          springs.add(a, b, (particle(x, a) - particle(x, b)).norm(), ks, kd, o.type);
        }
}

}  // namespace wobble
