// Basic numeric types of the simulator: double precision throughout, flat state vectors.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products, rotations

namespace wobble {

using Vec3 = Eigen::Vector3d;
using VecX = Eigen::VectorXd;

// A read-only flat vector without a copy: a whole VecX or its head (contact asks colliders about a prefix of a
// buffer sized once).
using StateRef = Eigen::Ref<const VecX>;

// Particle i of a flat 3n vector.
inline auto particle(VecX& s, Eigen::Index i) { return s.segment<3>(3 * i); }
inline auto particle(const VecX& s, Eigen::Index i) { return s.segment<3>(3 * i); }
inline auto particle(const StateRef& s, Eigen::Index i) { return s.segment<3>(3 * i); }

}  // namespace wobble
