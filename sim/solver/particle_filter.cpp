#include "sim/solver/particle_filter.h"

#include <cmath>

namespace wobble {

void ParticleFilter::reset(const VecX& inverse_mass) {
  const Eigen::Index n = inverse_mass.size();
  kind_.resize(n);
  direction_.resize(3 * n);
  for (Eigen::Index p = 0; p < n; ++p) kind_[p] = inverse_mass[p] != 0 ? Free : Held;
  constrained_ = 0;
}

Eigen::Matrix3d ParticleFilter::matrix(int p) const {
  switch (kind_[p]) {
    case Free:
      return Eigen::Matrix3d::Identity();
    case Normal:
      return Eigen::Matrix3d::Identity() - normal(p) * normal(p).transpose();
    case Line:
      return direction(p) * direction(p).transpose();
    default:
      return Eigen::Matrix3d::Zero();
  }
}

void ParticleFilter::intersect(int p, const Vec3& normal) {
  switch (kind_[p]) {
    case Normal: {  // two normals: the line both leave free, unless they are (nearly) one
      const Vec3 d = particle(direction_, p).cross(normal);
      const double sine = d.norm();
      if (sine < kParallel) return;
      kind_[p] = Line;
      particle(direction_, p) = d / sine;
      return;
    }
    case Line:  // a third normal out of the first two's plane leaves nothing free
      if (std::abs(particle(direction_, p).dot(normal)) >= kParallel) kind_[p] = Held;
      return;
    default:  // held: stays held
      return;
  }
}

}  // namespace wobble
