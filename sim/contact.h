// Collision response shared by every collider (course-framework rules, relative to the surface's motion).
//
// Inside accelerations (a pure function of the stage state, so every integrator sees the same contact model):
//   a particle within epsilon of a surface whose net force, relative to the surface's acceleration, pushes into it
//   gets the support force that cancels that push, and Coulomb friction: kinetic, -mu Fn vT/|vT|, while sliding;
//   static (cancels the tangential force up to mu Fn) while its tangential speed is below kStickSpeed.
// At step ends only (the stored state): a particle within epsilon and approaching the surface has its relative
//   normal velocity reversed and scaled by the restitution, v_n' = u_n - e (v_n - u_n); one below the surface is
//   moved back onto it.
#pragma once
#include <memory>
#include <span>

#include "colliders/collider.h"

namespace wobble {

inline constexpr double kStickSpeed = 1e-3;  // m/s: tangential speed under which contacts may stick

using Colliders = std::span<const std::unique_ptr<Collider>>;

void addContactForces(Colliders colliders, double t, const VecX& x, const VecX& v, const VecX& mass,
                      const VecX& inv_mass, VecX& f);

void resolveCollisions(Colliders colliders, double t, VecX& x, VecX& v, const VecX& inv_mass);

}  // namespace wobble
