// Contact constraints (dynamics.h) onto Baraff & Witkin's filter (particle_filter.h) and the velocity change the
// filter's removed part prescribes: S, and z with (I - S) dv = z (Baraff & Witkin 1998, "Large Steps in Cloth
// Simulation", section 5.3), for particles held by one surface or by several at once.
#pragma once
#include <vector>

#include "sim/dynamics.h"
#include "sim/solver/particle_filter.h"

namespace wobble {

// Constrains filter along every constraint's normal: a particle with several is constrained along their intersection
// (particle_filter.h: one normal, a line, or held); one that static friction holds (ContactConstraint::stick) is held.
void constrainFilter(const std::vector<ContactConstraint>& constraints, ParticleFilter& filter);

// dv += z on every constrained particle (constraints in particle order, filter as constrainFilter left it): z, in the
// span of the directions the filter removes, is the prescribed velocity change, n_i . z = h normal_acceleration_i for
// each of the particle's constraints i at once (the 2x2 or 3x3 Gram system of its normals; least squares over normals
// the filter merged as parallel); a particle held by static friction also by h tangential_acceleration. dv's removed
// part must be 0 before.
void addPrescribedChange(const std::vector<ContactConstraint>& constraints, const ParticleFilter& filter, double h,
                         VecX& dv);

}  // namespace wobble
