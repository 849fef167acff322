#include "sim/weighted_points.h"

namespace wobble {

void WeightedPoints::add(const std::array<int, 8>& particle, const std::array<double, 8>& weight, int first,
                         const VecX& inv_mass) {
  WeightedPoint w{particle, weight, 0};
  for (int k = 0; k < 8; ++k) {
    w.particle[k] += first;
    w.inverse_mass += w.weight[k] * w.weight[k] * inv_mass[w.particle[k]];
  }
  points_.push_back(w);
}

void WeightedPoints::blendAll(const VecX& s, VecX& out) const {
  out.resize(3 * size());
  const double* in = s.data();
  double* o = out.data();
  for (const WeightedPoint& w : points_) {  // the same sums as blend(), in the same order
    double x = 0, y = 0, z = 0;
    for (int k = 0; k < 8; ++k) {
      const double* q = in + 3 * std::size_t(w.particle[k]);
      x += w.weight[k] * q[0];
      y += w.weight[k] * q[1];
      z += w.weight[k] * q[2];
    }
    o[0] = x, o[1] = y, o[2] = z;
    o += 3;
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
