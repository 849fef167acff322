#include "sim/contact/constraints/filter.h"

namespace wobble {

void constrainFilter(const std::vector<ContactConstraint>& constraints, ParticleFilter& filter) {
  for (const ContactConstraint& c : constraints) {
    filter.constrain(c.particle, c.normal);
    if (c.stick) filter.hold(c.particle);
  }
}

void addPrescribedChange(const std::vector<ContactConstraint>& constraints, const ParticleFilter& filter, double h,
                         VecX& dv) {
  for (std::size_t k = 0; k < constraints.size();) {
    const ContactConstraint& c = constraints[k];
    std::size_t end = k + 1;
    while (end < constraints.size() && constraints[end].particle == c.particle) ++end;
    if (end == k + 1) {  // one surface: z along its normal (and, held by static friction, tangentially too)
      particle(dv, c.particle) += h * c.normal_acceleration * c.normal;
      if (c.stick) particle(dv, c.particle) += h * c.tangential_acceleration;
    } else {
      // Several: z in the span R of what the filter removes, with n_i . z = h a_i for every constraint i, from the
      // Gram system sum (R n_i)(R n_i)^T z = sum h a_i R n_i on R (S added: the same system made invertible, and z
      // stays in R since the right-hand side is). Exact for independent normals; for normals the filter merged
      // (within ParticleFilter::kParallel), their least-squares compromise.
      const Eigen::Matrix3d s = filter.matrix(c.particle);
      const Eigen::Matrix3d r = Eigen::Matrix3d::Identity() - s;
      Eigen::Matrix3d gram = s;
      Vec3 rhs = Vec3::Zero();
      for (std::size_t i = k; i < end; ++i) {
        const Vec3 n = r * constraints[i].normal;
        gram += n * n.transpose();
        rhs += h * constraints[i].normal_acceleration * n;
      }
      particle(dv, c.particle) += gram.ldlt().solve(rhs);
    }
    k = end;
  }
}

}  // namespace wobble
