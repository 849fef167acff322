#include "sim/solver/particle_filter.h"

namespace wobble {

void ParticleFilter::reset(const VecX& inverse_mass) {
  const Eigen::Index n = inverse_mass.size();
  kind_.resize(n);
  normal_.resize(3 * n);
  for (Eigen::Index p = 0; p < n; ++p) kind_[p] = inverse_mass[p] != 0 ? Free : Held;
  constrained_ = 0;
}

}  // namespace wobble
