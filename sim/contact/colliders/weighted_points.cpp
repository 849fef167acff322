#include "sim/contact/colliders/weighted_points.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "sim/contact/colliders/collider.h"

namespace wobble {

void WeightedPoints::add(const std::array<int, 8>& particle, const std::array<double, 8>& weight, int first,
                         const VecX& inv_mass) {
  // cellBounds holds a point in its cell's box only for a convex combination.
  double sum = 0;
  for (const double wk : weight) {
    if (!(wk >= 0)) throw std::invalid_argument("WeightedPoints::add: a weight is negative or not a number");
    sum += wk;
  }
  if (!(std::abs(sum - 1) <= 1e-12)) throw std::invalid_argument("WeightedPoints::add: the weights do not sum to 1");
  WeightedPoint w{particle, weight, 0};
  for (int k = 0; k < 8; ++k) {
    w.particle[k] += first;
    w.inverse_mass += w.weight[k] * w.weight[k] * inv_mass[w.particle[k]];
  }
  points_.push_back(w);
  const auto [it, added] = cell_index_.try_emplace(w.particle, cellCount());
  if (added) cells_.push_back(w.particle), cell_points_.emplace_back(), cell_weights_.emplace_back();
  const int c = it->second;
  cell_of_.push_back(c);
  const int lane = cell_points_[c].size() % 4;
  if (lane == 0) cell_weights_[c].push_back({});  // zeros
  for (int k = 0; k < 8; ++k) cell_weights_[c].back().weight[k][lane] = w.weight[k];
  cell_points_[c].push_back(size() - 1);
}

namespace {

// The same sums as WeightedPoints::blend(), in the same order.
inline void blendInto(const WeightedPoint& w, const double* in, double* o) {
  double x = 0, y = 0, z = 0;
  for (int k = 0; k < 8; ++k) {
    const double* q = in + 3 * std::size_t(w.particle[k]);
    x += w.weight[k] * q[0];
    y += w.weight[k] * q[1];
    z += w.weight[k] * q[2];
  }
  o[0] = x, o[1] = y, o[2] = z;
}

}  // namespace

// Compiled without FMA contraction (CMakeLists.txt): every clone takes blendValue's products and sums, lane by lane.
__attribute__((target_clones("avx2", "default"))) void WeightedPoints::cellPointsBelow(int c, const double* s,
                                                                                       double limit,
                                                                                       std::vector<int>& out) const {
  using Lanes = double __attribute__((vector_size(32)));  // GCC's vector extension: four doubles, lane by lane
  using Mask = long long __attribute__((vector_size(32)));
  const std::vector<int>& ids = cell_points_[c];
  const int count = ids.size();
  int first = 0;
  for (const WeightQuad& q : cell_weights_[c]) {
    Lanes sum = {0, 0, 0, 0};
    for (int k = 0; k < 8; ++k) {
      Lanes w;
      std::memcpy(&w, q.weight[k], sizeof w);
      sum += w * s[k];
    }
    const Mask below = sum < limit;  // most quads keep nothing: one test for the four
    if (below[0] | below[1] | below[2] | below[3])
      for (int lane = 0; lane < 4 && first + lane < count; ++lane)
        if (below[lane]) out.push_back(ids[first + lane]);
    first += 4;
  }
}

void WeightedPoints::blendAll(const VecX& s, VecX& out) const {
  out.resize(3 * size());
  double* o = out.data();
  for (const WeightedPoint& w : points_) blendInto(w, s.data(), o), o += 3;
}

void WeightedPoints::blendSome(const VecX& s, std::span<const int> which, VecX& out) const {
  if (out.size() < 3 * Eigen::Index(which.size())) out.resize(3 * Eigen::Index(which.size()));
  double* o = out.data();
  for (const int p : which) blendInto(points_[p], s.data(), o), o += 3;
}

void WeightedPoints::cellBounds(const VecX& x, std::vector<Eigen::AlignedBox3d>& out) const {
  out.resize(cells_.size());
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    Vec3 lo = particle(x, cells_[c][0]), hi = lo;
    for (int k = 1; k < 8; ++k) {
      const Vec3 q = particle(x, cells_[c][k]);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    // A blend rounds by a few units in the last place of the largest coordinate: far less than this.
    const double slack = roundOffSlack(std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()));
    out[c] = Eigen::AlignedBox3d(lo.array() - slack, hi.array() + slack);
  }
}

Vec3 WeightedPoints::acceleration(const VecX& f, const VecX& inv_mass, int p) const {
  const WeightedPoint& w = points_[p];
  Vec3 sum = Vec3::Zero();
  for (int k = 0; k < 8; ++k) sum += (w.weight[k] * inv_mass[w.particle[k]]) * particle(f, w.particle[k]);
  return sum;
}

void WeightedPoints::spread(int p, const Vec3& g, VecX& out) const {
  const WeightedPoint& w = points_[p];
  for (int k = 0; k < 8; ++k) particle(out, w.particle[k]) += w.weight[k] * g;
}

void WeightedPoints::shift(int p, const Vec3& d, const VecX& inv_mass, VecX& s) const {
  const WeightedPoint& w = points_[p];
  if (w.inverse_mass == 0) return;
  for (int k = 0; k < 8; ++k)
    particle(s, w.particle[k]) += (w.weight[k] * inv_mass[w.particle[k]] / w.inverse_mass) * d;
}

}  // namespace wobble
